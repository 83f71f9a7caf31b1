// Image-mapping math shared by the mapping methods (kfr, rmfr) and the baselines
// (hyperbolic, linear, fvrs): the forward/inverse maps with their Jacobians, the kernel
// functions of Meng 2018 §2.1, and the buffer passes (gather from the G-buffer, bilinear
// reconstruction, Gaussian filters, push-pull fill). Pure math + TBB loops; no renderer here.
//
// Coordinates: screen points in pixels with pixel i's centre at i + 0.5 (sim/core/math.h);
// reduced-buffer points (u, v) the same way in the w x h buffer.
#pragma once
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/core/image.h"
#include "sim/core/math.h"
#include "sim/render/gbuffer.h"

namespace fovsim {

// ---- Kernel functions K: [0,1] -> [0,1], monotonic, K(0) = 0, K(1) = 1 (Meng 2018 eq. 2.9).
enum class KernelKind { Power, Sine, Exp };
struct KernelFn {
  KernelKind kind = KernelKind::Power;
  double alpha = 4.0;  // exponent of K(x) = x^alpha (Power only)
  // K(x) = x^alpha (eq. 2.9 with one term), sin(x pi/2), (e^x - 1)/(e - 1) (Meng 2018 §2.1).
  double K(double x) const;
  double Kinv(double y) const;                    // inverse, y clamped to [0, 1]
  double Kinv_deriv(double y) const;              // d K^-1 / dy, finite (clamped away from 0 and 1)
  double K_deriv(double x) const;                 // d K / dx, finite (x clamped away from 0)
  static KernelKind parse(const std::string& s);  // "power" | "sine" | "exp"
  static const char* name(KernelKind k);
};

// ---- Kernel log-polar map (Meng 2018 eqs. 2.10-2.13, Alg. 2) for a W x H screen and a
// w x h LP-buffer around the gaze (gx, gy), which may lie anywhere (also off-screen).
// Direction of the kernel: u = w K(log r / L), r = exp(L K^-1(u / w)). This is eq. 2.8's
// density D ~ exp(-c K^-1(u/w)) / K^-1'(u/w) and the behaviour §2.1 and Figs. 1.14-1.17
// describe (larger alpha gives the periphery a larger share of the LP-buffer, alpha >= 5
// starves the fovea). Eq. 2.10 / Alg. 2 print K^-1 and K the other way round, which would
// invert that behaviour (alpha > 1 would move samples *to* the fovea); we follow eq. 2.8.
struct LogPolarMap {
  double W = 0, H = 0, w = 0, h = 0, gx = 0, gy = 0;
  double L = 1;  // eq. 2.12: log of the largest distance from the fovea to a screen corner
  KernelFn k;

  static LogPolarMap make(int W, int H, int w, int h, glm::dvec2 gaze, KernelFn k);
  // Eq. 2.10 (kernel direction above): screen point -> LP coords. Radii below 1 px (log < 0,
  // log 0 at the gaze) clamp to u = 0.
  glm::dvec2 forward(double x, double y) const;
  // Alg. 2 (A K(u) read as L K^-1(u/w), the exact inverse of forward()): LP -> screen point.
  glm::dvec2 inverse(double u, double v) const;
  // LP samples per screen pixel at (x, y): |det d(u,v)/d(x,y)| = w h K'(t) / (2 pi L r^2),
  // t = log r / L; radii below 1 px use r = 1 (the clamp of forward()).
  double density(double x, double y) const;
};

// ---- Rectangular map (Ye et al. 2022 eqs. 4-7) per axis, all four quadrants: the side of the
// gaze a pixel lies on selects the extent E (W - x^ or x^) of the normalisation N_X (eq. 5).
struct RectAxis {
  double S = 0;  // screen extent (W or H), pixels
  double s = 0;  // buffer extent (w or h)
  double c = 0;  // gaze coordinate, clamped to [0, S]
  double f = 1;  // fx or fy in pixels (> 0)
  static RectAxis make(int S, int s, double gaze, double f);
  // Eqs. 4-5 (stable form N = x' (f + E) / (E (f + |x'|)), u = s/S (c + N E)).
  double forward(double x) const;
  // Eqs. 6-7 (stable form x'' = f E N / (f + E (1 - |N|))), returns a screen coordinate.
  double inverse(double u) const;
  // du/dx = (s/S) f (f + E) / (f + |x'|)^2.
  double deriv(double x) const;
};
struct RectMap {
  RectAxis ax, ay;
  static RectMap make(int W, int H, int w, int h, glm::dvec2 gaze, double fx_px, double fy_px);
  glm::dvec2 forward(double x, double y) const { return {ax.forward(x), ay.forward(y)}; }
  glm::dvec2 inverse(double u, double v) const { return {ax.inverse(u), ay.inverse(v)}; }
  double density(double x, double y) const { return ax.deriv(x) * ay.deriv(y); }
};

// Reduced-buffer size for a screen extent and sigma = W/w (Meng 2018 §2.1, Ye et al. 2022 §3.2):
// round(S / sigma), at least 1.
int reduced_size(int S, double sigma);

// ---- Buffer passes ---------------------------------------------------------------------

// tbb::parallel_for over rows [0, n) (grain 4 rows); body(int row).
template <class Body>
void parallel_rows(int n, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 4), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y != r.end(); ++y) body(y);
  });
}

