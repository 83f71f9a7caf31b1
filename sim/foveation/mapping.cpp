#include "sim/foveation/mapping.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "sim/core/error.h"
#include "sim/foveation/simd_kernels.h"

namespace fovsim {

namespace {
constexpr double kE = 2.718281828459045;
constexpr double kTiny = 1e-12;
inline double clampd(double v, double lo, double hi) {
  return v < lo ? lo : (v > hi ? hi : v);
}
inline double finite_or(double v, double d) {
  return std::isfinite(v) ? v : d;
}
}  // namespace

// ---- kernels (Meng 2018 §2.1, eq. 2.9 and the two alternatives named after it) ----------
double KernelFn::K(double x) const {
  x = clampd(x, 0.0, 1.0);
  switch (kind) {
    case KernelKind::Power:
      return std::pow(x, alpha);
    case KernelKind::Sine:
      return std::sin(x * kPi * 0.5);
    case KernelKind::Exp:
      return (std::exp(x) - 1.0) / (kE - 1.0);
  }
  return x;
}
double KernelFn::Kinv(double y) const {
  y = clampd(y, 0.0, 1.0);
  switch (kind) {
    case KernelKind::Power:
      return std::pow(y, 1.0 / alpha);
    case KernelKind::Sine:
      return std::asin(y) * 2.0 / kPi;
    case KernelKind::Exp:
      return std::log1p(y * (kE - 1.0));
  }
  return y;
}
double KernelFn::Kinv_deriv(double y) const {
  y = clampd(y, kTiny, 1.0 - kTiny);
  switch (kind) {
    case KernelKind::Power:
      return std::pow(y, 1.0 / alpha - 1.0) / alpha;
    case KernelKind::Sine:
      return (2.0 / kPi) / std::sqrt(1.0 - y * y);
    case KernelKind::Exp:
      return (kE - 1.0) / (1.0 + y * (kE - 1.0));
  }
  return 1.0;
}
double KernelFn::K_deriv(double x) const {
  x = clampd(x, kTiny, 1.0);
  switch (kind) {
    case KernelKind::Power:
      return alpha * std::pow(x, alpha - 1.0);
    case KernelKind::Sine:
      return 0.5 * kPi * std::cos(x * kPi * 0.5);
    case KernelKind::Exp:
      return std::exp(x) / (kE - 1.0);
  }
  return 1.0;
}
KernelKind KernelFn::parse(const std::string& s) {
  if (s == "power") return KernelKind::Power;
  if (s == "sine") return KernelKind::Sine;
  if (s == "exp") return KernelKind::Exp;
  throw Error("kernel", "unknown kernel \"" + s + "\" (power, sine, exp)");
}
const char* KernelFn::name(KernelKind k) {
  switch (k) {
    case KernelKind::Power:
      return "power";
    case KernelKind::Sine:
      return "sine";
    case KernelKind::Exp:
      return "exp";
  }
  return "power";
}

// ---- kernel log-polar map ---------------------------------------------------------------
LogPolarMap LogPolarMap::make(int W, int H, int w, int h, glm::dvec2 gaze, KernelFn k) {
  LogPolarMap m;
  m.W = W;
  m.H = H;
  m.w = w;
  m.h = h;
  m.gx = finite_or(gaze.x, W * 0.5);
  m.gy = finite_or(gaze.y, H * 0.5);
  m.k = k;
  // Eqs. 2.12-2.13: L = log of the largest fovea-to-corner distance (gaze-dependent).
  double l1 = std::hypot(m.gx, m.gy), l2 = std::hypot(W - m.gx, H - m.gy);
  double l3 = std::hypot(m.gx, H - m.gy), l4 = std::hypot(W - m.gx, m.gy);
  double lmax = std::max(std::max(l1, l2), std::max(l3, l4));
  // A screen smaller than e pixels from the fovea would give L <= 1: keep L > 0.
  m.L = std::max(std::log(std::max(lmax, 1.0)), 1e-9);
  return m;
}

glm::dvec2 LogPolarMap::forward(double x, double y) const {
  const double dx = x - gx, dy = y - gy;
  const double r = std::hypot(dx, dy);
  // Eq. 2.10; log r < 0 (r < 1 px, incl. log 0 at the gaze) clamps to the first column.
  const double t = r > 1.0 ? std::min(std::log(r) / L, 1.0) : 0.0;
  // u = w K(t) (eq. 2.8's direction, see mapping.h): t = log r / L.
  const double u = k.K(t) * w;
  double th = std::atan2(dy, dx);  // eq. 2.10's arctan(y'/x') + 1[y' < 0] 2 pi, quadrant-correct
  if (th < 0) th += 2.0 * kPi;
  double v = th * h / (2.0 * kPi);
  if (!(v < h)) v = 0;  // th == 2 pi after rounding
  return {u, v};
}

glm::dvec2 LogPolarMap::inverse(double u, double v) const {
  // Alg. 2: x'' = exp(L K^-1(u/w)) cos(B v) + x^, y'' = ... sin(B v) + y^, B = 2 pi / h.
  const double r = std::exp(L * k.Kinv(u / w));
  const double th = v * 2.0 * kPi / h;
  return {gx + r * std::cos(th), gy + r * std::sin(th)};
}

double LogPolarMap::density(double x, double y) const {
  const double r = std::max(std::hypot(x - gx, y - gy), 1.0);
  const double t = std::min(std::log(r) / L, 1.0);
  // du/dr = w K'(t) / (L r); dv/(r dtheta) = h / (2 pi r).
  return w * h * k.K_deriv(t) / (2.0 * kPi * L * r * r);
}

// ---- rectangular map (Ye et al. 2022 eqs. 4-7) -----------------------------------------------
RectAxis RectAxis::make(int S, int s, double gaze, double f) {
  RectAxis a;
  a.S = S;
  a.s = s;
  a.c = clampd(finite_or(gaze, S * 0.5), 0.0, double(S));  // off-screen gaze: nearest edge
  a.f = f;
  return a;
}

double RectAxis::forward(double x) const {
  const double xp = x - c;
  const double E = xp >= 0 ? S - c : c;  // eq. 5: W - x^ right of the gaze, x^ left of it
  double N = 0;
  if (E > 0) N = clampd(xp * (f + E) / (E * (f + std::abs(xp))), -1.0, 1.0);
  return s / S * (c + N * E);  // eq. 4: N w (1 - x^/W) + x^ w / W (sign-symmetric)
}

double RectAxis::inverse(double u) const {
  const double q = u * S / s - c;  // eq. 7 numerator, scaled to screen pixels
  const double E = q >= 0 ? S - c : c;
  if (!(E > 0)) return c;
  const double N = clampd(q / E, -1.0, 1.0);
  // Eq. 6 x'' = f N_U / (f - |N_U|) with N_U = N f E / (f + E): rewritten without cancellation.
  return c + f * E * N / (f + E * (1.0 - std::abs(N)));
}

double RectAxis::deriv(double x) const {
  const double xp = x - c;
  const double E = xp >= 0 ? S - c : c;
  if (!(E > 0)) return 0.0;
  const double d = f + std::abs(xp);
  return s / S * f * ((f + E) / d) / d;
}

RectMap RectMap::make(int W, int H, int w, int h, glm::dvec2 gaze, double fx_px, double fy_px) {
  return {RectAxis::make(W, w, gaze.x, fx_px), RectAxis::make(H, h, gaze.y, fy_px)};
}

int reduced_size(int S, double sigma) {
  double v = std::round(double(S) / sigma);
  if (!(v >= 1)) return 1;
  return int(std::min(v, double(S)));
}

// ---- buffer passes ------------------------------------------------------------------------
size_t lp_gather(const GBuffer& src, const LogPolarMap& map, std::vector<uint32_t>& index,
                 std::vector<uint8_t>& used, glm::dvec2 jitter) {
  const int w = int(map.w), h = int(map.h);
  // LogPolarMap::inverse(iu + 0.5, iv + 0.5) split into its column and row factors.
  std::vector<double> rad(size_t(std::max(w, 0))), cs(size_t(std::max(h, 0))),
      sn(size_t(std::max(h, 0)));
  for (int iu = 0; iu < w; ++iu)
    rad[size_t(iu)] =
        std::exp(map.L * map.k.Kinv((iu + 0.5 + jitter.x) / map.w));  // Kinv clamps to [0, 1]
  for (int iv = 0; iv < h; ++iv) {
    const double th = (iv + 0.5 + jitter.y) * 2.0 * kPi / map.h;
    cs[size_t(iv)] = std::cos(th);
    sn[size_t(iv)] = std::sin(th);
  }
  const double gx = map.gx, gy = map.gy;
  return gather_index_rows(
      src, w, h,
      [&](int iv, int iu) {
        const double r = rad[size_t(iu)];
        return glm::dvec2(gx + r * cs[size_t(iv)], gy + r * sn[size_t(iv)]);
      },
      index, used);
}

void polar_angle_row(double* v, int n, double gx, double dy, double v_per_rad) {
  simd_polar_angle_row(v, n, gx, dy, v_per_rad);
}

namespace {
// lp_reconstruct's row loop; Kern(t) returns K(t) for t in [0, 1]. Per row: angles (vector
// loop), then radii (log, K) into a row of u, then the bilinear reads. The log (a libm call
// that clobbers every vector register) runs in its own loop so the bilinear loop keeps its
// values in registers; each pixel's operations are unchanged.
template <class Kern>
void lp_reconstruct_rows(const Image& lp, const LogPolarMap& map, int W, int H, Image& out,
                         Kern kern) {
  // Divisions by L and 2 pi / h as multiplications (a 1-ulp change of u, v in double).
  const double inv_L = 1.0 / map.L, w = map.w, h = map.h, gx = map.gx, gy = map.gy;
  const double v_per_rad = h / (2.0 * kPi), half_inv_L = 0.5 * inv_L;
  parallel_rows(H, [&, half_inv_L, w, h, gx, gy, v_per_rad, W](int y) {
    const int lw1 = lp.width - 1, lh = lp.height;
    const size_t lstride = size_t(lp.width) * 3;
    const float* lpd = lp.data.data();
    thread_local std::vector<double> vrow, urow;  // per-thread row scratch (no per-row allocation)
    vrow.resize(size_t(W));
    urow.resize(size_t(W));
    const double dy = (y + 0.5) - gy, dy2 = dy * dy;
    polar_angle_row(vrow.data(), W, gx, dy, v_per_rad);
    for (int x = 0; x < W; ++x) {
      // LogPolarMap::forward (eq. 2.10).
      const double dx = (x + 0.5) - gx;
      const double r2 = dx * dx + dy2;  // log r = log(r^2) / 2 (no sqrt)
      const double t = r2 > 1.0 ? std::min(std::log(r2) * half_inv_L, 1.0) : 0.0;
      urow[size_t(x)] = kern(t) * w;
    }
    float* o = out.row(y);
    for (int x = 0; x < W; ++x) {
      const double u = urow[size_t(x)];
      double v = vrow[size_t(x)];
      if (!(v < h)) v = 0;
      // bilinear(lp, u, v, true) for u in [0, w], v in [0, h) (finite; no clamp of fx, fy
      // needed): x clamps at the borders, y wraps.
      // floor() without the libm call (the base build has no SSE4.1 roundsd): fx, fy are
      // finite, in [-0.5, w] and [-0.5, h) and never -0 (u - 0.5 rounds an exact zero to +0),
      // so truncation, minus one below a negative fraction, is floor exactly, bit for bit.
      const double fx = u - 0.5, fy = v - 0.5;
      const int xt = int(fx), yt = int(fy);
      const int xi = double(xt) > fx ? xt - 1 : xt, yi = double(yt) > fy ? yt - 1 : yt;
      const float tx = float(fx - double(xi)), ty = float(fy - double(yi));
      const int x0 = xi < 0 ? 0 : xi, x1 = xi + 1 > lw1 ? lw1 : xi + 1;
      const int y0 = yi < 0 ? lh - 1 : yi, y1 = yi + 1 >= lh ? yi + 1 - lh : yi + 1;
      const float* r0 = lpd + size_t(y0) * lstride;
      const float* r1 = lpd + size_t(y1) * lstride;
      const float* a = r0 + 3 * x0;
      const float* b = r0 + 3 * x1;
      const float* c = r1 + 3 * x0;
      const float* d = r1 + 3 * x1;
      const float sx = 1 - tx, sy = 1 - ty;
      for (int ch = 0; ch < 3; ++ch) {
        const float top = a[ch] * sx + b[ch] * tx;
        const float bot = c[ch] * sx + d[ch] * tx;
        o[3 * x + ch] = top * sy + bot * ty;
      }
    }
  });
}
}  // namespace

void lp_reconstruct_exact(const Image& lp, const LogPolarMap& map, int W, int H, Image& out) {
  ensure_shape(out, W, H, 3);
  const KernelFn& k = map.k;
  // K(t) = t^alpha with integer alpha by squaring (default alpha = 4: (t^2)^2).
  const bool int_alpha = k.kind == KernelKind::Power && k.alpha >= 1 && k.alpha <= 64 &&
                         k.alpha == std::floor(k.alpha);
  if (int_alpha && k.alpha == 4.0) {
    lp_reconstruct_rows(lp, map, W, H, out, [](double t) {
      const double t2 = t * t;
      return t2 * t2;
    });
  } else if (int_alpha) {
    const int ia = int(k.alpha);
    lp_reconstruct_rows(lp, map, W, H, out, [ia](double t) { return ipow(t, ia); });
  } else {
    lp_reconstruct_rows(lp, map, W, H, out, [k](double t) { return k.K(t); });
  }
}

void lp_reconstruct(const Image& lp, const LogPolarMap& map, int W, int H, Image& out,
                    glm::dvec2 jitter) {
  ensure_shape(out, W, H, 3);
  if (W <= 0 || H <= 0) return;
  const KernelFn k = map.k;
  const bool pow4 = k.kind == KernelKind::Power && k.alpha == 4.0;
  const bool int_alpha = k.kind == KernelKind::Power && k.alpha >= 1 && k.alpha <= 64 &&
                         k.alpha == std::floor(k.alpha);
  const int ia = int_alpha ? int(k.alpha) : 0;
  // Per-frame terms in double, rounded once to float: dx per column, dy per row (so the only
  // float rounding of the inputs is that of dx and dy themselves).
  thread_local std::vector<float> dxs;
  dxs.resize(size_t(W));
  for (int x = 0; x < W; ++x) dxs[size_t(x)] = float((x + 0.5) - map.gx);
  const float half_inv_L = float(0.5 / map.L), w = float(map.w), h = float(map.h);
  const float v_per_rad = float(map.h / (2.0 * kPi));
  const float jx = float(jitter.x), jy = float(jitter.y);
  const float* dx = dxs.data();
  parallel_rows(H, [&, dx](int y) {
    thread_local std::vector<float> urow, vrow;  // per-thread row scratch, reused
    urow.resize(size_t(W));
    vrow.resize(size_t(W));
    const float dy = float((y + 0.5) - map.gy);
    simd_lp_uv_row(urow.data(), vrow.data(), dx, W, dy, half_inv_L, w, v_per_rad, h, pow4);
    if (!pow4)  // u holds t: apply K (double), then scale to the buffer
      for (int x = 0; x < W; ++x) {
        const double t = urow[size_t(x)];
        urow[size_t(x)] = float((int_alpha ? ipow(t, ia) : k.K(t)) * map.w);
      }
    if (jx != 0.f || jy != 0.f)  // TAA jitter: read where the jittered gather put the point
      for (int x = 0; x < W; ++x) {
        urow[size_t(x)] = std::clamp(urow[size_t(x)] - jx, 0.f, w);
        float v = vrow[size_t(x)] - jy;
        v = v < 0.f ? v + h : (v >= h ? v - h : v);
        vrow[size_t(x)] = v < h ? v : 0.f;
      }
    simd_bilinear_wrap_row(out.row(y), urow.data(), vrow.data(), W, lp.data.data(), lp.width,
                           lp.height);
  });
}

std::vector<float> kernel_with_variance(double v) {
  if (!(v > 0)) return {1.f};
  if (v <= 0.5) {
    const float a = float(v * 0.5);
    return {a, float(1.0 - v), a};
  }
  const int half = std::min(127, std::max(2, int(std::ceil(3.0 * std::sqrt(v)))));
  auto weights = [half](double sg, std::vector<double>& w) {
    w.assign(size_t(2 * half + 1), 0.0);
    double sum = 0;
    for (int i = -half; i <= half; ++i)
      sum += (w[size_t(i + half)] = std::exp(-i * i / (2 * sg * sg)));
    double var = 0;
    for (int i = -half; i <= half; ++i) var += (w[size_t(i + half)] /= sum) * double(i) * i;
    return var;
  };
  // The variance of the normalised sampled Gaussian grows monotonically with sigma: bisect.
  std::vector<double> w;
  double lo = 0.05, hi = 4.0 * std::sqrt(v) + 1.0;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (weights(mid, w) < v ? lo : hi) = mid;
  }
  weights(0.5 * (lo + hi), w);
  return std::vector<float>(w.begin(), w.end());
}

