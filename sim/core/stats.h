// Confidence intervals for the mean of an autocorrelated series (consecutive frames of a
// trace are strongly correlated: a fixation lasts ~20-40 frames at 90 Hz).
//
// Estimator: non-overlapping batch means with a fixed number of batches (Schmeiser, "Batch
// Size Effects in the Analysis of Simulation Output", Operations Research 30(3), 1982; Law
// and Kelton, "Simulation Modeling and Analysis", §9.5.3). The series is cut into
// kCiBatches consecutive batches of m = floor(n / kCiBatches) values; when m is well above
// the correlation time, the batch means are nearly independent and normal, and
//   mean ± t(0.975, kCiBatches - 1) · s_batch / sqrt(kCiBatches)
// is a 95% interval. A fixed, small batch count (10, Schmeiser's lower end) keeps batches
// as long as possible for a given frame count, which is what matters for bias at short runs;
// the Student-t quantile pays for the few degrees of freedom. The mean itself is the mean of
// all n values; the variance estimate uses the first kCiBatches·m values (the last
// n mod kCiBatches values, fewer than kCiBatches, are left out of it).
// Below kCiMinSamples values (batches of fewer than 2 frames) the batch-means interval is
// undefined (nan); mean_interval then offers the short-run interval below, with its caveat.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace fovsim {

constexpr size_t kCiBatches = 10;
constexpr size_t kCiMinSamples = 2 * kCiBatches;
// Student-t 0.975 quantile with kCiBatches - 1 = 9 degrees of freedom.
constexpr double kCiT975 = 2.262157162798205;

// The fewest values the short-run interval is computed from (below it the lag-1
// autocorrelation of the values says too little about their correlation).
constexpr size_t kCiShortMinSamples = 8;

// Which estimator gave an interval.
enum class IntervalKind {
  none,         // undefined: `why` says why
  batch_means,  // batch_means_interval
  short_run,    // short_run_interval (fewer than kCiMinSamples values)
};

struct MeanInterval {
  double mean = 0;        // mean of all values (nan when there are none)
  double half_width = 0;  // 95% half-width; nan when n < kCiMinSamples or any value is not finite
  size_t n = 0;
  size_t batch_size = 0;  // m (0 when undefined)
  IntervalKind kind = IntervalKind::none;
  double n_eff = 0;  // short_run: the effective sample size used
  // Why the interval is undefined (empty when it is defined), e.g. "5 finite frames (an
  // interval needs >= 8)", never with a comma: what the summary's `ci_missing` column and the
  // run's note say.
  std::string why;
  double lo() const { return mean - half_width; }
  double hi() const { return mean + half_width; }
};

// `x` in time order. Non-finite values make the interval undefined: filter them first.
MeanInterval batch_means_interval(const std::vector<double>& x);

// A 95% interval for the mean of a short series (kCiShortMinSamples <= n < kCiMinSamples, where
// batch means has no batches of 2): the Student-t interval on the frame mean with an effective
// sample size from the lag-1 autocorrelation, as for an AR(1) process (Bayley and Hammersley
// 1946; Wilks, "Statistical Methods in the Atmospheric Sciences", §5.2.4):
//   r1 = sum (x_t - xbar)(x_{t+1} - xbar) / sum (x_t - xbar)^2, bias-corrected by
//   r1 + (1 + 3 r1) / n (Marriott and Pope 1954: E[r1] ~ phi - (1 + 3 phi) / n for AR(1)) and
//   clamped to [0, 0.9];  n_eff = n (1 - r) / (1 + r), at least 2;
//   half-width = t(0.975, floor(n_eff) - 1) * s / sqrt(n_eff)   (s: sample standard deviation).
// Caveat (docs/intervals.md): it assumes AR(1)-like correlation and estimates r1 from the few
// values there are; on AR(1) series it covers ~96% at phi = 0, ~90% at phi = 0.5 and only
// ~75-85% at phi = 0.9. Outside that range of n it is undefined (nan, `why` set).
MeanInterval short_run_interval(const std::vector<double>& x);

// The interval a summary reports: batch means from kCiMinSamples values, the short-run interval
// from kCiShortMinSamples, else undefined with the reason.
MeanInterval mean_interval(const std::vector<double>& x);

// "batch_means", "short_run", "none".
const char* interval_kind_name(IntervalKind k);

// The same Student-t interval over kCiBatches values that already are per-batch statistics
// (e.g. a pooled metric evaluated on each batch, sim/metrics/registry.h Pooling::sequence):
// mean of the values ± kCiT975 · s / sqrt(kCiBatches). nan half-width unless `per_batch` has
// exactly kCiBatches finite values.
MeanInterval interval_of_batch_values(const std::vector<double>& per_batch);

}  // namespace fovsim