// Core of gather_gbuffer: slot i = (iu, iv) of a w x h buffer takes the nearest sample of the
// full-res G-buffer src at the screen point at(iv, iu) (lets callers hoist per-row / per-column
// terms). Writes index[i] = that sample's index in src, or GBufferRef::kNone for a point outside
// the screen (or not finite), and used[i] = (index[i] != kNone). The buffer is then shaded
// through GBufferRef(src, index.data(), w, h): the gather reads no G-buffer channel. (Copying
// the five shading channels per slot meant five streams of scattered cache-line reads and cost
// 3.6x OpenCV's warpPolar forward map; the shader reads the same values through the index.)
template <class AtFn>
size_t gather_index_rows(const GBuffer& src, int w, int h, AtFn&& at, std::vector<uint32_t>& index,
                         std::vector<uint8_t>& used) {
  if (src.size() >= size_t(GBufferRef::kNone))
    throw std::length_error("gather_index_rows: G-buffer too large for 32-bit indices");
  index.resize(size_t(std::max(w, 0)) * size_t(std::max(h, 0)));
  used.resize(index.size());
  const double W = src.width, H = src.height;
  const size_t sw = size_t(src.width);
  const size_t xmax = size_t(src.width - 1), ymax = size_t(src.height - 1);
  std::vector<size_t> row_n(size_t(std::max(h, 0)), 0);
  parallel_rows(h, [&](int iv) {
    const size_t row0 = size_t(iv) * size_t(w);
    uint32_t* o = index.data() + row0;
    uint8_t* o_used = used.data() + row0;
    size_t n = 0;
    for (int iu = 0; iu < w; ++iu) {
      const glm::dvec2 p = at(iv, iu);
      // NaN and +-inf fail these comparisons (no separate finiteness test needed).
      const bool in = p.x >= 0 && p.y >= 0 && p.x < W && p.y < H;
      o[iu] = in ? uint32_t(std::min(size_t(p.y), ymax) * sw + std::min(size_t(p.x), xmax))
                 : GBufferRef::kNone;
      o_used[iu] = uint8_t(in);
      n += in;
    }
    row_n[size_t(iv)] = n;
  });
  size_t n = 0;
  for (size_t r : row_n) n += r;
  return n;
}

// Pass 1 gather (Meng 2018 §2.2.2, Ye et al. 2022 §3.2 "TG-buffer"): slot i = (iu, iv) of a w x h
// buffer takes the nearest full-res G-buffer sample at the screen point inv(iu + 0.5, iv + 0.5)
// as an index into src (see gather_index_rows); points outside the screen (or not finite) leave
// the slot cleared (kNone, a miss) and used[i] = 0. Returns the number of used slots. Parallel
// over rows; deterministic.
template <class InvFn>
size_t gather_gbuffer(const GBuffer& src, int w, int h, InvFn&& inv, std::vector<uint32_t>& index,
                      std::vector<uint8_t>& used) {
  return gather_index_rows(
      src, w, h, [&](int iv, int iu) { return inv(iu + 0.5, iv + 0.5); }, index, used);
}

