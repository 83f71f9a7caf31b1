// LDR-FLIP from ../shared/metrics/FLIP.md (Andersson et al., "FLIP: A Difference Evaluator for
// Alternating Images", HPG 2020; reference code NVlabs/flip v1.6). Section numbers below are
// FLIP.md's. Everything runs in double, planes included: with float planes, flat regions next to
// a feature kept ~1e-8 responses whose q_f = 0.5 root moved E by up to 4e-5 (FLIP.md §9). Rows are
// processed in parallel with TBB; each task allocates its row buffers once, never per pixel. The
// result is bit-identical at any thread count: every output value depends only on its own taps, and
// the mean is summed per row, then over rows in order.
#include "sim/metrics/flip.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include "sim/core/error.h"
#include "sim/core/math.h"

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

double srgb_to_linear(double c) {
  static const SrgbTable table;
  return table(c);
}

// §4.2-4.3: display sRGB -> YCxCz.
void srgb_to_ycxcz(double r, double g, double b, double out[3]) {
  const double R = srgb_to_linear(r), G = srgb_to_linear(g), B = srgb_to_linear(b);
  const double X = kM[0][0] * R + kM[0][1] * G + kM[0][2] * B;
  const double Y = kM[1][0] * R + kM[1][1] * G + kM[1][2] * B;
  const double Z = kM[2][0] * R + kM[2][1] * G + kM[2][2] * B;
  const double y = Y * kInvYn;
  out[0] = 116.0 * y - 16.0;
  out[1] = 500.0 * (X * kInvXn - y);
  out[2] = 200.0 * (y - Z * kInvZn);
}

// Cube root of t > 0: exponent-bit estimate, then three Halley steps (cubic convergence:
// ~3% -> 1e-5 -> 1e-15 -> rounding); within 3 ulp of std::cbrt on [0.008, 1.2] (checked on 2M
// points), without std::cbrt's frexp/scalbn library calls.
double cube_root(double t) {
  uint64_t bits;
  std::memcpy(&bits, &t, sizeof bits);
  bits = bits / 3 + 0x2A9F7893782DA1CEull;  // (bits - one) / 3 + one, one = bits of 1.0, rebalanced
  double y;
  std::memcpy(&y, &bits, sizeof y);
  for (int i = 0; i < 3; ++i) {
    const double y3 = y * y * y;
    y *= (y3 + 2.0 * t) / (2.0 * y3 + t);
  }
  return y;
}

// §4.6 CIELAB f(t).
double lab_f(double t) {
  constexpr double d = 6.0 / 29.0;
  return t > d * d * d ? cube_root(t) : t / (3.0 * d * d) + 4.0 / 29.0;
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

// §4.5-4.6: filtered YCxCz -> XYZ -> linear RGB, clamp -> Hunt-adjusted Lab.
void ycxcz_to_hunt_lab(double yy, double cx, double cz, double out[3]) {
  const double t = (yy + 16.0) / 116.0;
  const double X = kXn * (t + cx / 500.0), Y = kYn * t, Z = kZn * (t - cz / 200.0);
  const double R = clamp01(kMinv[0][0] * X + kMinv[0][1] * Y + kMinv[0][2] * Z);
  const double G = clamp01(kMinv[1][0] * X + kMinv[1][1] * Y + kMinv[1][2] * Z);
  const double B = clamp01(kMinv[2][0] * X + kMinv[2][1] * Y + kMinv[2][2] * Z);
  linear_to_hunt_lab(R, G, B, out);
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

// Horizontal pass (§4.4, §5.3) with clamp-to-edge: for each (kernel, out) pair,
// out(x,y) = sum_i k[i] (scale in(clamp(x+i-r), y) + offset).
struct HOut {
  const std::vector<double>* k;
  Real* out;
};
void hpass(int W, int H, int r, const Real* in, double scale, double offset, const HOut* outs,
           int n_out) {
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
    std::vector<double> pad(size_t(W) + 2 * size_t(r));
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const Real* src = in + size_t(y) * size_t(W);
      for (int x = -r; x < W + r; ++x)
        pad[size_t(x + r)] = scale * src[std::min(std::max(x, 0), W - 1)] + offset;
      for (int o = 0; o < n_out; ++o) {
        const double* k = outs[o].k->data();
        Real* dst = outs[o].out + size_t(y) * size_t(W);
        for (int x = 0; x < W; ++x) {
          const double* p = &pad[size_t(x)];
          double acc = 0;
          for (int i = 0; i <= 2 * r; ++i) acc += k[i] * p[i];
          dst[x] = Real(acc);
        }
      }
    }
  });
}

// Vertical pass of one output row with clamp-to-edge: out[x] = sum_j k[j] in(x, clamp(y+j-r)).
void vrow(int W, int H, int r, const Real* in, const std::vector<double>& k, int y, double* out) {
  std::fill(out, out + W, 0.0);
  for (int j = 0; j <= 2 * r; ++j) {
    const int yy = std::min(std::max(y + j - r, 0), H - 1);
    const Real* src = in + size_t(yy) * size_t(W);
    const double kj = k[size_t(j)];
    for (int x = 0; x < W; ++x) out[x] += kj * src[x];
  }
}

