// `fovsim run`: one config = scene + display + trace + methods + metrics + GPU profiles +
// outputs (docs/architecture.md §2, §8). Frames stream: the reference of a frame is rendered once
// and shared by every method; no whole-trace image storage.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "sim/cost/budget.h"
#include "sim/experiment/config.h"
#include "sim/experiment/run_options.h"
#include "sim/experiment/table.h"

namespace fovsim {

struct RunOptions : RunControl {  // models_dir, threads, watchdog_s, targets, use_cache
  std::string out_dir;            // empty -> results/<name>
  bool print_summary = true;      // summary table on stdout at the end
  std::string command_line;       // recorded in the manifest
};

struct RunResult {
  std::string out_dir;
  ResultTable frames;
  ResultTable summary;
  Json target;                        // manifest "target" record when targets were given
  std::vector<std::string> warnings;  // suspicious but valid values (manifest "warnings")
  bool printed_summary = false;       // the summary table (with the results path) was printed
  std::string fidelity_note;          // manifest "fidelity" note (empty at scale >= 0.5)
  // Notes for stderr: intervals that are missing or short-run (interval_notes), start-up
  // frames left out of the means.
  std::vector<std::string> notes;
};

RunResult run_experiment(const LoadedConfig& cfg, const RunOptions& opt);

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
void mark_reference_floor(ResultTable& summary, const ResultTable& frames,
                          const std::map<std::string, std::map<int, double>>& floor);

}  // namespace fovsim
