// 95% confidence intervals on a run's aggregates (issue 13): which summary columns carry a
// `<col>_ci95` half-width, and paired intervals for differences between the configs of one
// run (same frames, same gaze). Estimator: batch means (sim/core/stats.h).
#pragma once
#include <string>
#include <vector>

#include "sim/experiment/table.h"

namespace fovsim {

// True for the frames.csv columns whose summary mean gets a `<col>_ci95`: every numeric column
// except frame/time/gaze position, the wall-clock columns (ref_ms, sim_ms: not reproducible)
// and method parameters (constant per config).
bool has_interval(const std::string& column);

// The metrics compared pairwise in paired.csv (those present in the frames table).
const std::vector<std::string>& headline_metrics();

// One row per (config_a, config_b, metric) for every pair of configs costed on the same GPU,
// a before b in first-seen order: frames (paired frames with both values finite), mean_a,
// mean_b, diff = mean of (a - b) per frame, diff_ci95 (batch means over the per-frame
// differences, nan below kCiMinSamples frames), diff_lo, diff_hi, and differs (1 when the
// interval excludes 0, 0 when it contains it, nan when undefined).
ResultTable paired_differences(const ResultTable& frames);

}  // namespace fovsim
