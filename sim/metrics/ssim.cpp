// SSIM (Wang, Bovik, Sheikh, Simoncelli 2004, IEEE TIP 13(4), eq. 13 with Gaussian
// weighting, §III-C) on Rec.709 luma of display-encoded values, data range L = 1:
//   mu_x = G * x, sigma_x^2 = G * x^2 - mu_x^2, sigma_xy = G * xy - mu_x mu_y  (population)
//   SSIM(x,y) = (2 mu_x mu_y + C1)(2 sigma_xy + C2) / ((mu_x^2 + mu_y^2 + C1)(sigma_x^2 + sigma_y^2
//   + C2)) C1 = (K1 L)^2, C2 = (K2 L)^2, K1 = 0.01, K2 = 0.03; G = 11x11 Gaussian, sigma 1.5,
//   normalised to sum 1 (radius int(3.5 sigma + 0.5) = 5, as scipy.ndimage with truncate 3.5).
// The mean is over the image cropped by the window radius (skimage's crop(S, pad)); every
// window of a kept pixel lies inside the image, so the boundary mode ('reflect' in skimage)
// never influences the result and is not needed here.
//
// G is separable: a horizontal pass, then a vertical pass, each summed as
// g[R] v[R] + sum_{k<R} g[k] (v[k] + v[2R-k]) in that order (the order every SSIM value of
// fovsim was computed with; tests/metrics/metrics_ssim_test.cpp pins it). The reference's
// statistics (its luma, mu_y, G * y^2) are the same for every test image of a frame, so
// ssim_prepare computes them once and ssim(test, prepared) only filters x, x^2 and xy.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "sim/core/error.h"
#include "sim/core/math.h"
#include "sim/metrics/error_sums.h"
#include "sim/metrics/metrics.h"

