// LDR-FLIP from ../shared/metrics/FLIP.md (Andersson et al., "FLIP: A Difference Evaluator for
// Alternating Images", HPG 2020; reference code NVlabs/flip v1.6). Section numbers below are
// FLIP.md's. Everything runs in double, planes included: with float planes, flat regions next to
// a feature kept ~1e-8 responses whose q_f = 0.5 root moved E by up to 4e-5 (FLIP.md §9). Rows are
// processed in parallel with TBB; each task allocates its row buffers once, never per pixel. The
// result is bit-identical at any thread count: every output value depends only on its own taps, and
// the mean is summed per row, then over rows in order. The separable filters run row by row
// through per-task rings of filtered rows; the hot per-pixel loops have SSE2 forms with the same
// IEEE operations in the same order as their scalar forms (tests/metrics/metrics_kernels_test.cpp
// pins them to a straightforward implementation, bit for bit).
#include "sim/metrics/flip.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "sim/core/error.h"
#include "sim/core/math.h"
#include "sim/core/message_text.h"
#include "sim/core/params.h"

namespace fovsim {

namespace {

using Real = double;  // storage type of the intermediate planes
using Plane = std::vector<Real>;

// §3, §4.2: white point (D65) and its reciprocals; rational RGB->XYZ matrix and its inverse.
constexpr double kXn = 0.950428545, kYn = 1.0, kZn = 1.088900371;
constexpr double kInvXn = 1.052156925, kInvYn = 1.0, kInvZn = 0.918357670;
constexpr double kM[3][3] = {
    {10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
    {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
    {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}};
constexpr double kMinv[3][3] = {{3.241003275, -1.537398934, -0.498615861},
                                {-0.969224334, 1.875930071, 0.041554224},
                                {0.055639423, -0.204011202, 1.057148933}};
// §3 constants.
constexpr double kQc = 0.7, kPc = 0.4, kPt = 0.95, kW = 0.082, kQf = 0.5, kHunt = 0.01;

double clamp01(double v) {
  return std::min(std::max(v, 0.0), 1.0);
}

// §4.1, exact.
double srgb_to_linear_exact(double c) {
  const double l = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  return clamp01(l);
}

// §4.1 through a table: the input clamped to [0,1] (equivalent, since §4.1 clamps the output)
// and linearly interpolated over 16384 intervals: |error| < 2e-9 (h^2 max|f''| / 8, f'' <= 3.1)
// except in the interval holding the 0.04045 knee (< 1e-7), far below FLIP.md's 1e-4 tolerance.
// Saves the three pow calls per pixel that dominated the metric's cost.
struct SrgbTable {
  static constexpr int kN = 16384;
  std::vector<double> v;
  SrgbTable() : v(kN + 2) {
    for (int i = 0; i <= kN; ++i) v[size_t(i)] = srgb_to_linear_exact(double(i) / kN);
    v[kN + 1] = v[kN];
  }
  double operator()(double c) const {
    if (!(c > 0.0)) return 0.0;  // also NaN -> 0 (black), as negatives
    if (c >= 1.0) return 1.0;
    const double t = c * kN;
    const int i = int(t);
    const double f = t - i;
    return v[size_t(i)] + f * (v[size_t(i) + 1] - v[size_t(i)]);
  }
};

const SrgbTable& srgb_table() {
  static const SrgbTable table;
  return table;
}

double srgb_to_linear(double c) {
  return srgb_table()(c);
}

// §4.2-4.3: display sRGB -> YCxCz (the table passed in, so that a loop looks it up once).
inline void srgb_to_ycxcz(const SrgbTable& T, double r, double g, double b, double out[3]) {
  const double R = T(r), G = T(g), B = T(b);
  const double X = kM[0][0] * R + kM[0][1] * G + kM[0][2] * B;
  const double Y = kM[1][0] * R + kM[1][1] * G + kM[1][2] * B;
  const double Z = kM[2][0] * R + kM[2][1] * G + kM[2][2] * B;
  const double y = Y * kInvYn;
  out[0] = 116.0 * y - 16.0;
  out[1] = 500.0 * (X * kInvXn - y);
  out[2] = 200.0 * (y - Z * kInvZn);
}

// srgb_to_ycxcz over one row of n pixels with c channels (grey copied to RGB, alpha dropped),
// into the three YCxCz planes' rows. SSE2 two pixels at a time: the table's index, fraction and
// interpolation and the matrix products are the same IEEE operations as SrgbTable::operator()
// and srgb_to_ycxcz (the index is computed from the value clamped to [0,1], which equals it
// wherever the interpolation is selected, and keeps the table reads in bounds otherwise).
void srgb_to_ycxcz_row(const SrgbTable& T, const float* p, int n, int c, double* o0, double* o1,
                       double* o2) {
  int x = 0;
#if defined(__SSE2__)
  const __m128d zero = _mm_setzero_pd(), one = _mm_set1_pd(1.0),
                scale = _mm_set1_pd(double(SrgbTable::kN));
  const double* v = T.v.data();
  auto lin = [&](__m128d cv) {  // SrgbTable::operator() on two values
    const __m128d t = _mm_mul_pd(_mm_min_pd(_mm_max_pd(cv, zero), one), scale);
    const __m128i i = _mm_cvttpd_epi32(t);
    const __m128d f = _mm_sub_pd(t, _mm_cvtepi32_pd(i));
    const int i0 = _mm_cvtsi128_si32(i), i1 = _mm_cvtsi128_si32(_mm_shuffle_epi32(i, 1));
    const __m128d lo = _mm_set_pd(v[i1], v[i0]), hi = _mm_set_pd(v[i1 + 1], v[i0 + 1]);
    const __m128d interp = _mm_add_pd(lo, _mm_mul_pd(f, _mm_sub_pd(hi, lo)));
    const __m128d ge1 = _mm_cmpge_pd(cv, one), pos = _mm_cmpgt_pd(cv, zero);
    return _mm_and_pd(pos, _mm_or_pd(_mm_and_pd(ge1, one), _mm_andnot_pd(ge1, interp)));
  };
  auto k = [](double d) { return _mm_set1_pd(d); };
  auto dot = [&](const double(&m)[3], __m128d a, __m128d b, __m128d d) {
    return _mm_add_pd(_mm_add_pd(_mm_mul_pd(k(m[0]), a), _mm_mul_pd(k(m[1]), b)),
                      _mm_mul_pd(k(m[2]), d));
  };
  const size_t cs = size_t(c), gi = c >= 3 ? 1 : 0, bi = c >= 3 ? 2 : 0;
  for (; x + 2 <= n; x += 2) {
    const float* a = p + size_t(x) * cs;
    const float* b = a + cs;
    const __m128d R = lin(_mm_set_pd(b[0], a[0])), G = lin(_mm_set_pd(b[gi], a[gi])),
                  B = lin(_mm_set_pd(b[bi], a[bi]));
    const __m128d X = dot(kM[0], R, G, B), Y = dot(kM[1], R, G, B), Z = dot(kM[2], R, G, B);
    const __m128d y = _mm_mul_pd(Y, k(kInvYn));
    _mm_storeu_pd(o0 + x, _mm_sub_pd(_mm_mul_pd(k(116.0), y), k(16.0)));
    _mm_storeu_pd(o1 + x, _mm_mul_pd(k(500.0), _mm_sub_pd(_mm_mul_pd(X, k(kInvXn)), y)));
    _mm_storeu_pd(o2 + x, _mm_mul_pd(k(200.0), _mm_sub_pd(y, _mm_mul_pd(Z, k(kInvZn)))));
  }
#endif
  for (; x < n; ++x) {
    const float* px = p + size_t(x) * size_t(c);
    const double r = px[0], g = c >= 3 ? px[1] : px[0], b = c >= 3 ? px[2] : px[0];
    double out[3];
    srgb_to_ycxcz(T, r, g, b, out);
    o0[x] = out[0];
    o1[x] = out[1];
    o2[x] = out[2];
  }
}

// Cube root of t > 0: exponent-bit estimate, then three Halley steps (cubic convergence:
// ~3% -> 1e-5 -> 1e-15 -> rounding); within 3 ulp of std::cbrt on [0.008, 1.2] (checked on 2M
// points), without std::cbrt's frexp/scalbn library calls.
inline double cube_root_seed(double t) {
  uint64_t bits;
  std::memcpy(&bits, &t, sizeof bits);
  bits = bits / 3 + 0x2A9F7893782DA1CEull;  // (bits - one) / 3 + one, one = bits of 1.0, rebalanced
  double y;
  std::memcpy(&y, &bits, sizeof y);
  return y;
}
inline double halley_step(double y, double t) {
  const double y3 = y * y * y;
  return y * ((y3 + 2.0 * t) / (2.0 * y3 + t));
}
double cube_root(double t) {
  double y = cube_root_seed(t);
  for (int i = 0; i < 3; ++i) y = halley_step(y, t);
  return y;
}

// §4.6 CIELAB f(t): the cube root above (6/29)^3, else the linear segment.
constexpr double kLabD = 6.0 / 29.0, kLabD3 = kLabD * kLabD * kLabD;
inline double lab_f_linear(double t) {
  return t / (3.0 * kLabD * kLabD) + 4.0 / 29.0;
}
double lab_f(double t) {
  return t > kLabD3 ? cube_root(t) : lab_f_linear(t);
}

// §4.6: linear RGB -> XYZ -> CIELAB -> Hunt-adjusted (L*, 0.01 L* a*, 0.01 L* b*).
void linear_to_hunt_lab(double R, double G, double B, double out[3]) {
  const double X = kM[0][0] * R + kM[0][1] * G + kM[0][2] * B;
  const double Y = kM[1][0] * R + kM[1][1] * G + kM[1][2] * B;
  const double Z = kM[2][0] * R + kM[2][1] * G + kM[2][2] * B;
  const double fx = lab_f(X * kInvXn), fy = lab_f(Y * kInvYn), fz = lab_f(Z * kInvZn);
  const double L = 116.0 * fy - 16.0;
  out[0] = L;
  out[1] = kHunt * L * 500.0 * (fx - fy);
  out[2] = kHunt * L * 200.0 * (fy - fz);
}

// §4.5-4.6 over one row of n pixels: filtered YCxCz -> XYZ -> linear RGB, clamp -> XYZ ->
// Hunt-adjusted Lab (linear_to_hunt_lab), with C_z given as its two Gaussians' parts (summed
// here). Written as passes over arrays, two pixels at a time with SSE2; each pixel sees the
// operations of the per-pixel form, in the same order (metrics_kernels_test pins it). The SSE2
// path computes the cube roots for every t (their seeds in a scalar pass: a 64-bit integer
// division) and selects them where t > (6/29)^3, as lab_f does. `tmp` holds 6 n doubles.
void ycxcz_to_hunt_lab_row(const double* fy, const double* fcx, const double* fcz,
                           const double* fcz2, int n, double* L, double* A, double* B,
                           double* tmp) {
  double *tx = tmp, *ty = tx + n, *tz = ty + n, *cx = tz + n, *cy = cx + n, *cz = cy + n;
  int x = 0;
#if defined(__SSE2__)
  // Two pixels at a time with SSE2 (baseline x86-64): the same IEEE operations in the same
  // order. std::max(v, 0.0) is (v < 0 ? 0 : v), i.e. max_pd(0, v) (keeps -0 and NaN as the
  // scalar code does); std::min(w, 1.0) is min_pd(1, w).
  const __m128d zero = _mm_setzero_pd(), one = _mm_set1_pd(1.0);
  auto cl = [&](__m128d v) { return _mm_min_pd(one, _mm_max_pd(zero, v)); };
  auto c = [](double v) { return _mm_set1_pd(v); };
  auto dot = [&](const double(&m)[3], __m128d a, __m128d b, __m128d d) {
    return _mm_add_pd(_mm_add_pd(_mm_mul_pd(c(m[0]), a), _mm_mul_pd(c(m[1]), b)),
                      _mm_mul_pd(c(m[2]), d));
  };
  for (; x + 2 <= n; x += 2) {
    const __m128d t = _mm_div_pd(_mm_add_pd(_mm_loadu_pd(fy + x), c(16.0)), c(116.0));
    const __m128d zc = _mm_add_pd(_mm_loadu_pd(fcz + x), _mm_loadu_pd(fcz2 + x));
    const __m128d X =
        _mm_mul_pd(c(kXn), _mm_add_pd(t, _mm_div_pd(_mm_loadu_pd(fcx + x), c(500.0))));
    const __m128d Y = _mm_mul_pd(c(kYn), t);
    const __m128d Z = _mm_mul_pd(c(kZn), _mm_sub_pd(t, _mm_div_pd(zc, c(200.0))));
    const __m128d R = cl(dot(kMinv[0], X, Y, Z)), G = cl(dot(kMinv[1], X, Y, Z)),
                  Bl = cl(dot(kMinv[2], X, Y, Z));
    _mm_storeu_pd(tx + x, _mm_mul_pd(dot(kM[0], R, G, Bl), c(kInvXn)));
    _mm_storeu_pd(ty + x, _mm_mul_pd(dot(kM[1], R, G, Bl), c(kInvYn)));
    _mm_storeu_pd(tz + x, _mm_mul_pd(dot(kM[2], R, G, Bl), c(kInvZn)));
  }
#endif
  for (; x < n; ++x) {
    const double t = (fy[x] + 16.0) / 116.0;
    const double zc = fcz[x] + fcz2[x];
    const double X = kXn * (t + fcx[x] / 500.0), Y = kYn * t, Z = kZn * (t - zc / 200.0);
    const double R = clamp01(kMinv[0][0] * X + kMinv[0][1] * Y + kMinv[0][2] * Z);
    const double G = clamp01(kMinv[1][0] * X + kMinv[1][1] * Y + kMinv[1][2] * Z);
    const double Bl = clamp01(kMinv[2][0] * X + kMinv[2][1] * Y + kMinv[2][2] * Z);
    tx[x] = (kM[0][0] * R + kM[0][1] * G + kM[0][2] * Bl) * kInvXn;
    ty[x] = (kM[1][0] * R + kM[1][1] * G + kM[1][2] * Bl) * kInvYn;
    tz[x] = (kM[2][0] * R + kM[2][1] * G + kM[2][2] * Bl) * kInvZn;
  }
  for (x = 0; x < n; ++x) {
    cx[x] = cube_root_seed(tx[x]);
    cy[x] = cube_root_seed(ty[x]);
    cz[x] = cube_root_seed(tz[x]);
  }
  x = 0;
#if defined(__SSE2__)
  auto halley = [&](__m128d y, __m128d t) {
    const __m128d y3 = _mm_mul_pd(_mm_mul_pd(y, y), y);
    return _mm_mul_pd(y, _mm_div_pd(_mm_add_pd(y3, _mm_mul_pd(c(2.0), t)),
                                    _mm_add_pd(_mm_mul_pd(c(2.0), y3), t)));
  };
  auto lin = [&](__m128d t) {  // lab_f_linear
    return _mm_add_pd(_mm_div_pd(t, c(3.0 * kLabD * kLabD)), c(4.0 / 29.0));
  };
  auto sel = [&](__m128d t, __m128d root) {  // t > (6/29)^3 ? root : linear (NaN: linear)
    const __m128d m = _mm_cmpgt_pd(t, c(kLabD3));
    return _mm_or_pd(_mm_and_pd(m, root), _mm_andnot_pd(m, lin(t)));
  };
  for (; x + 2 <= n; x += 2) {
    const __m128d ttx = _mm_loadu_pd(tx + x), tty = _mm_loadu_pd(ty + x),
                  ttz = _mm_loadu_pd(tz + x);
    __m128d a = _mm_loadu_pd(cx + x), b = _mm_loadu_pd(cy + x), d = _mm_loadu_pd(cz + x);
    for (int i = 0; i < 3; ++i) {
      a = halley(a, ttx);
      b = halley(b, tty);
      d = halley(d, ttz);
    }
    const __m128d fx = sel(ttx, a), fyv = sel(tty, b), fz = sel(ttz, d);
    const __m128d l = _mm_sub_pd(_mm_mul_pd(c(116.0), fyv), c(16.0));
    const __m128d hl = _mm_mul_pd(c(kHunt), l);
    _mm_storeu_pd(L + x, l);
    _mm_storeu_pd(A + x, _mm_mul_pd(_mm_mul_pd(hl, c(500.0)), _mm_sub_pd(fx, fyv)));
    _mm_storeu_pd(B + x, _mm_mul_pd(_mm_mul_pd(hl, c(200.0)), _mm_sub_pd(fyv, fz)));
  }
#endif
  for (; x < n; ++x) {
    double a = cx[x], b = cy[x], d = cz[x];
    for (int i = 0; i < 3; ++i) {
      a = halley_step(a, tx[x]);
      b = halley_step(b, ty[x]);
      d = halley_step(d, tz[x]);
    }
    const double fx = tx[x] > kLabD3 ? a : lab_f_linear(tx[x]);
    const double fyv = ty[x] > kLabD3 ? b : lab_f_linear(ty[x]);
    const double fz = tz[x] > kLabD3 ? d : lab_f_linear(tz[x]);
    const double l = 116.0 * fyv - 16.0;
    L[x] = l;
    A[x] = kHunt * l * 500.0 * (fx - fyv);
    B[x] = kHunt * l * 200.0 * (fyv - fz);
  }
}

// §5.3: edge and point magnitudes of one row from the x- and y-filtered responses (SSE2: the
// same IEEE products, sums and square roots, two pixels at a time).
void feature_magnitudes_row(const double* ex, const double* ey, const double* px, const double* py,
                            int n, double* edge, double* point) {
  int x = 0;
#if defined(__SSE2__)
  auto mag = [](__m128d a, __m128d b) {
    return _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(a, a), _mm_mul_pd(b, b)));
  };
  for (; x + 2 <= n; x += 2) {
    _mm_storeu_pd(edge + x, mag(_mm_loadu_pd(ex + x), _mm_loadu_pd(ey + x)));
    _mm_storeu_pd(point + x, mag(_mm_loadu_pd(px + x), _mm_loadu_pd(py + x)));
  }
#endif
  for (; x < n; ++x) {
    edge[x] = std::sqrt(ex[x] * ex[x] + ey[x] * ey[x]);
    point[x] = std::sqrt(px[x] * px[x] + py[x] * py[x]);
  }
}

// §4.7
double hyab(const double a[3], const double b[3]) {
  const double da = a[1] - b[1], db = a[2] - b[2];
  return std::fabs(a[0] - b[0]) + std::sqrt(da * da + db * db);
}

double compute_c_max() {
  double green[3], blue[3];
  linear_to_hunt_lab(0, 1, 0, green);
  linear_to_hunt_lab(0, 0, 1, blue);
  return std::pow(hyab(green, blue), kQc);
}

// Normalises the positive taps to sum +1 and the negative taps to -1 (§5.2).
void normalise_pos_neg(std::vector<double>& k) {
  double pos = 0, neg = 0;
  for (double v : k) (v > 0 ? pos : neg) += std::fabs(v);
  for (double& v : k) v = v > 0 ? v / pos : (neg > 0 ? v / neg : v);
}

// Horizontal pass (§4.4, §5.3) of one row with clamp-to-edge: for each kernel o,
// dst[o][x] = sum_i k_o[i] (scale src[clamp(x+i-r)] + offset), accumulated from 0 in tap order.
// Tap-outer loops vectorise over x; each dst[o][x] sees the per-pixel accumulator's operations.
void hrow(int W, int r, const Real* src, double scale, double offset,
          const std::vector<double>* const* ks, int nk, double* pad, double* const* dst) {
  for (int x = -r; x < W + r; ++x)
    pad[size_t(x + r)] = scale * src[std::min(std::max(x, 0), W - 1)] + offset;
  for (int o = 0; o < nk; ++o) {
    const double* k = ks[o]->data();
    double* d = dst[o];
    for (int x = 0; x < W; ++x) d[x] = 0.0;
    for (int i = 0; i <= 2 * r; ++i) {
      const double ki = k[i];
      const double* p = pad + i;
      for (int x = 0; x < W; ++x) d[x] += ki * p[x];
    }
  }
}

// Vertical pass of one output row: out[x] = sum_j k[j] h_j[x], accumulated from 0 in tap order,
// h_j = the horizontally filtered source row clamp(y + j - r).
void vrow(int W, int r, const double* const* h, const std::vector<double>& k, double* out) {
  std::fill(out, out + W, 0.0);
  for (int j = 0; j <= 2 * r; ++j) {
    const double* src = h[j];
    const double kj = k[size_t(j)];
    for (int x = 0; x < W; ++x) out[x] += kj * src[x];
  }
}

// A task's horizontally filtered rows: for each of NP planes, a ring of the 2r+1 rows of the
// current output row's window, so that the filtered planes never go through memory at full
// size. Slot of source row sy (unclamped): (sy - first) mod (2r+1); it holds the filtered
// row clamp(sy), as the per-plane passes read it.
struct RowRing {
  int W = 0, taps = 0, first = 0, np = 0;
  std::vector<double> buf;
  void reset(int w, int r, int y0, int n_planes) {
    W = w;
    taps = 2 * r + 1;
    first = y0 - r;
    np = n_planes;
    buf.resize(size_t(np) * size_t(taps) * size_t(W) + size_t(W) + 2 * size_t(r));
  }
  double* row(int plane, int sy) {
    return buf.data() + (size_t(plane) * taps + size_t((sy - first) % taps)) * size_t(W);
  }
  double* pad() { return buf.data() + size_t(np) * size_t(taps) * size_t(W); }
  // Window of output row y in plane p: rows y-r .. y+r.
  void window(int plane, int y, const double** h) {
    const int r = (taps - 1) / 2;
    for (int j = 0; j < taps; ++j) h[j] = row(plane, y - r + j);
  }
};

// Output rows per task: at least 32, about 4 tasks per thread (a task filters 2r extra rows).
int task_rows(int H) {
  const int tasks = 4 * std::max(1, tbb::this_task_arena::max_concurrency());
  return std::max(32, (H + tasks - 1) / tasks);
}

void prepare(const Image& img, const flip_detail::Kernels& k, FlipPrepared& out, Plane (&ycc)[3]) {
  const int W = img.width, H = img.height, C = img.channels;
  const size_t N = img.pixels();
  for (Plane* p : {&out.L, &out.A, &out.B, &out.edge, &out.point}) p->resize(N);
  // §4.1-4.3 per pixel. Grey (1 or 2 channels) is copied to RGB; alpha is dropped (§1).
  const SrgbTable& table = srgb_table();
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const size_t o = size_t(y) * size_t(W);
      srgb_to_ycxcz_row(table, img.row(y), W, C, &ycc[0][o], &ycc[1][o], &ycc[2][o]);
    }
  });
  auto clamp_row = [H](int sy) { return std::min(std::max(sy, 0), H - 1); };
  // §4.4: horizontal then vertical CSF passes; C_z is the sum of two separable Gaussians. Then
  // §4.5-4.6 per pixel.
  tbb::parallel_for(
      tbb::blocked_range<int>(0, H, task_rows(H)), [&](const tbb::blocked_range<int>& rows) {
        const int r = k.r_s, y0 = rows.begin();
        RowRing ring;
        ring.reset(W, r, y0, 4);
        std::vector<double> buf(10 * size_t(W));
        double *fy = buf.data(), *fcx = fy + W, *fcz = fcx + W, *fcz2 = fcz + W,
               *lab_tmp = fcz2 + W;
        const std::vector<double>* ky[1] = {&k.y};
        const std::vector<double>* kx[1] = {&k.cx};
        const std::vector<double>* kz[2] = {&k.cz1, &k.cz2};
        auto load = [&](int sy) {
          const size_t o = size_t(clamp_row(sy)) * size_t(W);
          double* d0[1] = {ring.row(0, sy)};
          double* d1[1] = {ring.row(1, sy)};
          double* d2[2] = {ring.row(2, sy), ring.row(3, sy)};
          hrow(W, r, &ycc[0][o], 1.0, 0.0, ky, 1, ring.pad(), d0);
          hrow(W, r, &ycc[1][o], 1.0, 0.0, kx, 1, ring.pad(), d1);
          hrow(W, r, &ycc[2][o], 1.0, 0.0, kz, 2, ring.pad(), d2);
        };
        for (int sy = y0 - r; sy < y0 + r; ++sy) load(sy);
        std::vector<const double*> h(size_t(2 * r + 1));
        for (int y = y0; y < rows.end(); ++y) {
          load(y + r);
          ring.window(0, y, h.data());
          vrow(W, r, h.data(), k.y, fy);
          ring.window(1, y, h.data());
          vrow(W, r, h.data(), k.cx, fcx);
          ring.window(2, y, h.data());
          vrow(W, r, h.data(), k.cz1, fcz);
          ring.window(3, y, h.data());
          vrow(W, r, h.data(), k.cz2, fcz2);
          const size_t o = size_t(y) * size_t(W);
          ycxcz_to_hunt_lab_row(fy, fcx, fcz, fcz2, W, &out.L[o], &out.A[o], &out.B[o], lab_tmp);
        }
      });
  // §5.1-5.3 on the unfiltered Y': A = (Y' + 16) / 116; one x-pass (D, S, G), then the y-pass:
  // edge = (x-D then y-G, x-G then y-D), point = (x-S then y-G, x-G then y-S).
  tbb::parallel_for(tbb::blocked_range<int>(0, H, task_rows(H)),
                    [&](const tbb::blocked_range<int>& rows) {
                      const int r = k.r_f, y0 = rows.begin();
                      RowRing ring;
                      ring.reset(W, r, y0, 3);
                      std::vector<double> buf(4 * size_t(W));
                      double *ex = buf.data(), *px = ex + W, *ey = px + W, *py = ey + W;
                      const std::vector<double>* kf[3] = {&k.d, &k.s, &k.g};
                      auto load = [&](int sy) {
                        double* d[3] = {ring.row(0, sy), ring.row(1, sy), ring.row(2, sy)};
                        hrow(W, r, &ycc[0][size_t(clamp_row(sy)) * size_t(W)], 1.0 / 116.0,
                             16.0 / 116.0, kf, 3, ring.pad(), d);
                      };
                      for (int sy = y0 - r; sy < y0 + r; ++sy) load(sy);
                      std::vector<const double*> h(size_t(2 * r + 1));
                      for (int y = y0; y < rows.end(); ++y) {
                        load(y + r);
                        ring.window(0, y, h.data());
                        vrow(W, r, h.data(), k.g, ex);
                        ring.window(1, y, h.data());
                        vrow(W, r, h.data(), k.g, px);
                        ring.window(2, y, h.data());
                        vrow(W, r, h.data(), k.d, ey);
                        vrow(W, r, h.data(), k.s, py);
                        const size_t o = size_t(y) * size_t(W);
                        feature_magnitudes_row(ex, ey, px, py, W, &out.edge[o], &out.point[o]);
                      }
                    });
}

}  // namespace