double kernel_variance(const std::vector<float>& k) {
  const int half = int(k.size()) / 2;
  double var = 0;
  for (int i = -half; i <= half; ++i) var += double(k[size_t(i + half)]) * double(i) * i;
  return var;
}

std::vector<float> post_aa_kernel_native(int n) {
  // The float operations of the kernel as it always was (golden outputs at render.scale 1).
  const double sg = 0.3 * ((n - 1) * 0.5 - 1.0) + 0.8;
  std::vector<float> v(static_cast<size_t>(n));
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    double d = i - (n - 1) * 0.5;
    v[size_t(i)] = float(std::exp(-d * d / (2 * sg * sg)));
    sum += v[size_t(i)];
  }
  for (auto& e : v) e = float(e / sum);
  return v;
}

std::vector<float> post_aa_kernel(int n, double scale) {
  std::vector<float> k = post_aa_kernel_native(n);
  if (scale == 1.0) return k;
  return kernel_with_variance(scale * scale * kernel_variance(k));
}

double gaussian3x3_from(Image& img, int x0, bool wrap_y, Image* scratch, double scale) {
  const int w = img.width, h = img.height;
  x0 = std::clamp(x0, 0, w);
  if (x0 >= w || h == 0) return 0;
  // Meng 2018 §2.2.3's [1 2 1]/4 (0.5 LP-pixel^2) at the display's resolution: 0.5 s^2 here.
  const std::vector<float> k = kernel_with_variance(0.5 * scale * scale);
  const int half = int(k.size()) / 2;
  const float k0 = k[size_t(half) - 1], k1 = k[size_t(half)];  // the 3-tap form's weights
  Image local;
  Image& tmp = scratch ? *scratch : local;  // horizontal result; only columns >= x0 are used
  ensure_shape(tmp, w, h, img.channels);
  parallel_rows(h, [&](int y) {
    for (int x = x0; x < w; ++x) {
      float* o = tmp.at(x, y);
      if (half == 1) {
        const float* l = img.at(std::max(x - 1, 0), y);
        const float* m = img.at(x, y);
        const float* r = img.at(std::min(x + 1, w - 1), y);
        for (int c = 0; c < 3; ++c) o[c] = k0 * l[c] + k1 * m[c] + k0 * r[c];
        continue;
      }
      float acc[3] = {0, 0, 0};
      for (int i = -half; i <= half; ++i) {
        const float* s = img.at(std::clamp(x + i, 0, w - 1), y);
        for (int c = 0; c < 3; ++c) acc[c] += k[size_t(i + half)] * s[c];
      }
      std::copy_n(acc, 3, o);
    }
  });
  auto row_at = [&](int y) { return wrap_y ? ((y % h) + h) % h : std::clamp(y, 0, h - 1); };
  parallel_rows(h, [&](int y) {
    for (int x = x0; x < w; ++x) {
      float* o = img.at(x, y);
      if (half == 1) {
        const float* a = tmp.at(x, row_at(y - 1));
        const float* m = tmp.at(x, y);
        const float* b = tmp.at(x, row_at(y + 1));
        for (int c = 0; c < 3; ++c) o[c] = k0 * a[c] + k1 * m[c] + k0 * b[c];
        continue;
      }
      float acc[3] = {0, 0, 0};
      for (int i = -half; i <= half; ++i) {
        const float* s = tmp.at(x, row_at(y + i));
        for (int c = 0; c < 3; ++c) acc[c] += k[size_t(i + half)] * s[c];
      }
      std::copy_n(acc, 3, o);
    }
  });
  return 6.0 * double(w - x0) * double(h);
}