// Bilinear sample of an RGB image at continuous pixel coordinates (centres at i + 0.5).
// x clamps at the borders; y wraps around when wrap_y (LP-buffer angle axis), else clamps.
// Inline: it is the inner loop of every reconstruction pass.
inline glm::vec3 bilinear(const Image& img, double x, double y, bool wrap_y) {
  const int w = img.width, h = img.height;
  double fx = (std::isfinite(x) ? x : 0.0) - 0.5, fy = (std::isfinite(y) ? y : 0.0) - 0.5;
  fx = fx < -1.0 ? -1.0 : (fx > double(w) ? double(w) : fx);
  if (!wrap_y) fy = fy < -1.0 ? -1.0 : (fy > double(h) ? double(h) : fy);
  const double x0f = std::floor(fx), y0f = std::floor(fy);
  const float tx = float(fx - x0f), ty = float(fy - y0f);
  int x0 = int(x0f), y0 = int(y0f), x1 = x0 + 1, y1 = y0 + 1;
  x0 = std::clamp(x0, 0, w - 1);
  x1 = std::clamp(x1, 0, w - 1);
  if (wrap_y) {
    if (y0f >= 0 && y0f < double(h - 1)) {  // common case: no wrap (same rows as below)
      y0 = int(y0f);
      y1 = y0 + 1;
    } else {
      long m0 = long(y0f) % h, m1 = (long(y0f) + 1) % h;
      y0 = int(m0 < 0 ? m0 + h : m0);
      y1 = int(m1 < 0 ? m1 + h : m1);
    }
  } else {
    y0 = std::clamp(y0, 0, h - 1);
    y1 = std::clamp(y1, 0, h - 1);
  }
  const float* a = img.at(x0, y0);
  const float* b = img.at(x1, y0);
  const float* c = img.at(x0, y1);
  const float* d = img.at(x1, y1);
  glm::vec3 top = glm::vec3(a[0], a[1], a[2]) * (1 - tx) + glm::vec3(b[0], b[1], b[2]) * tx;
  glm::vec3 bot = glm::vec3(c[0], c[1], c[2]) * (1 - tx) + glm::vec3(d[0], d[1], d[2]) * tx;
  return top * (1 - ty) + bot * ty;
}

// Resizes img only when its shape changes (no per-frame zero fill of buffers that are
// overwritten in full anyway).
inline void ensure_shape(Image& img, int w, int h, int c) {
  if (img.width != w || img.height != h || img.channels != c) img.resize(w, h, c);
}

// x^n for a small positive integer n by repeated squaring (K(x) = x^alpha with integer alpha,
// the default alpha = 4 being (x^2)^2); equals std::pow to about 1 ulp.
inline double ipow(double x, int n) {
  double r = 1.0;
  for (;;) {
    if (n & 1) r *= x;
    n >>= 1;
    if (!n) return r;
    x *= x;
  }
}

// Polar angle of (dx, dy) in [0, 2 pi): std::atan2 with the negative half shifted by 2 pi,
// inline (Cephes atan: range reduction at tan(3 pi/8) and 0.66, rational P4/Q5, ~1e-16
// relative). (0, 0) gives 0 like std::atan2(+0, +0).
inline double angle_0_2pi(double dy, double dx) {
  constexpr double kPio2 = 1.57079632679489661923, kPio4 = 0.78539816339744830962;
  constexpr double kMoreBits = 6.123233995736765886130e-17;
  const double ay = std::abs(dy), ax = std::abs(dx);
  if (!(ay > 0 || ax > 0)) return std::isnan(dy + dx) ? std::atan2(dy, dx) : 0.0;
  double x = ay / ax;  // in [0, inf]
  double y0 = 0, extra = 0;
  if (x > 2.41421356237309504880) {
    y0 = kPio2;
    extra = kMoreBits;
    x = -1.0 / x;
  } else if (x > 0.66) {
    y0 = kPio4;
    extra = 0.5 * kMoreBits;
    x = (x - 1.0) / (x + 1.0);
  }
  const double z = x * x;
  const double p = (((-8.750608600031904122785e-1 * z - 1.615753718733365076637e1) * z -
                     7.500855792314704667340e1) *
                        z -
                    1.228866684490136173410e2) *
                       z -
                   6.485021904942025371773e1;
  const double q = ((((z + 2.485846490142306297962e1) * z + 1.650270098316988542046e2) * z +
                     4.328810604912902668951e2) *
                        z +
                    4.853903996359136964868e2) *
                       z +
                   1.945506571482613964425e2;
  const double base = y0 + ((x * (z * p / q) + x) + extra);  // atan(|dy| / |dx|) in [0, pi/2]
  const double pi = 2.0 * kPio2;
  if (dx < 0) return dy < 0 ? pi + base : pi - base;
  return dy < 0 ? 2.0 * pi - base : base;
}