double flip_default_ppd() {
  return 0.7 * (3840.0 / 0.7) * kPi / 180.0;
}

namespace flip_detail {

double c_max() {
  static const double v = compute_c_max();
  return v;
}

double srgb_to_linear_table(double c) {
  return srgb_to_linear(c);
}

double lab_cube_root(double t) {
  return cube_root(t);
}

Kernels kernels(double ppd) {
  Kernels k;
  // §4.4: one radius from b_max = 0.04 for all three channels.
  k.r_s = int(std::ceil(3.0 * std::sqrt(0.04 / (2.0 * kPi * kPi)) * ppd));
  const int n = 2 * k.r_s + 1;
  auto gauss = [&](double a, double b, std::vector<double>& t) {
    t.resize(size_t(n));
    const double amp = std::sqrt(a * std::sqrt(kPi / b));
    for (int i = -k.r_s; i <= k.r_s; ++i)
      t[size_t(i + k.r_s)] = amp * std::exp(-kPi * kPi * i * i / (b * ppd * ppd));
  };
  auto sum = [](const std::vector<double>& t) {
    double s = 0;
    for (double v : t) s += v;
    return s;
  };
  gauss(1.0, 0.0047, k.y);
  gauss(1.0, 0.0053, k.cx);
  for (auto* t : {&k.y, &k.cx}) {
    const double s = sum(*t);
    for (double& v : *t) v /= s;
  }
  gauss(34.1, 0.04, k.cz1);
  gauss(13.5, 0.025, k.cz2);
  const double s1 = sum(k.cz1), s2 = sum(k.cz2), norm = 1.0 / std::sqrt(s1 * s1 + s2 * s2);
  for (auto* t : {&k.cz1, &k.cz2})
    for (double& v : *t) v *= norm;

  // §5.2: feature kernels, sigma = 0.5 w ppd pixels.
  const double sigma = 0.5 * kW * ppd;
  k.r_f = int(std::ceil(3.0 * sigma));
  const int m = 2 * k.r_f + 1;
  k.g.resize(size_t(m));
  k.d.resize(size_t(m));
  k.s.resize(size_t(m));
  for (int i = -k.r_f; i <= k.r_f; ++i) {
    const double g = std::exp(-double(i) * i / (2.0 * sigma * sigma));
    const size_t j = size_t(i + k.r_f);
    k.g[j] = g;
    k.d[j] = -i * g;
    k.s[j] = (double(i) * i / (sigma * sigma) - 1.0) * g;
  }
  const double sg = sum(k.g);
  for (double& v : k.g) v /= sg;
  normalise_pos_neg(k.d);
  normalise_pos_neg(k.s);
  return k;
}

}  // namespace flip_detail