double variable_gaussian(Image& img, const std::vector<uint8_t>& eta, int max_eta, Image* scratch,
                         double scale) {
  const int w = img.width, h = img.height;
  max_eta = std::max(1, max_eta | 1);
  // Kernel weights per odd size code (Meng 2018 eq. 2.14's eta in display pixels; at scale 1
  // OpenCV's getGaussianKernel sigma rule over eta taps, else the same variance times scale^2 in
  // simulated pixels), indexed by eta.
  std::vector<std::vector<float>> k(size_t(max_eta) + 1);
  for (int n = 3; n <= max_eta; n += 2) k[size_t(n)] = post_aa_kernel(n, scale);
  Image local;
  Image& tmp = scratch ? *scratch : local;
  ensure_shape(tmp, w, h, 3);
  std::vector<double> row_taps(size_t(h), 0.0);
  auto size_at = [&](int x, int y) {
    int n = std::min<int>(eta[size_t(y) * size_t(w) + size_t(x)], max_eta);
    return (n >= 3) ? (n | 1) : 1;
  };
  // Calls run(x0, x1, n) for each maximal run [x0, x1) of equal kernel size code along row y.
  auto for_runs = [&](int y, auto&& run) {
    int x = 0;
    while (x < w) {
      const int n = size_at(x, y);
      int x1 = x + 1;
      while (x1 < w && size_at(x1, y) == n) ++x1;
      run(x, x1, n);
      x = x1;
    }
  };
  // Horizontal pass. Per pixel: acc = 0; acc += kv[i] * s[x + i - half] for i = 0..taps-1 (x
  // clamped at the borders) -- the run form performs exactly these float operations.
  parallel_rows(h, [&](int y) {
    double taps = 0;
    const float* srow = img.row(y);
    float* orow = tmp.row(y);
    for_runs(y, [&](int x0, int x1, int code) {
      const int n = code < 3 ? 1 : int(k[size_t(code)].size());
      if (n < 3) {
        std::copy(srow + 3 * size_t(x0), srow + 3 * size_t(x1), orow + 3 * size_t(x0));
        return;
      }
      const auto& kv = k[size_t(code)];
      const int half = n / 2;
      auto clamped = [&](int x) {
        float acc[3] = {0, 0, 0};
        for (int i = 0; i < n; ++i) {
          const float* s = srow + 3 * size_t(std::clamp(x + i - half, 0, w - 1));
          for (int c = 0; c < 3; ++c) acc[c] += kv[size_t(i)] * s[c];
        }
        float* o = orow + 3 * size_t(x);
        o[0] = acc[0];
        o[1] = acc[1];
        o[2] = acc[2];
      };
      // Interior [a, b): every tap inside the row.
      const int a = std::min(std::max(x0, half), x1), b = std::max(a, std::min(x1, w - half));
      for (int x = x0; x < a; ++x) clamped(x);
      if (b > a) {
        const float* rows[256];  // n <= 255
        for (int i = 0; i < n; ++i) rows[i] = srow + 3 * size_t(a + i - half);
        simd_weighted_rows(orow + 3 * size_t(a), rows, kv.data(), n, 3 * size_t(b - a));
      }
      for (int x = b; x < x1; ++x) clamped(x);
      taps += double(code) * double(x1 - x0);
    });
    row_taps[size_t(y)] = taps;
  });
  // Vertical pass (rows clamped); pixels whose kernel is the identity keep their value.
  parallel_rows(h, [&](int y) {
    double taps = 0;
    float* orow = img.row(y);
    for_runs(y, [&](int x0, int x1, int code) {
      const int n = code < 3 ? 1 : int(k[size_t(code)].size());
      if (n < 3) return;
      const auto& kv = k[size_t(code)];
      const int half = n / 2;
      const float* rows[256];  // n <= 255
      for (int i = 0; i < n; ++i)
        rows[i] = tmp.row(std::clamp(y + i - half, 0, h - 1)) + 3 * size_t(x0);
      simd_weighted_rows(orow + 3 * size_t(x0), rows, kv.data(), n, 3 * size_t(x1 - x0));
      taps += double(code) * double(x1 - x0);
    });
    row_taps[size_t(y)] += taps;
  });
  double total = 0;
  for (double t : row_taps) total += t;
  return total;
}

