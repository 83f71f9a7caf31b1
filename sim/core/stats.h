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
// Below kCiMinSamples values (batches of fewer than 2 frames) the interval is undefined (nan).
#pragma once
#include <cstddef>
#include <vector>

namespace fovsim {

constexpr size_t kCiBatches = 10;
constexpr size_t kCiMinSamples = 2 * kCiBatches;
// Student-t 0.975 quantile with kCiBatches - 1 = 9 degrees of freedom.
constexpr double kCiT975 = 2.262157162798205;

struct MeanInterval {
  double mean = 0;        // mean of all values (nan when there are none)
  double half_width = 0;  // 95% half-width; nan when n < kCiMinSamples or any value is not finite
  size_t n = 0;
  size_t batch_size = 0;  // m (0 when undefined)
  double lo() const { return mean - half_width; }
  double hi() const { return mean + half_width; }
};

// `x` in time order. Non-finite values make the interval undefined: filter them first.
MeanInterval batch_means_interval(const std::vector<double>& x);

// The same Student-t interval over kCiBatches values that already are per-batch statistics
// (e.g. a pooled metric evaluated on each batch, sim/metrics/registry.h Pooling::sequence):
// mean of the values ± kCiT975 · s / sqrt(kCiBatches). nan half-width unless `per_batch` has
// exactly kCiBatches finite values.
MeanInterval interval_of_batch_values(const std::vector<double>& per_batch);

}  // namespace fovsim
