// Start-up transients left out of the means (docs/intervals.md "Start-up frames"): a method
// with temporal state declares how many frames it needs after a (re)start before its rows
// are representative (FoveationMethod::warmup_frames: TWFR's cold first frame redraws every
// pixel), and a stateful metric how long its temporal filters take to settle
// (SequenceMetric::settle_frames: FovVideoVDP's). frames.csv keeps every recorded row; the
// summary, paired differences, the reference's floor and the per-phase and per-state means
// are computed without them unless frames.include_startup is set. Frames rendered unrecorded
// before (frames.warmup) count towards both.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "sim/core/params.h"
#include "sim/experiment/table.h"

namespace fovsim {

struct StartupPlan {
  bool include = false;     // frames.include_startup: keep them in the means
  int warmup_rendered = 0;  // frames.warmup: rendered before the first recorded frame
  // Per method label: the frames it declares (FoveationMethod::warmup_frames).
  std::map<std::string, int> method_frames;
  // Per stateful metric (its registry name): the settle time in frames at the run's frame
  // rate and in seconds, and the per-frame columns it writes (the pooled column, the metric's
  // own, both also with the foveation-loss suffix).
  struct Metric {
    std::string name;
    int frames = 0;
    double seconds = 0;
    std::vector<std::string> columns;
  };
  std::vector<Metric> metrics;
};

// What exclude_startup did, for the manifest ("startup"), the summary and the notes.
struct StartupReport {
  Json manifest;
  // Per config_id: the rows left out of every mean (its method's warm-up).
  std::map<std::string, int> rows_dropped;
  // Metrics whose settle time could not be left out: the run has too few frames after it
  // (their means include the settling frames, their intervals are undefined).
  std::vector<std::pair<std::string, std::string>> unsettled;  // (metric, reason)
  std::vector<std::string> notes;                              // for stderr
};

// `frames` in recorded order; returns the table the means are computed from. A method's
// warm-up is left out only when frames remain; a metric's settle frames only when at least
// kCiShortMinSamples frames remain (else `unsettled`).
ResultTable exclude_startup(const ResultTable& frames, const StartupPlan& plan,
                            StartupReport& report);

// The summary after exclude_startup: `startup_frames` per row (rows_dropped), and for each
// unsettled metric its intervals (`_ci95`, `_lo`, `_hi`) undefined, with the reason in
// `ci_missing`.
void mark_startup(ResultTable& summary, const StartupReport& report, const StartupPlan& plan);

}  // namespace fovsim
