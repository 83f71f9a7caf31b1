// Synthetic head + eye-movement traces (docs/architecture.md "Inputs: displays, traces, scenes,
// configs"; parameters and sources in models/eyemodel/default.json and traces/README.md "Synthetic
// traces").
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "sim/core/param_table.h"
#include "sim/core/params.h"
#include "sim/display/display.h"
#include "sim/trace/trace.h"

namespace fovsim {

// Every number of the eye-movement model. Defaults equal models/eyemodel/default.json.
struct EyeModel {
  double internal_rate_hz = 1000;
  // Fixations: gamma-distributed durations (mean, sd) clipped to [min, max].
  double fix_mean_ms = 275, fix_sd_ms = 110, fix_min_ms = 80, fix_max_ms = 1500;
  // Saccades: main sequence D = intercept + slope*A; Vpeak = vmax (1 - exp(-A/c)).
  double sac_intercept_ms = 21, sac_slope_ms_per_deg = 2.2, sac_vmax_deg_s = 600, sac_c_deg = 10;
  // Free-viewing amplitude: gamma(mean, sd) clipped to [min, max]; horizontal bias in [0,1].
  double amp_mean_deg = 8, amp_sd_deg = 6, amp_min_deg = 0.5, amp_max_deg = 40,
         horizontal_bias = 0.5;
  // Eye-in-head limits: beyond `eye_range_deg` a quick phase / head movement recentres the eye;
  // gaze is kept `fov_margin_deg` inside the display's FOV.
  double eye_range_deg = 35, fov_margin_deg = 2;
  // Head-assisted gaze shifts: beyond eye_only_range the head contributes slope*(A - range).
  double head_eye_only_range_deg = 20, head_slope = 0.7, head_latency_ms = 20,
         head_dur_base_ms = 150, head_dur_slope_ms_per_deg = 5;
  double vor_gain = 1.0;
  // Smooth pursuit.
  double pursuit_gain = 0.9, pursuit_catchup_deg = 1.5, pursuit_latency_ms = 130;
  // Blinks.
  double blink_rate_per_min = 15, blink_mean_ms = 150, blink_min_ms = 100, blink_max_ms = 300;
  // Tracker.
  double noise_deg = 0.15;
  int latency_samples = 0;
  // Scenario parameters.
  struct Fixate {
    double radius_deg = 1.0, microsaccade_mean_deg = 0.4, head_sway_deg = 0.5, head_sway_hz = 0.3;
  } fixate;
  struct FreeViewing {
    double roi_h_deg = 60, roi_v_deg = 25, elevation_deg = -5;
  } free_viewing;
  struct Reading {
    double line_width_deg = 30, line_spacing_deg = 1.5, lines = 10, saccade_mean_deg = 2.0,
           saccade_sd_deg = 0.6, regression_prob = 0.1, fix_mean_ms = 225, fix_sd_ms = 80,
           blink_rate_per_min = 5, return_undershoot_deg = 1.5;
  } reading;
  struct Pursuit {
    double speed_min_deg_s = 5, speed_max_deg_s = 20, range_h_deg = 20, range_v_deg = 10;
  } pursuit;
  struct Walk {
    double speed_m_s = 1.3, eye_height_m = 1.6, step_hz = 1.9, bob_m = 0.02, sway_m = 0.015,
           yaw_amp_deg = 25, yaw_hz = 0.08, pitch_amp_deg = 5, pitch_hz = 0.13, roi_h_deg = 60,
           roi_v_deg = 25, elevation_deg = -8;
  } walk;
  struct Sweep {
    double amplitude_deg = 45, peak_speed_deg_s = 150, pause_s = 0.8;
  } sweep;

  static EyeModel from_params(Params& p);  // every key optional, defaults as above
  Json to_json() const;                    // same layout as default.json
};

// The eye-model keys, one table per section of the file ("" = top level, "fixation",
// "scenarios/reading", ...), bound to EyeModel's members (defaults: its initialisers above);
// from_params and to_json walk them, configs/README.md lists them (synth_params.cpp).
struct EyeModelSection {
  const char* path;
  ParamTable<EyeModel> table;
};
const std::vector<EyeModelSection>& eye_model_tables();

// Scenario names: fixate, free-viewing, reading, pursuit, walk-through, head-sweep.
const std::vector<std::string>& synth_scenarios();

// Seeds of synthetic traces (trace.synthetic.seed, `trace synth --seed`): integers in
// [0, 2^53], exact as JSON numbers and doubles, so distinct seeds are distinct traces.
constexpr double kMaxSynthSeed = 9007199254740992.0;

struct SynthOptions {
  std::string scenario = "free-viewing";
  uint64_t seed = 1;
  double duration_s = 10;
  double rate_hz = 90;  // output rate
};

// Samples synthesize() holds at once: duration x the larger of the output rate and the
// model's internal rate (+1), computed without generating anything. Callers compare it with
// their limit (trace.max_samples, `trace synth --max-samples`) before generating.
double synth_sample_count(const EyeModel& m, const SynthOptions& o);

// Per internal sample ground truth (for tests and plots).
struct SynthDebug {
  enum Phase { Fixation = 0, Saccade = 1, Pursuit = 2 };
  std::vector<int> phase;
  std::vector<glm::dvec3> gaze_world, target_world;  // target: the pursuit target or fixation goal
  std::vector<char> blink;
};

// Noise-free, latency-free trace at the internal rate (1 kHz by default).
Trace synth_internal(const EyeModel& m, const SynthOptions& o, const Display& d,
                     SynthDebug* dbg = nullptr);
// The trace a tracker would report: internal trace resampled to o.rate_hz, then latency,
// Gaussian noise and blink hold applied; gaze clamped into the display FOV.
Trace synthesize(const EyeModel& m, const SynthOptions& o, const Display& d);

// Eye model = built-in defaults overridden by `overrides` (an object, or a string naming a
// JSON file relative to base_dir). Errors name the file / JSON path of the offending key.
EyeModel load_eye_model(const Json& overrides, const std::string& where_file,
                        const std::string& where_path, const std::string& base_dir);

}  // namespace fovsim