double push_pull_fill(Image& img, const std::vector<uint8_t>& valid) {
  // Level 0: premultiplied colour + weight; pull halves the size until 1x1 (weights clamped
  // to 1), push fills each level's deficit (1 - w) from the bilinear parent colour. Every
  // pixel of a level is computed independently: rows run in parallel, the same bits at any
  // thread count. The pyramid is per-thread scratch kept across calls (no per-frame
  // allocation once the sizes are reached).
  struct Level {
    int w = 0, h = 0;
    std::vector<glm::vec4> p;  // rgb premultiplied, a = weight
  };
  thread_local std::vector<Level> lv;
  size_t nl = 0;
  auto next_level = [&](int w, int h) -> Level& {
    if (lv.size() <= nl) lv.emplace_back();
    Level& L = lv[nl++];
    L.w = w;
    L.h = h;
    L.p.resize(size_t(w) * size_t(h));
    return L;
  };
  {
    Level& L0 = next_level(img.width, img.height);
    const int C = img.channels, W0 = img.width;
    parallel_rows(img.height, [&](int y) {
      for (int x = 0; x < W0; ++x) {
        const size_t i = size_t(y) * size_t(W0) + size_t(x);
        const float* s = &img.data[i * size_t(C)];
        L0.p[i] = valid[i] ? glm::vec4(s[0], s[1], s[2], 1.f) : glm::vec4(0.f);
      }
    });
  }
  double taps = 0;
  while (lv[nl - 1].w > 1 || lv[nl - 1].h > 1) {
    const int fw = lv[nl - 1].w, fh = lv[nl - 1].h;
    Level& c = next_level((fw + 1) / 2, (fh + 1) / 2);
    const Level& f = lv[nl - 2];
    parallel_rows(c.h, [&](int y) {
      for (int x = 0; x < c.w; ++x) {
        glm::vec4 acc(0.f);
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            int fx = std::min(2 * x + dx, f.w - 1), fy = std::min(2 * y + dy, f.h - 1);
            acc += f.p[size_t(fy) * size_t(f.w) + size_t(fx)];
          }
        if (acc.a > 1.f) acc /= acc.a;
        c.p[size_t(y) * size_t(c.w) + size_t(x)] = acc;
      }
    });
    taps += 4.0 * double(c.w) * double(c.h);
  }
  std::vector<double> row_taps;
  for (size_t l = nl - 1; l-- > 0;) {
    Level& f = lv[l];
    const Level& c = lv[l + 1];
    row_taps.assign(size_t(f.h), 0.0);
    parallel_rows(f.h, [&](int y) {
      double t = 0;
      for (int x = 0; x < f.w; ++x) {
        glm::vec4& q = f.p[size_t(y) * size_t(f.w) + size_t(x)];
        if (q.a >= 1.f) continue;
        // Bilinear parent at this pixel's centre in parent coordinates.
        double px = (x + 0.5) * 0.5 - 0.5, py = (y + 0.5) * 0.5 - 0.5;
        int x0 = int(std::floor(px)), y0 = int(std::floor(py));
        float tx = float(px - x0), ty = float(py - y0);
        glm::vec4 acc(0.f);
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            int cx = std::clamp(x0 + dx, 0, c.w - 1), cy = std::clamp(y0 + dy, 0, c.h - 1);
            float wgt = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty);
            const glm::vec4& s = c.p[size_t(cy) * size_t(c.w) + size_t(cx)];
            if (s.a > 0.f) acc += wgt * glm::vec4(glm::vec3(s) / s.a, 1.f);
          }
        t += 4;
        if (acc.a > 0.f) {
          glm::vec3 col = glm::vec3(acc) / acc.a;
          q = glm::vec4(glm::vec3(q) + (1.f - q.a) * col, 1.f);
        }
      }
      row_taps[size_t(y)] = t;
    });
    for (double t : row_taps) taps += t;
  }
  const Level& L0 = lv[0];
  const int C = img.channels, W0 = img.width;
  parallel_rows(img.height, [&](int y) {
    for (int x = 0; x < W0; ++x) {
      const size_t i = size_t(y) * size_t(W0) + size_t(x);
      if (valid[i]) continue;
      float* d = &img.data[i * size_t(C)];
      const glm::vec4& q = L0.p[i];
      glm::vec3 col = q.a > 0.f ? glm::vec3(q) / q.a : glm::vec3(0.f);
      d[0] = col.x;
      d[1] = col.y;
      d[2] = col.z;
    }
  });
  return taps;
}

}  // namespace fovsim