namespace fovsim {

namespace {
constexpr double kSigma = 1.5, kTruncate = 3.5, kK1 = 0.01, kK2 = 0.03;
constexpr int kRadius = int(kTruncate * kSigma + 0.5);  // 5 -> 11 taps
constexpr int kTaps = 2 * kRadius + 1;
constexpr int kBlockRows = 64;  // least output rows per TBB task

// Output rows per task: at least kBlockRows, and about 4 tasks per thread, so that the 2R source
// rows each task primes its ring with stay a small share. The values do not depend on it (each
// row's sum is its own), only the cost does.
int grain(int rows) {
  const int tasks = 4 * std::max(1, tbb::this_task_arena::max_concurrency());
  return std::max(kBlockRows, (rows + tasks - 1) / tasks);
}

struct Kernel {
  double g[kTaps];
  Kernel() {
    double s = 0;
    for (int k = 0; k < kTaps; ++k) {
      const double x = k - kRadius;
      g[k] = std::exp(-0.5 / (kSigma * kSigma) * x * x);
      s += g[k];
    }
    for (double& v : g) v /= s;
  }
};
const Kernel& kernel() {
  static const Kernel K;
  return K;
}

// Luma (fovsim::luma, float as in to_luma) of row y as doubles.
void luma_row(const Image& im, int y, double* out) {
  const float* p = im.row(y);
  const int W = im.width, C = im.channels;
  if (C == 1) {
    for (int x = 0; x < W; ++x) out[x] = p[x];
  } else {
    for (int x = 0; x < W; ++x)
      out[x] = luma(p[size_t(x) * C], p[size_t(x) * C + 1], p[size_t(x) * C + 2]);
  }
}

// Horizontal pass of one source row (W values) to the Wv = W - 2R valid columns. Tap-outer
// loops vectorise over x; every dst[x] sees the same operations in the same order.
void hpass_row(const Kernel& K, const double* src, double* dst, int Wv) {
  constexpr int R = kRadius;
  for (int x = 0; x < Wv; ++x) dst[x] = K.g[R] * src[x + R];
  for (int k = 0; k < R; ++k) {
    const double g = K.g[k];
    const double* lo = src + k;
    const double* hi = src + (2 * R - k);
    for (int x = 0; x < Wv; ++x) dst[x] += g * (lo[x] + hi[x]);
  }
}

// Vertical pass of one output row from the 2R+1 horizontally filtered rows of its window.
void vpass_row(const Kernel& K, const double* const* rows, double* dst, int Wv) {
  constexpr int R = kRadius;
  const double* mid = rows[R];
  for (int x = 0; x < Wv; ++x) dst[x] = K.g[R] * mid[x];
  for (int k = 0; k < R; ++k) {
    const double g = K.g[k];
    const double* lo = rows[k];
    const double* hi = rows[2 * R - k];
    for (int x = 0; x < Wv; ++x) dst[x] += g * (lo[x] + hi[x]);
  }
}

// Gaussian-filters NP planes over the output rows [y0, y1) (image rows, all in the valid
// region). src(sy, in) writes the NP planes' values of source row sy (W each) to in[0..NP-1];
// sink(y, out) receives the NP filtered rows (Wv each). The horizontally filtered source rows
// live in a ring of 2R+1 rows per plane (each source row is filtered once per task, and the
// working set stays small), in place of a full-height buffer.
template <int NP, class Src, class Sink>
void filter_rows(int W, int y0, int y1, Src&& src, Sink&& sink) {
  constexpr int R = kRadius;
  const Kernel& K = kernel();
  const int Wv = W - 2 * R;
  thread_local std::vector<double> buf;  // reused across tasks and calls
  buf.resize(size_t(NP) * (size_t(W) + size_t(kTaps + 1) * size_t(Wv)));
  double* in[NP];
  double* out[NP];
  double* ring[NP];
  for (int c = 0; c < NP; ++c) {
    in[c] = buf.data() + size_t(c) * W;
    out[c] = buf.data() + size_t(NP) * W + size_t(c) * Wv;
    ring[c] = buf.data() + size_t(NP) * (size_t(W) + Wv) + size_t(c) * kTaps * Wv;
  }
  const int first = y0 - R;  // source row in ring slot 0
  auto load = [&](int sy) {
    src(sy, in);
    const size_t slot = size_t((sy - first) % kTaps);
    for (int c = 0; c < NP; ++c) hpass_row(K, in[c], ring[c] + slot * Wv, Wv);
  };
  for (int sy = first; sy < y0 + R; ++sy) load(sy);
  const double* rows[kTaps];
  for (int y = y0; y < y1; ++y) {
    load(y + R);
    for (int c = 0; c < NP; ++c) {
      for (int k = 0; k < kTaps; ++k) rows[k] = ring[c] + size_t((y - y0 + k) % kTaps) * Wv;
      vpass_row(K, rows, out[c], Wv);
    }
    sink(y, static_cast<const double* const*>(out));
  }
}

void check_ssim_input(const Image& a, const char* where) {
  if (a.channels == 2) throw Error(where, "2-channel images have no luma");
  if (a.width < kTaps || a.height < kTaps)
    throw Error(where, "image " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                           " is smaller than the 11x11 window");
}
}  // namespace

void ssim_prepare(const Image& ref, SsimPrepared& out) {
  if (ref.empty()) throw Error("metrics.ssim", "empty image");
  check_ssim_input(ref, "metrics.ssim");
  const int W = ref.width, H = ref.height, R = kRadius, Wv = W - 2 * R;
  out.width = out.height = out.channels = 0;  // invalid until complete
  out.luma.resize(ref.pixels());
  out.mu.resize(size_t(Wv) * size_t(H - 2 * R));
  out.mom2.resize(out.mu.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) luma_row(ref, y, &out.luma[size_t(y) * W]);
  });
  auto src = [&](int sy, double* const* in) {
    const double* l = &out.luma[size_t(sy) * W];
    for (int x = 0; x < W; ++x) {
      in[0][x] = l[x];
      in[1][x] = l[x] * l[x];
    }
  };
  auto sink = [&](int y, const double* const* f) {
    const size_t o = size_t(y - R) * size_t(Wv);
    for (int x = 0; x < Wv; ++x) {
      out.mu[o + size_t(x)] = f[0][x];
      out.mom2[o + size_t(x)] = f[1][x];
    }
  };
  tbb::parallel_for(
      tbb::blocked_range<int>(R, H - R, grain(H - 2 * R)),
      [&](const tbb::blocked_range<int>& r) { filter_rows<2>(W, r.begin(), r.end(), src, sink); });
  out.width = W;
  out.height = H;
  out.channels = ref.channels;
}

