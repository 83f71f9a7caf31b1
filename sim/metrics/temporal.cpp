// Temporal error (docs/architecture.md "Metrics"): flicker is seen in the periphery, so measure how
// much the signed luma error changes from one frame to the next there:
//   err_t(x) = luma(test_t)(x) - luma(ref_t)(x)
//   temporal_error = sqrt( mean over x with ecc_t(x) >= fovea_deg of (err_t(x) - err_{t-1}(x))^2 )
// A static error (same artefact every frame) scores 0; NaN when there is no previous frame.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <utility>

#include "sim/core/error.h"
#include "sim/core/math.h"
#include "sim/metrics/error_sums.h"
#include "sim/metrics/metrics.h"

namespace fovsim {

double temporal_error(const Image& test, const Image& ref, const std::vector<float>& ecc_deg,
                      double fovea_deg, TemporalState& st) {
  detail::check_same_size(test, ref, "metrics.temporal_error");
  detail::check_ecc(test, ecc_deg, "metrics.temporal_error");
  if (test.channels == 2) throw Error("metrics.temporal_error", "2-channel images have no luma");
  const int W = test.width, H = test.height, C = test.channels;
  const bool have_prev =
      st.prev_error.width == W && st.prev_error.height == H && st.prev_error.channels == 1;
  if (st.scratch.width != W || st.scratch.height != H || st.scratch.channels != 1)
    st.scratch.resize(W, H, 1);
  std::vector<double> rows(2 * size_t(H), 0.0);  // per row: sum of squared change, count

  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) {
      const float* pt = test.row(y);
      const float* pr = ref.row(y);
      float* cur = st.scratch.row(y);
      for (int x = 0; x < W; ++x) {
        const size_t i = size_t(x) * C;
        cur[x] = C == 1 ? pt[i] - pr[i]
                        : luma(pt[i], pt[i + 1], pt[i + 2]) - luma(pr[i], pr[i + 1], pr[i + 2]);
      }
      if (!have_prev) continue;
      const float* prev = st.prev_error.row(y);
      const float* e = &ecc_deg[size_t(y) * size_t(W)];
      double s = 0, n = 0;
      for (int x = 0; x < W; ++x) {
        if (e[x] >= fovea_deg) {
          const double d = double(cur[x]) - double(prev[x]);
          s += d * d;
          n += 1;
        }
      }
      rows[2 * size_t(y)] = s;
      rows[2 * size_t(y) + 1] = n;
    }
  });
  std::swap(st.prev_error, st.scratch);
  if (!have_prev) return std::numeric_limits<double>::quiet_NaN();
  double s = 0, n = 0;
  for (int y = 0; y < H; ++y) {
    s += rows[2 * size_t(y)];
    n += rows[2 * size_t(y) + 1];
  }
  return n > 0 ? std::sqrt(s / n) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace fovsim
