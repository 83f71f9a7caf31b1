// SSIM (Wang, Bovik, Sheikh, Simoncelli 2004, IEEE TIP 13(4), eq. 13 with Gaussian
// weighting, §III-C) on Rec.709 luma of display-encoded values, data range L = 1:
//   mu_x = G * x, sigma_x^2 = G * x^2 - mu_x^2, sigma_xy = G * xy - mu_x mu_y  (population)
//   SSIM(x,y) = (2 mu_x mu_y + C1)(2 sigma_xy + C2) / ((mu_x^2 + mu_y^2 + C1)(sigma_x^2 + sigma_y^2
//   + C2)) C1 = (K1 L)^2, C2 = (K2 L)^2, K1 = 0.01, K2 = 0.03; G = 11x11 Gaussian, sigma 1.5,
//   normalised to sum 1 (radius int(3.5 sigma + 0.5) = 5, as scipy.ndimage with truncate 3.5).
// The mean is over the image cropped by the window radius (skimage's crop(S, pad)); every
// window of a kept pixel lies inside the image, so the boundary mode ('reflect' in skimage)
// never influences the result and is not needed here.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

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
constexpr int kBlockRows = 64;  // output rows per task-local buffer

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
}  // namespace

double ssim(const Image& a, const Image& b) {
  detail::check_same_size(a, b, "metrics.ssim");
  if (a.channels == 2) throw Error("metrics.ssim", "2-channel images have no luma");
  const int W = a.width, H = a.height;
  if (W < kTaps || H < kTaps)
    throw Error("metrics.ssim", "image " + std::to_string(W) + "x" + std::to_string(H) +
                                    " is smaller than the 11x11 window");
  static const Kernel K;
  const double C1 = (kK1 * 1.0) * (kK1 * 1.0), C2 = (kK2 * 1.0) * (kK2 * 1.0);
  const int R = kRadius, Wv = W - 2 * R;  // valid (cropped) columns [R, W-R)
  const int y_lo = R, y_hi = H - R;       // valid rows
  std::vector<double> row_sum(size_t(H), 0.0);

  tbb::parallel_for(
      tbb::blocked_range<int>(y_lo, y_hi, kBlockRows), [&](const tbb::blocked_range<int>& range) {
        // Per-thread row scratch, kept across tasks and calls (no allocation per frame).
        thread_local std::vector<double> la, lb, prod, vrow;
        thread_local std::vector<double>
            hbuf;  // 5 planes x (rows + 2R) x Wv, horizontally filtered
        la.resize(size_t(W));
        lb.resize(size_t(W));
        prod.resize(5 * size_t(W));
        vrow.resize(5 * size_t(Wv));
        for (int y0 = range.begin(); y0 < range.end(); y0 += kBlockRows) {
          const int y1 = std::min(range.end(), y0 + kBlockRows);
          const int nsrc = (y1 - y0) + 2 * R;
          hbuf.assign(5 * size_t(nsrc) * size_t(Wv), 0.0);
          // Horizontal pass over source rows y0-R .. y1-1+R (all inside the image).
          for (int j = 0; j < nsrc; ++j) {
            const int sy = y0 - R + j;
            luma_row(a, sy, la.data());
            luma_row(b, sy, lb.data());
            double* p0 = &prod[0];
            double* p1 = &prod[size_t(W)];
            double* p2 = &prod[2 * size_t(W)];
            double* p3 = &prod[3 * size_t(W)];
            double* p4 = &prod[4 * size_t(W)];
            for (int x = 0; x < W; ++x) {
              p0[x] = la[x];
              p1[x] = lb[x];
              p2[x] = la[x] * la[x];
              p3[x] = lb[x] * lb[x];
              p4[x] = la[x] * lb[x];
            }
            for (int c = 0; c < 5; ++c) {
              const double* src = &prod[size_t(c) * W];
              double* dst = &hbuf[(size_t(c) * nsrc + j) * size_t(Wv)];
              // Tap-outer loops vectorise over x; the kernel is symmetric (g[k] = g[2R-k]).
              for (int x = 0; x < Wv; ++x) dst[x] = K.g[R] * src[x + R];
              for (int k = 0; k < R; ++k) {
                const double g = K.g[k];
                const double* lo = src + k;
                const double* hi = src + (2 * R - k);
                for (int x = 0; x < Wv; ++x) dst[x] += g * (lo[x] + hi[x]);
              }
            }
          }
          // Vertical pass and the SSIM map for output rows y0 .. y1-1.
          for (int y = y0; y < y1; ++y) {
            const int j0 = y - y0;  // first source row of the window in hbuf
            for (int c = 0; c < 5; ++c) {
              double* dst = &vrow[size_t(c) * Wv];
              const double* mid = &hbuf[(size_t(c) * nsrc + j0 + R) * size_t(Wv)];
              for (int x = 0; x < Wv; ++x) dst[x] = K.g[R] * mid[x];
              for (int k = 0; k < R; ++k) {
                const double* lo = &hbuf[(size_t(c) * nsrc + j0 + k) * size_t(Wv)];
                const double* hi = &hbuf[(size_t(c) * nsrc + j0 + 2 * R - k) * size_t(Wv)];
                const double g = K.g[k];
                for (int x = 0; x < Wv; ++x) dst[x] += g * (lo[x] + hi[x]);
              }
            }
            const double* ux = &vrow[0];
            const double* uy = &vrow[size_t(Wv)];
            const double* uxx = &vrow[2 * size_t(Wv)];
            const double* uyy = &vrow[3 * size_t(Wv)];
            const double* uxy = &vrow[4 * size_t(Wv)];
            double s = 0;
            for (int x = 0; x < Wv; ++x) {
              const double vx = uxx[x] - ux[x] * ux[x];
              const double vy = uyy[x] - uy[x] * uy[x];
              const double vxy = uxy[x] - ux[x] * uy[x];
              const double A1 = 2 * ux[x] * uy[x] + C1, A2 = 2 * vxy + C2;
              const double B1 = ux[x] * ux[x] + uy[x] * uy[x] + C1, B2 = vx + vy + C2;
              s += (A1 * A2) / (B1 * B2);
            }
            row_sum[size_t(y)] = s;
          }
        }
      });

  // Serial sum in row order: identical at any thread count.
  double total = 0;
  for (int y = y_lo; y < y_hi; ++y) total += row_sum[size_t(y)];
  return total / (double(Wv) * double(y_hi - y_lo));
}

}  // namespace fovsim
