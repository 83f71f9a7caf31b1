// A cell's summary (summary.csv, summary.json; results/README.md "summary.csv"): per
// configuration the means of its frames with their 95% intervals and the budget decision, the
// notes about intervals that are missing or short-run, and the reference's floor. Written by
// the frame engine for every cell (write_cell_outputs, cell_outputs.cpp); merge, recost and the
// tests call it on their own tables.
#pragma once
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "sim/cost/budget.h"
#include "sim/experiment/table.h"

namespace fovsim {

// Per-config summary of a frames table: means of numeric columns, each followed by its 95%
// batch-means half-width `<col>_ci95` (sim/experiment/intervals.h), frames, est_ms_total
// p50/p95/p99; the budget decision on the p95 frame (sim/cost/budget.h decide_budget, the one
// definition): p_fit (probability that it fits under the row's GPU profile's held-out errors),
// fit_level, fits_budget (p_fit >= fit_level), fit_threshold_ms (the largest p95 estimate that
// fits at that level) and headroom_ms (budget_ms - p95, the point estimate's margin). Without
// `rule`, no profile has an interval: the point estimate decides at the default level.
// Each interval's estimator is in the text column `ci_method` (the kinds used in the row:
// "batch_means", "short_run"; sim/core/stats.h mean_interval) and every column whose interval is
// undefined though it has a mean in `ci_missing` ("col col: why; col: why").
ResultTable summarize(const ResultTable& frames, double budget_ms, const FitRule* rule = nullptr);

// The run's notes about its intervals (printed on stderr by the CLI): one per reason a headline
// column (est_ms_total, shaded_fraction, the registry's headline metrics) has no interval,
// naming the columns and configs, and one when short-run intervals were used.
std::vector<std::string> interval_notes(const ResultTable& summary);

// The reference's floor (docs/metrics.md "Two references"): `floor[column][frame]` holds each
// metric of `full` at the methods' sampling rate against the converged reference. Adds the
// text column `at_floor` to every summary row: the registry metrics (space-separated, e.g.
// "rmse_fovea fpsnr") whose per-frame values for that configuration cannot be told from the
// floor's: the 95% batch-means interval of the paired per-frame differences contains 0 (below
// 20 frames: every difference within 1e-9 relative). Such a metric measures the 1-spp aliasing
// of the reference comparison, not the method: read its `_fl` column instead.
// `floor_of(label)` is the floor of the method entry with that label (its foveation-loss
// reference: `full` with the entry's TAA settings), nullptr when it has none.
using FloorValues = std::map<std::string, std::map<int, double>>;
void mark_reference_floor(ResultTable& summary, const ResultTable& frames,
                          const std::function<const FloorValues*(const std::string&)>& floor_of);

}  // namespace fovsim