// One screen row of angles: v[i] = angle_0_2pi(dy, i + 0.5 - gx) * v_per_rad for i < n,
// bit-identical to the scalar function (vectorised loop of lp_reconstruct).
void polar_angle_row(double* v, int n, double gx, double dy, double v_per_rad);

// ---- KFR's two mapping passes (Meng 2018 §2.2-2.3), callable on their own (bench_methods).
// Forward map / pass 1 (§2.2.1-2.2.2): gathers the (map.w x map.h) LP-buffer from the
// full-res G-buffer, slot (u, v) taking the nearest sample at map.inverse(u, v), as an index
// into src (the LP G-buffer is GBufferRef(src, index.data(), w, h); see gather_index_rows).
// Returns the number of used slots. Alg. 2 is separable in polar form: the radius
// exp(L K^-1(u/w)) depends on the column only and cos/sin(B v) on the row only, so both are
// tabulated once per frame (the same double expressions as LogPolarMap::inverse).
// `jitter` (LP pixels, TAA's Halton offset, taa.h) moves every slot's point to
// map.inverse(u + jitter.x, v + jitter.y); zero leaves the bits as without it.
size_t lp_gather(const GBuffer& src, const LogPolarMap& map, std::vector<uint32_t>& index,
                 std::vector<uint8_t>& used, glm::dvec2 jitter = {0.0, 0.0});
// Inverse map / pass 2 (Alg. 2 as a gather): every pixel of the W x H output maps forward
// (eq. 2.10) and reads the RGB LP-buffer (lp: map.w x map.h) bilinearly, angle (y) wrapping.
// Parallel over rows. Float SIMD (simd_lp_uv_row + simd_bilinear_wrap_row, the same bits on
// every FOVSIM_SIMD path): dx, dy rounded from double once, ln and atan as Cephes float
// polynomials, float bilinear weights. Error bound against lp_reconstruct_exact (tested by
// MappingFastPath.LpReconstructFloatWithinBound): the LP coordinates differ by |du|, |dv| <=
// 2e-3 LP pixels (measured 3.4e-4 and 8.4e-5 at 1440x1600), so each output value differs by at most
// (|du| + |dv|) times the largest difference between neighbouring LP values, plus 1e-6.
// `jitter`: the LP-buffer was gathered with that offset (lp_gather); each pixel reads the buffer at
// its forward map minus the offset (u clamped to [0, w], v wrapped), so the image does not move
// with the jitter. Zero leaves the bits as without it.
void lp_reconstruct(const Image& lp, const LogPolarMap& map, int W, int H, Image& out,
                    glm::dvec2 jitter = {0.0, 0.0});
// The double-precision form (LogPolarMap::forward + bilinear() per pixel, per-row terms
// hoisted, integer alpha by ipow): the reference of lp_reconstruct's float path.
void lp_reconstruct_exact(const Image& lp, const LogPolarMap& map, int W, int H, Image& out);

