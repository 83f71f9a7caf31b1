// 95% confidence intervals on a run's aggregates: which summary columns carry a
// `<col>_ci95` half-width, and paired intervals for differences between the configs of one
// run (same frames, same gaze). Estimator: batch means (sim/core/stats.h).
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "sim/core/params.h"
#include "sim/core/stats.h"
#include "sim/experiment/table.h"

namespace fovsim {

// True for the frames.csv columns whose summary mean gets a `<col>_ci95`: every numeric column
// except frame/time/gaze position, the wall-clock columns (ref_ms, sim_ms: not reproducible)
// and method parameters (constant per config).
bool has_interval(const std::string& column);

// The headline columns: est_ms_total, shaded_fraction and the registry's headline metrics with
// their shown foveation-loss columns (console notes, tracking states).
const std::vector<std::string>& headline_metrics();

// The metrics compared pairwise in paired.csv (those present in the frames table): the headline
// columns, then the registry's `paired` metrics and their `_fl` columns (rmse_fovea,
// rmse_fovea_fl, rmse_periphery, rmse_periphery_fl: sim/metrics/registry.h paired_metric_names).
const std::vector<std::string>& paired_metrics();

// One row per (config_a, config_b, metric) for every pair of configs costed on the same GPU,
// a before b in first-seen order: frames (paired frames with both values finite), mean_a,
// mean_b, diff = mean of (a - b) per frame, diff_ci95 (batch means over the per-frame
// differences, nan below kCiMinSamples frames), diff_lo, diff_hi, and differs (1 when the
// interval excludes 0, 0 when it contains it, nan when undefined).
ResultTable paired_differences(const ResultTable& frames);

// The known bias of `metric` at a run's fidelity, in the metric's unit: `fidelity` is the
// manifest's fidelity record (fidelity.known_bias, measured by the fidelity ladder,
// docs/fidelity.md): psnr and fpsnr in dB, shaded_fraction as a fraction, est_ms_total as the
// ladder's percentage of max(|mean_a|, |mean_b|). nan when the record states no bias (a rung
// the ladder did not measure, or render.scale >= 0.5) or the metric has none.
double fidelity_bias(const Json& fidelity, const std::string& metric, double mean_a, double mean_b);

// `paired` (paired_differences, a sweep's paired.csv) with, on every row, the columns
// fidelity_bias (fidelity_bias() of the row's metric) and below_fidelity_bias: 1 when |diff|
// is smaller than that bias (the difference may not hold at full resolution, whatever its
// interval says), 0 when it is not, nan when no bias is known. `n_real_but_below` (optional)
// gets the number of rows with below_fidelity_bias = 1 whose interval excludes 0 (differs =
// 1): differences the run calls real that its fidelity cannot vouch for.
ResultTable with_fidelity_bias(const ResultTable& paired, const Json& fidelity,
                               size_t* n_real_but_below = nullptr);

// The frames.csv column a paired difference of `metric` reads: the metric itself, or for a
// sequence-pooled metric (sim/metrics/registry.h) its pooled column (fvvdp_jod -> fvvdp_q).
std::string paired_source_column(const std::string& metric);

// The numeric columns of one paired.csv row (frames .. differs) for `metric`: config a's rows
// paired with config b's rows of the same frame index; a sequence-pooled metric's difference is
// that of the pooled values (sim/metrics/registry.h).
void paired_columns(const std::vector<const ResultRow*>& a,
                    const std::map<double, const ResultRow*>& b_by_frame, const std::string& metric,
                    ResultRow& row);

// ---- `fovsim run --target`: stop when the intervals are narrow enough ----

// One requested precision: the 95% half-width of `column`'s mean must be at most `value`
// (absolute, in the column's unit) or `value` percent of |mean| (relative), for every config.
struct IntervalTarget {
  std::string spec;    // as given, e.g. "est_ms_total:1%"
  std::string column;  // a frames.csv column with an interval (has_interval)
  double value = 0;
  bool relative = false;
  // "ranking[:COLUMN]": the order of the configs by COLUMN is settled (docs/intervals.md):
  // per GPU, configs with a finite mean sorted by it, and for every two neighbours in that
  // order the paired 95% interval of their per-frame difference excludes 0 (or the difference
  // is exactly 0 on every paired frame: a tie that no frame count resolves).
  bool ranking = false;
};

// Column ranked by a bare "ranking" target.
inline constexpr const char* kDefaultRankingColumn = "fpsnr";

// Parses "<column>:<value>[%|dB|ms]" (value > 0, finite; dB and ms are read as absolute
// values in the column's unit) or "ranking[:<column>]". Errors name the flag: "--target SPEC:
// ...".
IntervalTarget parse_target(const std::string& spec);

// Sampling under --target (docs/intervals.md): the frame range is cut into units of
// kTargetUnitFrames consecutive frames. Without temporal methods the units are evaluated in a
// seeded random order, each preceded by kTargetWarmupFrames unrecorded frames (the previous
// trace frame: temporal_error needs it), so every recorded row equals the full run's row for
// that frame. With a temporal method (TWFR: its cost and error drift over hundreds of frames,
// which no short warm-up reproduces) the units are taken in trace order, i.e. the run is the
// full run cut short. Targets are checked after every unit, and may stop the run once
// kTargetMinUnits units are in (each of the kCiBatches batches then spans >= 2 units).
constexpr int kTargetUnitFrames = 10;
constexpr int kTargetWarmupFrames = 1;
constexpr int kTargetMinUnits = 2 * int(kCiBatches);

// Seeded random permutation of 0..units-1 (Fisher-Yates on PCG32): the order in which the
// sampling units are evaluated. Same seed, same order.
std::vector<int> sampling_order(int units, uint64_t seed);

// True when every target holds for every config of `frames` (rows in evaluation order; a
// config whose column has no finite value is exact, e.g. the PSNR of `full`, and passes).
// `achieved` (if given) receives {config_id: {column: {"mean", "ci95", "target", "met"}}}, and
// for a ranking target {"ranking:<column>": {"met", "order": {gpu: [config_id...]}, "pairs":
// [{"a", "b", "gpu", "diff", "ci95", "frames", "settled"}]}}.
// A column absent from every row is an error naming the flag.
bool targets_met(const std::vector<IntervalTarget>& targets, const ResultTable& frames,
                 Json* achieved);

}  // namespace fovsim