double ssim(const Image& a, const SsimPrepared& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    throw Error("metrics.ssim", "images differ in size: " + std::to_string(a.width) + "x" +
                                    std::to_string(a.height) + "x" + std::to_string(a.channels) +
                                    " vs " + std::to_string(b.width) + "x" +
                                    std::to_string(b.height) + "x" + std::to_string(b.channels));
  check_ssim_input(a, "metrics.ssim");
  const int W = a.width, H = a.height;
  const double C1 = (kK1 * 1.0) * (kK1 * 1.0), C2 = (kK2 * 1.0) * (kK2 * 1.0);
  const int R = kRadius, Wv = W - 2 * R;  // valid (cropped) columns [R, W-R)
  const int y_lo = R, y_hi = H - R;       // valid rows
  std::vector<double> row_sum(size_t(H), 0.0);

  auto src = [&](int sy, double* const* in) {  // x, x^2, xy
    luma_row(a, sy, in[0]);
    const double* la = in[0];
    const double* lb = &b.luma[size_t(sy) * W];
    for (int x = 0; x < W; ++x) {
      in[1][x] = la[x] * la[x];
      in[2][x] = la[x] * lb[x];
    }
  };
  auto sink = [&](int y, const double* const* f) {
    thread_local std::vector<double> ratio;
    ratio.resize(size_t(Wv));
    const double *ux = f[0], *uxx = f[1], *uxy = f[2];
    const double* uy = &b.mu[size_t(y - R) * size_t(Wv)];
    const double* uyy = &b.mom2[size_t(y - R) * size_t(Wv)];
    // The per-pixel SSIM vectorises; the row sum stays serial, in x order.
    for (int x = 0; x < Wv; ++x) {
      const double vx = uxx[x] - ux[x] * ux[x];
      const double vy = uyy[x] - uy[x] * uy[x];
      const double vxy = uxy[x] - ux[x] * uy[x];
      const double A1 = 2 * ux[x] * uy[x] + C1, A2 = 2 * vxy + C2;
      const double B1 = ux[x] * ux[x] + uy[x] * uy[x] + C1, B2 = vx + vy + C2;
      ratio[size_t(x)] = (A1 * A2) / (B1 * B2);
    }
    double s = 0;
    for (int x = 0; x < Wv; ++x) s += ratio[size_t(x)];
    row_sum[size_t(y)] = s;
  };
  tbb::parallel_for(
      tbb::blocked_range<int>(y_lo, y_hi, grain(y_hi - y_lo)),
      [&](const tbb::blocked_range<int>& r) { filter_rows<3>(W, r.begin(), r.end(), src, sink); });

  // Serial sum in row order: identical at any thread count.
  double total = 0;
  for (int y = y_lo; y < y_hi; ++y) total += row_sum[size_t(y)];
  return total / (double(Wv) * double(y_hi - y_lo));
}

double ssim(const Image& a, const Image& b) {
  detail::check_same_size(a, b, "metrics.ssim");
  check_ssim_input(a, "metrics.ssim");
  SsimPrepared p;
  ssim_prepare(b, p);
  return ssim(a, p);
}

}  // namespace fovsim
