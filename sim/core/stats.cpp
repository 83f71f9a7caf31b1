#include "sim/core/stats.h"

#include <cmath>

namespace fovsim {

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
  if (!finite || x.size() < kCiMinSamples) return r;
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
  return r;
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
  if (!finite || v.size() != kCiBatches) return r;
  double ss = 0;
  for (double x : v) ss += (x - r.mean) * (x - r.mean);
  r.half_width = kCiT975 * std::sqrt(ss / double(kCiBatches - 1) / double(kCiBatches));
  r.batch_size = 1;
  return r;
}

}  // namespace fovsim
