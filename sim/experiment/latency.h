// Latency what-if (docs/latency.md): a method foveates around the gaze the system
// had at t - latency while metrics use the true gaze at display time t; a velocity-threshold
// saccade detector labels every frame (saccade / suppression / fixation) on the true gaze; an
// optional main-sequence predictor moves the estimate to the predicted saccade landing point.
#pragma once
#include <set>
#include <string>

#include "sim/core/param_info.h"
#include "sim/core/params.h"
#include "sim/experiment/table.h"
#include "sim/trace/trace.h"

namespace fovsim {

struct LatencyConfig {
  bool enabled = false;  // the run config has a "latency" block (columns appear only then)
  double tracker_ms = 0, render_ms = 0, display_ms = 0;
  std::string jitter = "none";  // none | normal | uniform
  double jitter_ms = 0;         // normal: sd; uniform: width of [0, jitter_ms)
  uint64_t seed = 1;
  bool render_from_estimate = false;
  std::string predictor = "none";  // none | main_sequence
  double predictor_min_deg = 1.0;  // travelled angle before the predictor trusts a saccade
  // Saccade detector (true gaze): speed above threshold = saccade.
  double saccade_deg_s = 75, suppression_ms = 50;
  // Main sequence (defaults: models/eyemodel/default.json): Vpeak = vmax (1 - exp(-A/c)),
  // duration = intercept + slope * A.
  double ms_vmax_deg_s = 600, ms_c_deg = 10, ms_intercept_ms = 21, ms_slope_ms_per_deg = 2.2;

  static LatencyConfig from_params(Params& root);  // reads root["latency"] if present
  // Fixed part plus this frame's jitter (seeded per frame: same at any thread count / order).
  double total_ms(int frame, double render_part_ms) const;
};

// The `latency` block's keys and those of its `saccade` and `main_sequence` objects.
const ParamTable<LatencyConfig>& latency_table();
const ParamTable<LatencyConfig>& latency_saccade_table();
const ParamTable<LatencyConfig>& latency_main_sequence_table();

enum class GazePhase { Fixation, Saccade, Suppression };
const char* phase_name(GazePhase p);

// Phase of display time t on the true gaze: saccade if the speed (central difference over one
// frame period) exceeds the threshold; suppression if a saccade sample lies in the preceding
// suppression window (probed every millisecond); fixation otherwise (includes pursuit below
// the threshold).
GazePhase gaze_phase(const Trace& truth, double t, double frame_period_s, const LatencyConfig& c);

// The gaze the method uses for display time t with total latency L (s): the sample at t - L;
// with the main-sequence predictor, if a saccade is in flight at t - L (backward speed above
// threshold, travelled >= predictor_min_deg), its landing point predicted from the onset, the
// direction travelled and the amplitude implied by the main sequence (docs/latency.md).
TraceSample estimated_gaze(const Trace& truth, double t, double latency_s, double frame_period_s,
                           const LatencyConfig& c);

// Adds per-phase means to a summary (results/README.md "Latency what-if"): frames_<phase> and
// <metric>_<phase> for every name in `metrics` plus gaze_error_deg, phase in {saccade,
// suppression, fixation}; the per-frame "phase" text is dropped from the summary rows.
ResultTable summarize_phases(const ResultTable& frames, const ResultTable& summary,
                             const std::set<std::string>& metrics);

}  // namespace fovsim