static std::string dims(const Image& a) {
  return std::to_string(a.width) + "x" + std::to_string(a.height) + "x" +
         std::to_string(a.channels);
}

// Below this the filters of kernels() underflow (E is NaN at 1e-300).
constexpr double kFlipMinPpd = 1e-2;

Range flip_ppd_range() {
  return Range::closed(kFlipMinPpd, 1e6);
}

double flip_max_ppd(int width, int height) {
  const double side = std::max(64.0, double(std::max(width, height)));
  // The larger of the two radii per unit ppd: the CSF radius 3 sqrt(b_max / (2 pi^2)), b_max =
  // 0.04 (kernels() above; the feature radius 1.5 w = 0.123 is smaller).
  const double per_ppd = 3.0 * std::sqrt(0.04 / (2.0 * kPi * kPi));
  return std::floor(side / per_ppd);
}

void check_flip_ppd(double ppd, int width, int height, const std::string& where) {
  check_number(where, ppd, flip_ppd_range());  // the one numeric check (params.h)
  const double mx = flip_max_ppd(width, height);
  if (ppd > mx)
    throw Error(where, "pixels per degree " + shortest_number(ppd) + " is over the FLIP limit of " +
                           shortest_number(mx) + " for a " + std::to_string(width) + "x" +
                           std::to_string(height) +
                           " image (filter radius at most max(64, longer side) pixels)");
}