void prepare(const Image& img, const flip_detail::Kernels& k, FlipPrepared& out, Plane (&ycc)[3],
             Plane (&tmp)[4]) {
  const int W = img.width, H = img.height, C = img.channels;
  const size_t N = img.pixels();
  for (Plane* p : {&out.L, &out.A, &out.B, &out.edge, &out.point}) p->resize(N);
  // §4.1-4.3 per pixel. Grey (1 or 2 channels) is copied to RGB; alpha is dropped (§1).
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const float* p = img.row(y);
      for (int x = 0; x < W; ++x) {
        const float* px = p + size_t(x) * size_t(C);
        const double r = px[0], g = C >= 3 ? px[1] : px[0], b = C >= 3 ? px[2] : px[0];
        double v[3];
        srgb_to_ycxcz(r, g, b, v);
        const size_t i = size_t(y) * size_t(W) + size_t(x);
        ycc[0][i] = Real(v[0]);
        ycc[1][i] = Real(v[1]);
        ycc[2][i] = Real(v[2]);
      }
    }
  });
  // §4.4: horizontal then vertical CSF passes; C_z is the sum of two separable Gaussians.
  HOut h0{&k.y, tmp[0].data()}, h1{&k.cx, tmp[1].data()};
  HOut h2[2] = {{&k.cz1, tmp[2].data()}, {&k.cz2, tmp[3].data()}};
  hpass(W, H, k.r_s, ycc[0].data(), 1.0, 0.0, &h0, 1);
  hpass(W, H, k.r_s, ycc[1].data(), 1.0, 0.0, &h1, 1);
  hpass(W, H, k.r_s, ycc[2].data(), 1.0, 0.0, h2, 2);
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
    std::vector<double> buf(5 * size_t(W));
    double *fy = buf.data(), *fcx = fy + W, *fcz = fcx + W, *fcz2 = fcz + W;
    for (int y = rows.begin(); y < rows.end(); ++y) {
      vrow(W, H, k.r_s, tmp[0].data(), k.y, y, fy);
      vrow(W, H, k.r_s, tmp[1].data(), k.cx, y, fcx);
      vrow(W, H, k.r_s, tmp[2].data(), k.cz1, y, fcz);
      vrow(W, H, k.r_s, tmp[3].data(), k.cz2, y, fcz2);
      const size_t o = size_t(y) * size_t(W);
      for (int x = 0; x < W; ++x) {
        double lab[3];
        ycxcz_to_hunt_lab(fy[x], fcx[x], fcz[x] + fcz2[x], lab);
        out.L[o + size_t(x)] = Real(lab[0]);
        out.A[o + size_t(x)] = Real(lab[1]);
        out.B[o + size_t(x)] = Real(lab[2]);
      }
    }
  });
  // §5.1-5.3 on the unfiltered Y': A = (Y' + 16) / 116; one x-pass (D, S, G), then the y-pass.
  HOut hf[3] = {{&k.d, tmp[0].data()}, {&k.s, tmp[1].data()}, {&k.g, tmp[2].data()}};
  hpass(W, H, k.r_f, ycc[0].data(), 1.0 / 116.0, 16.0 / 116.0, hf, 3);
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
    std::vector<double> buf(4 * size_t(W));
    double *ex = buf.data(), *px = ex + W, *ey = px + W, *py = ey + W;
    for (int y = rows.begin(); y < rows.end(); ++y) {
      vrow(W, H, k.r_f, tmp[0].data(), k.g, y, ex);
      vrow(W, H, k.r_f, tmp[1].data(), k.g, y, px);
      vrow(W, H, k.r_f, tmp[2].data(), k.d, y, ey);
      vrow(W, H, k.r_f, tmp[2].data(), k.s, y, py);
      const size_t o = size_t(y) * size_t(W);
      for (int x = 0; x < W; ++x) {
        out.edge[o + size_t(x)] = Real(std::sqrt(ex[x] * ex[x] + ey[x] * ey[x]));
        out.point[o + size_t(x)] = Real(std::sqrt(px[x] * px[x] + py[x] * py[x]));
      }
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

static void check_ppd(double ppd) {
  if (!(std::isfinite(ppd) && ppd > 0))
    throw Error("metrics.flip",
                "pixels per degree must be finite and > 0, got " + std::to_string(ppd));
}

void flip_prepare(const Image& img, double ppd, FlipPrepared& out, FlipWorkspace* ws) {
  if (img.empty()) throw Error("metrics.flip", "empty image");
  if (img.channels > 4)
    throw Error("metrics.flip", "expected 1 to 4 channels, got " + std::to_string(img.channels));
  check_ppd(ppd);
  const size_t N = img.pixels();
  const flip_detail::Kernels k = flip_detail::kernels(ppd);
  FlipWorkspace local;
  FlipWorkspace& w = ws ? *ws : local;
  Plane(&ycc)[3] = w.ycc;
  Plane(&tmp)[4] = w.tmp;
  for (Plane& p : ycc) p.resize(N);
  for (Plane& p : tmp) p.resize(N);
  prepare(img, k, out, ycc, tmp);
  out.width = img.width;
  out.height = img.height;
  out.ppd = ppd;
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
  const double cmax = flip_detail::c_max(), knee = kPc * cmax, inv_sqrt2 = 1.0 / std::sqrt(2.0);
  const double ln_knee_d = std::log(knee) / kQc;  // e < knee  <=>  ln d < ln(knee) / q_c
  const double ln_pt_knee = std::log(kPt / knee);
  Image local;
  Image& E = map ? *map : local;
  if (E.width != W || E.height != H || E.channels != 1) E.resize(W, H, 1);
  std::vector<double> row_sum(size_t(H), 0.0);
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const size_t o = size_t(y) * size_t(W);
      float* e_row = E.row(y);
      double s = 0;
      for (int x = 0; x < W; ++x) {
        const size_t i = o + size_t(x);
        const double a[3] = {pr.L[i], pr.A[i], pr.B[i]}, b[3] = {pt.L[i], pt.A[i], pt.B[i]};
        const double d = hyab(a, b);
        const double de = std::fabs(pr.edge[i] - pt.edge[i]);
        const double dp = std::fabs(pr.point[i] - pt.point[i]);
        const double df = std::sqrt(inv_sqrt2 * std::max(de, dp));  // ^q_f, q_f = 0.5
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
