#include "sim/core/stats.h"

#include <algorithm>
#include <cmath>

namespace fovsim {

namespace {

bool all_finite(const std::vector<double>& x) {
  for (double v : x)
    if (!std::isfinite(v)) return false;
  return true;
}

// Student-t 0.975 quantiles for 1..19 degrees of freedom (the short-run interval's range).
constexpr double kT975[] = {12.706204736, 4.302652730, 3.182446305, 2.776445105, 2.570581836,
                            2.446911851,  2.364624252, 2.306004135, 2.262157163, 2.228138852,
                            2.200985160,  2.178812830, 2.160368656, 2.144786688, 2.131449546,
                            2.119905299,  2.109815578, 2.100922040, 2.093024054};

}  // namespace

const char* interval_kind_name(IntervalKind k) {
  switch (k) {
    case IntervalKind::batch_means:
      return "batch_means";
    case IntervalKind::short_run:
      return "short_run";
    case IntervalKind::none:
      break;
  }
  return "none";
}

MeanInterval batch_means_interval(const std::vector<double>& x) {
  MeanInterval r;
  r.n = x.size();
  r.half_width = NAN;
  if (x.empty()) {
    r.mean = NAN;
    return r;
  }
  double sum = 0;
  bool finite = true;
  for (double v : x) {
    sum += v;
    finite = finite && std::isfinite(v);
  }
  r.mean = sum / double(x.size());
  if (!finite) {
    r.why = "a value is not finite";
    return r;
  }
  if (x.size() < kCiMinSamples) {
    r.why = std::to_string(x.size()) +
            " finite frames (batch means needs >= " + std::to_string(kCiMinSamples) + ")";
    return r;
  }
  const size_t m = x.size() / kCiBatches;
  double bm[kCiBatches];
  double grand = 0;
  for (size_t b = 0; b < kCiBatches; ++b) {
    double s = 0;
    for (size_t i = b * m; i < (b + 1) * m; ++i) s += x[i];
    bm[b] = s / double(m);
    grand += bm[b];
  }
  grand /= double(kCiBatches);
  double ss = 0;
  for (double v : bm) ss += (v - grand) * (v - grand);
  const double var_of_mean = ss / double(kCiBatches - 1) / double(kCiBatches);
  r.half_width = kCiT975 * std::sqrt(var_of_mean);
  r.batch_size = m;
  r.kind = IntervalKind::batch_means;
  return r;
}

MeanInterval short_run_interval(const std::vector<double>& x) {
  MeanInterval r;
  r.n = x.size();
  r.half_width = NAN;
  r.mean = NAN;
  if (x.empty()) {
    r.why = "no finite frames";
    return r;
  }
  double sum = 0;
  for (double v : x) sum += v;
  r.mean = sum / double(x.size());
  if (!all_finite(x)) {
    r.why = "a value is not finite";
    return r;
  }
  const size_t n = x.size();
  if (n < kCiShortMinSamples || n >= kCiMinSamples) {
    r.why = std::to_string(n) + " finite frames (the short-run interval needs " +
            std::to_string(kCiShortMinSamples) + ".." + std::to_string(kCiMinSamples - 1) + ")";
    return r;
  }
  double ss = 0, lag = 0;
  for (size_t i = 0; i < n; ++i) {
    const double d = x[i] - r.mean;
    ss += d * d;
    if (i + 1 < n) lag += d * (x[i + 1] - r.mean);
  }
  r.kind = IntervalKind::short_run;
  if (ss == 0) {  // a constant series: the mean is exact
    r.half_width = 0;
    r.n_eff = double(n);
    return r;
  }
  double r1 = lag / ss;
  r1 += (1 + 3 * r1) / double(n);  // Marriott and Pope 1954: the bias of r1 for AR(1)
  r1 = std::clamp(r1, 0.0, 0.9);
  r.n_eff = std::max(2.0, double(n) * (1 - r1) / (1 + r1));
  const size_t df = size_t(std::floor(r.n_eff)) - 1;  // 1 .. n - 1 <= 18: floor is conservative
  const double s2 = ss / double(n - 1);
  r.half_width = kT975[df - 1] * std::sqrt(s2 / r.n_eff);
  return r;
}

MeanInterval mean_interval(const std::vector<double>& x) {
  if (x.size() >= kCiMinSamples || x.size() < kCiShortMinSamples || !all_finite(x)) {
    MeanInterval r = batch_means_interval(x);
    if (r.kind == IntervalKind::none && x.size() < kCiShortMinSamples)
      r.why = x.empty() ? "no finite frames"
                        : std::to_string(x.size()) + " finite frames (an interval needs >= " +
                              std::to_string(kCiShortMinSamples) + ")";
    return r;
  }
  return short_run_interval(x);
}

MeanInterval interval_of_batch_values(const std::vector<double>& v) {
  MeanInterval r;
  r.n = v.size();
  r.half_width = NAN;
  double sum = 0;
  bool finite = true;
  for (double x : v) {
    sum += x;
    finite = finite && std::isfinite(x);
  }
  r.mean = v.empty() ? NAN : sum / double(v.size());
  if (!finite || v.size() != kCiBatches) {
    r.why = !finite ? "a batch value is not finite"
                    : std::to_string(v.size()) + " batch values (needs " +
                          std::to_string(kCiBatches) + ")";
    return r;
  }
  double ss = 0;
  for (double x : v) ss += (x - r.mean) * (x - r.mean);
  r.half_width = kCiT975 * std::sqrt(ss / double(kCiBatches - 1) / double(kCiBatches));
  r.batch_size = 1;
  r.kind = IntervalKind::batch_means;
  return r;
}

}  // namespace fovsim