void flip_prepare(const Image& img, double ppd, FlipPrepared& out, FlipWorkspace* ws) {
  if (img.empty()) throw Error("metrics.flip", "empty image");
  if (img.channels > 4)
    throw Error("metrics.flip", "expected 1 to 4 channels, got " + std::to_string(img.channels));
  check_flip_ppd(ppd, img.width, img.height, "metrics.flip");
  const size_t N = img.pixels();
  const flip_detail::Kernels k = flip_detail::kernels(ppd);
  FlipWorkspace local;
  FlipWorkspace& w = ws ? *ws : local;
  Plane(&ycc)[3] = w.ycc;
  for (Plane& p : ycc) p.resize(N);
  prepare(img, k, out, ycc);
  out.width = img.width;
  out.height = img.height;
  out.ppd = ppd;
}

// §4.7 and §5.4 for n pixels from index o: d = HyAB distance of the Lab values (hyab()),
// df = max(|edge|, |point| differences) / sqrt(2), to the power q_f = 0.5. SSE2 as above;
// std::max(de, dp) is (de < dp ? dp : de), i.e. max_pd(dp, de).
static void flip_differences_row(const FlipPrepared& pr, const FlipPrepared& pt, size_t o, int n,
                                 double* d, double* df) {
  const double inv_sqrt2 = 1.0 / std::sqrt(2.0);
  const double *rL = &pr.L[o], *rA = &pr.A[o], *rB = &pr.B[o], *re = &pr.edge[o],
               *rp = &pr.point[o];
  const double *tL = &pt.L[o], *tA = &pt.A[o], *tB = &pt.B[o], *te = &pt.edge[o],
               *tp = &pt.point[o];
  int x = 0;
#if defined(__SSE2__)
  const __m128d abs_mask = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
  const __m128d k = _mm_set1_pd(inv_sqrt2);
  auto ld = [](const double* p) { return _mm_loadu_pd(p); };
  for (; x + 2 <= n; x += 2) {
    const __m128d da = _mm_sub_pd(ld(rA + x), ld(tA + x)), db = _mm_sub_pd(ld(rB + x), ld(tB + x));
    const __m128d dl = _mm_and_pd(abs_mask, _mm_sub_pd(ld(rL + x), ld(tL + x)));
    _mm_storeu_pd(d + x,
                  _mm_add_pd(dl, _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(da, da), _mm_mul_pd(db, db)))));
    const __m128d de = _mm_and_pd(abs_mask, _mm_sub_pd(ld(re + x), ld(te + x)));
    const __m128d dp = _mm_and_pd(abs_mask, _mm_sub_pd(ld(rp + x), ld(tp + x)));
    _mm_storeu_pd(df + x, _mm_sqrt_pd(_mm_mul_pd(k, _mm_max_pd(dp, de))));
  }