// Scale invariance (docs/fidelity.md "Scale invariance of the methods"): a filter a method
// defines in display pixels is applied at render.scale s in simulated pixels, so its variance
// in simulated pixels is s^2 times the native one. kernel_with_variance(v) is the symmetric
// discrete kernel (odd length, weights sum to 1) of variance v (pixels^2): [v/2, 1 - v, v/2] for
// v <= 0.5 (at v = 0.5 exactly [1 2 1]/4; a blur narrower than a pixel keeps its variance, not
// its Gaussian shape), else a Gaussian sampled at the integers over +-max(2, ceil(3 sqrt(v)))
// (at most +-127) whose sigma is solved so the normalised weights have variance v.
std::vector<float> kernel_with_variance(double v);
// Variance (pixels^2) of a normalised odd-length kernel, sum_i w_i d_i^2.
double kernel_variance(const std::vector<float>& k);
// The native eta-tap kernel of Meng 2018 eq. 2.14's post filter (sigma from OpenCV's
// getGaussianKernel rule 0.3 ((eta - 1)/2 - 1) + 0.8), normalised.
std::vector<float> post_aa_kernel_native(int eta);
// The kernel variable_gaussian applies for size code eta (odd >= 3) at render scale s: the native
// kernel at s = 1 (bit for bit), else kernel_with_variance(s^2 * variance of the native one).
std::vector<float> post_aa_kernel(int eta, double scale);

// Separable 3x3 Gaussian [1 2 1]/4 x [1 2 1]/4 (Meng 2018 §2.2.3's internal anti-aliasing, a
// kernel of 0.5 LP-pixel^2 variance per axis at the display's resolution) applied to columns
// x >= x0 of an RGB image (rows wrap when wrap_y). At render scale s the LP-buffer has s times
// the native LP-pixel density per axis, so the kernel is kernel_with_variance(0.5 s^2):
// [a, 1 - 2a, a] with a = s^2 / 4 for s <= 1, wider for s > 1. In place; the temporary is
// *scratch when given (kept by the caller across frames), else a local. Returns the taps of
// the native 3x3 kernel (6 per filtered pixel: the work the display-resolution filter does).
double gaussian3x3_from(Image& img, int x0, bool wrap_y, Image* scratch = nullptr,
                        double scale = 1.0);

// Spatially varying separable Gaussian: eta[i] gives the kernel size code eta (odd, eta <= 1
// means untouched) per pixel, defined in display pixels (Meng 2018 eq. 2.14); the kernel of a
// code is post_aa_kernel(eta, scale) (at scale 1: sigma by OpenCV's getGaussianKernel rule
// 0.3 ((eta - 1)/2 - 1) + 0.8 over eta taps). Horizontal then vertical pass. Returns the
// number of taps the native kernels read (eta per pixel and pass, whatever the scale: the
// display-resolution filter's work). Pixels are processed in runs of equal eta along a row
// (each run one contiguous, vectorisable multiply-add per tap, same float operation order as
// a per-pixel loop). The intermediate is *scratch when given, else a local.
double variable_gaussian(Image& img, const std::vector<uint8_t>& eta, int max_eta,
                         Image* scratch = nullptr, double scale = 1.0);

// Push-pull hole filling (Gortler et al. 1996, as used by Ye et al. 2022 §2 for sparse samples):
// pixels with valid[i] == 0 get an interpolation of valid neighbours at the coarsest needed
// scale. Valid pixels are unchanged. Returns the number of filter taps read.
double push_pull_fill(Image& img, const std::vector<uint8_t>& valid);

// Pixel radius, along each of the 4 screen axes from the gaze, at which the eccentricity
// reaches `deg` (bisection on `ecc(x, y)`); returns the largest of the 4 (square layer
// extent for the baselines). `ecc` is any callable (x, y) -> degrees.
template <class EccFn>
double radius_px_for_deg(EccFn&& ecc, glm::dvec2 gaze, double deg, double max_px) {
  double best = 0;
  const glm::dvec2 dirs[4] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (auto d : dirs) {
    double lo = 0, hi = max_px;
    if (ecc(gaze.x + d.x * hi, gaze.y + d.y * hi) < deg) {
      best = std::max(best, hi);
      continue;
    }
    for (int it = 0; it < 48; ++it) {
      double mid = 0.5 * (lo + hi);
      if (ecc(gaze.x + d.x * mid, gaze.y + d.y * mid) < deg)
        lo = mid;
      else
        hi = mid;
    }
    best = std::max(best, 0.5 * (lo + hi));
  }
  return best;
}

}  // namespace fovsim