#endif
  for (; x < n; ++x) {
    const double a[3] = {rL[x], rA[x], rB[x]}, b[3] = {tL[x], tA[x], tB[x]};
    d[x] = hyab(a, b);
    const double de = std::fabs(re[x] - te[x]);
    const double dp = std::fabs(rp[x] - tp[x]);
    df[x] = std::sqrt(inv_sqrt2 * std::max(de, dp));
  }
}

double flip(const FlipPrepared& pr, const FlipPrepared& pt, Image* map) {
  if (pr.width != pt.width || pr.height != pt.height)
    throw Error("metrics.flip", "images differ in size: " + std::to_string(pr.width) + "x" +
                                    std::to_string(pr.height) + " vs " + std::to_string(pt.width) +
                                    "x" + std::to_string(pt.height));
  if (pr.ppd != pt.ppd)
    throw Error("metrics.flip", "images prepared at different pixels per degree");
  if (pr.width <= 0 || pr.height <= 0) throw Error("metrics.flip", "empty image");
  const int W = pr.width, H = pr.height;
  const size_t N = size_t(W) * size_t(H);

  // §4.7-4.8, §5.4, §6 per pixel; §8 mean summed per row, then over rows in order.
  const double cmax = flip_detail::c_max(), knee = kPc * cmax;
  const double ln_knee_d = std::log(knee) / kQc;  // e < knee  <=>  ln d < ln(knee) / q_c
  const double ln_pt_knee = std::log(kPt / knee);
  Image local;
  Image& E = map ? *map : local;
  if (E.width != W || E.height != H || E.channels != 1) E.resize(W, H, 1);
  std::vector<double> row_sum(size_t(H), 0.0);
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
    std::vector<double> buf(2 * size_t(W));
    double *d_row = buf.data(), *df_row = d_row + W;
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const size_t o = size_t(y) * size_t(W);
      float* e_row = E.row(y);
      // The colour and feature differences first, in a loop that vectorises, then the powers.
      flip_differences_row(pr, pt, o, W, d_row, df_row);
      double s = 0;
      for (int x = 0; x < W; ++x) {
        const double d = d_row[x], df = df_row[x];
        double v;
        if (d == 0.0) {
          v = df == 1.0 ? 1.0 : 0.0;  // pow(0, 1 - df), without the pow calls (§6)
        } else {
          // e = d^q_c; below the knee dc = e p_t / knee, so ln dc = q_c ln d + ln(p_t / knee) and
          // dc^(1 - df) is one exp (one log and one exp per pixel instead of two pow calls).
          const double ln_d = std::log(d);
          if (ln_d < ln_knee_d) {
            v = std::exp((1.0 - df) * (kQc * ln_d + ln_pt_knee));
          } else {
            const double e = std::exp(kQc * ln_d);
            const double dc = kPt + (e - knee) / (cmax - knee) * (1.0 - kPt);
            v = df == 0.0 ? dc : std::pow(dc, 1.0 - df);
          }
        }
        e_row[x] = float(v);
        s += v;
      }
      row_sum[size_t(y)] = s;
    }
  });
  double total = 0;
  for (double s : row_sum) total += s;
  return total / double(N);
}

double flip(const Image& ref, const Image& test, double ppd, Image* map) {
  if (ref.width != test.width || ref.height != test.height || ref.channels != test.channels)
    throw Error("metrics.flip", "images differ in size: " + dims(ref) + " vs " + dims(test));
  FlipPrepared pr, pt;
  FlipWorkspace ws;
  flip_prepare(ref, ppd, pr, &ws);
  flip_prepare(test, ppd, pt, &ws);
  return flip(pr, pt, map);
}

Image flip_colormap(const Image& map) {
  // Polynomial fit of matplotlib's "magma" (van der Walt and Smith), coefficients by Matt
  // Zucker (public domain, CC0): c(t) = sum_k c_k t^k, clamped to [0,1].
  static const double c[7][3] = {
      {-0.002136485053939582, -0.000749655052795221, -0.005386127855323933},
      {0.2516605407371642, 0.6775232436837668, 2.494026599312351},
      {8.353717279216625, -3.577719514958484, 0.3144679030132573},
      {-27.66873308576866, 14.26473078096533, -13.64921318813922},
      {52.17613981234068, -27.94360607168351, 12.94416944238394},
      {-50.76852536473588, 29.04658282127291, 4.23415299384598},
      {18.65570506591883, -11.48977351997711, -5.601961508734096}};
  Image out(map.width, map.height, 3);
  for (size_t i = 0; i < map.pixels(); ++i) {
    double t = map.data[i * size_t(map.channels)];
    t = std::isfinite(t) ? clamp01(t) : 1.0;
    for (int ch = 0; ch < 3; ++ch) {
      double v = c[6][ch];
      for (int p = 5; p >= 0; --p) v = v * t + c[p][ch];
      out.data[3 * i + size_t(ch)] = float(clamp01(v));
    }
  }
  return out;
}

}  // namespace fovsim
