// FovVideoVDP v1.2 (Mantiuk et al. 2021), from ../shared/metrics/FovVideoVDP.md (sections §).
// Layout: constants (§2), display (§3), CSF formula and tables (§8), temporal taps (§5), pyramid
// (§6), the reference stream (§4-§8 of the reference planes), the test stream (§7, §9, §10).
#include "sim/metrics/fvvdp.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "sim/core/error.h"
#include "sim/core/powf_det.h"
#include "sim/core/powf_lanes.h"
#include "sim/core/scratch_pool.h"
#include "sim/metrics/metrics.h"
#include "sim/metrics/registry.h"

namespace fovsim {

namespace {

constexpr double kPiD = 3.14159265358979323846;

// §2: calibrated parameters of fvvdp_1_20 (Mantiuk et al. 2021, reference v1.2.x).
constexpr double kMaskP = 2.4;
constexpr double kMaskC = -0.973838;
constexpr double kWTransient = 0.25;
constexpr double kBeta = 1.52134;
constexpr double kBetaTch = 0.666092;
constexpr double kSustainedSigma = 0.5;
constexpr double kSustainedBeta = 0.06;
constexpr double kSensitivityCorrectionDb = 16.2596;
constexpr double kJodA = -0.0161713;
constexpr double kLogJodExp = -0.2280;
constexpr double kMaskQ[2] = {2.43685, 4.946};
constexpr double kKcm = 0.604562;
constexpr double kCsfSigma = 1.5;                   // csf_sigma = -1.5: sigma = 1.5 / rho degrees
constexpr double kTransientK2 = 0.062170507756932;  // §5.2

const char* kWhere = "metrics.fvvdp";

template <class F>
void for_rows(int h, int w, F f) {
  const int grain = std::max(1, 16384 / std::max(1, w));
  tbb::parallel_for(tbb::blocked_range<int>(0, h, grain), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) f(y);
  });
}

// ---------------------------------------------------------------------------------------------
// §8.2 CSF model (Mantiuk et al. 2021 §3.4; castleCSF-style achromatic mechanism).

double lum_dep(const double* p, int n, double lum) {
  if (n == 1) return p[0];
  double v = p[0] * std::pow(1.0 + p[1] / lum, -p[2]);
  if (n == 5) v *= 1.0 - std::pow(1.0 + p[3] / lum, -p[4]);
  return v;
}

struct Mechanism {
  double smax[5];
  int nsmax;
  double fmax[3];
  int nfmax;
  double bw, gamma, a_prime;
  bool lowpass;
};

const Mechanism kMech[3] = {
    {{356404, 6.2726, 0.320031, 895943, 7.77919e-05},
     5,
     {2.3021, 3317.45, 0.186215},
     3,
     1.07516,
     1.1107,
     52.9768,
     false},
    {{423.978, 15.4032, 0.50343, 0, 0}, 3, {0.122699, 0, 0}, 1, 2.70669, 1.72903, 1.38437, true},
    {{11811.9, 196.342, 0.339396, 0, 0}, 3, {7.1099e-08, 0, 0}, 1, 5.3416, 1.47263, 0.282573, true},
};

double mech_sensitivity(const Mechanism& m, double rho, double area, double lum) {
  const double smax = lum_dep(m.smax, m.nsmax, lum);
  const double fmax = lum_dep(m.fmax, m.nfmax, lum);
  double speak;
  if (m.lowpass && rho < fmax) {
    speak = smax;
  } else {
    const double d = std::log10(rho) - std::log10(fmax);
    speak = smax / std::pow(10.0, d * d / (0.5 * std::pow(2.0, m.bw)));
  }
  const double ag = std::pow(area, m.gamma) * rho * rho;
  return speak * std::sqrt(ag / (m.a_prime + 0.65 * area + ag));
}

// Spatio-velocity CSF of Laird et al. 2006 (after Daly), §8.2 (b).
double daly_d(double rho, double v) {
  constexpr double c0 = 0.6329, c1 = 0.8404, c2 = 0.7986;
  const double vp = std::max(v, 0.1);
  const double l = std::fabs(std::log10(c2 * vp / 3.0));
  const double kappa = 6.1 + 7.3 * l * l * l;
  const double rho_max = 45.9 / (c2 * vp + 2.0);
  const double q = 2.0 * kPiD * c1 * rho;
  return kappa * c0 * c1 * c2 * vp * q * q * std::exp(-4.0 * kPiD * c1 * rho / rho_max);
}

double spatial_sensitivity(double rho, double area, double L) {
  static const double M_lms[3][3] = {{0.187596268556126, 0.585168649077728, -0.026384263306304},
                                     {-0.133397430663221, 0.405505777260049, 0.034502127690364},
                                     {0.000244379021663, -0.000542995890619, 0.019406849066323}};
  static const double M_acc[3][3] = {
      {1, 0.256197, 6.42477e-7}, {1, -0.933541, 0.00373304}, {-0.00130319, -1.1504, 1}};
  const double white[3] = {0.95047, 1.0, 1.08883};
  const double delta[3] = {0.698, 0.302, 0.019613};
  double c[3], norm2 = 0;
  for (int i = 0; i < 3; ++i) {
    const double lms_w = M_lms[i][0] * white[0] + M_lms[i][1] * white[1] + M_lms[i][2] * white[2];
    c[i] = delta[i] / (L * lms_w);
    norm2 += c[i] * c[i];
  }
  const double lms_w0 = M_lms[0][0] * white[0] + M_lms[0][1] * white[1] + M_lms[0][2] * white[2];
  const double lms_w1 = M_lms[1][0] * white[0] + M_lms[1][1] * white[1] + M_lms[1][2] * white[2];
  const double lum = L * lms_w0 + L * lms_w1;
  double C2 = 0;
  for (int i = 0; i < 3; ++i) {
    const double a = M_acc[i][0] * c[0] + M_acc[i][1] * c[1] + M_acc[i][2] * c[2];
    const double s = std::fabs(a) * mech_sensitivity(kMech[i], rho, area, lum);
    C2 += s * s;
  }
  return std::sqrt(3.0) * std::sqrt(C2) / std::sqrt(norm2);
}

// ---------------------------------------------------------------------------------------------
// §8.3 tables: log2 CSF on a 32^3 grid, computed once per process.

constexpr int kN = 32;

struct CsfTables {
  float Y[kN], rho[kN], ecc[kN];
  float ylog[kN], rholog[kN], eccsqrt[kN];
  std::vector<float> T[2];  // [omega][i + 32 j + 1024 k] = log2 CSF(rho_j, Y_i, e_k)
  float at(int w, int i, int j, int k) const { return T[w][size_t(i + kN * j + kN * kN * k)]; }
};

const CsfTables& csf_tables() {
  static const CsfTables tables = [] {
    CsfTables t;
    for (int i = 0; i < kN; ++i) {
      t.Y[i] = float(std::pow(10.0, -3.0 + 7.0 * i / 31.0));
      t.rho[i] = float(std::pow(2.0, -4.0 + 10.0 * i / 31.0));
      const double s = i * std::sqrt(120.0) / 31.0;
      t.ecc[i] = float(s * s);
      t.ylog[i] = float(std::log2(double(t.Y[i])));
      t.rholog[i] = float(std::log2(double(t.rho[i])));
      t.eccsqrt[i] = float(std::sqrt(double(t.ecc[i])));
    }
    for (int w = 0; w < 2; ++w) {
      t.T[w].resize(size_t(kN) * kN * kN);
      const double omega = w == 0 ? 0.0 : 5.0;
      tbb::parallel_for(0, kN, [&](int k) {
        const double e = std::pow(k * std::sqrt(120.0) / 31.0, 2.0);
        for (int j = 0; j < kN; ++j) {
          const double rho = std::pow(2.0, -4.0 + 10.0 * j / 31.0);
          for (int i = 0; i < kN; ++i) {
            const double Y = std::pow(10.0, -3.0 + 7.0 * i / 31.0);
            const double v = fvvdp_detail::csf_formula(rho, omega, Y, e);
            t.T[w][size_t(i + kN * j + kN * kN * k)] = float(std::log2(std::max(v, 1e-4)));
          }
        }
      });
    }
    return t;
  }();
  return tables;
}

struct Axis {
  int lo, hi;
  float t;
};

// §8.3 per-axis rule: hi = smallest index with x_hi >= q (capped at 31), lo = max(hi - 1, 0),
// t = (q - x_lo) / (x_hi - x_lo + 1e-6), 0 when hi = lo, at least 0. `q` is already clamped to
// the node range. Nodes are near-uniform: start from the analytic index, then correct.
inline Axis axis_lookup(float q, const float* x, float x0, float step) {
  int hi = int(std::ceil((q - x0) / step));
  hi = std::min(std::max(hi, 0), kN - 1);
  while (hi < kN - 1 && x[hi] < q) ++hi;
  while (hi > 0 && x[hi - 1] >= q) --hi;
  Axis a;
  a.hi = hi;
  a.lo = std::max(hi - 1, 0);
  if (a.hi == a.lo) {
    a.t = 0.f;
  } else {
    a.t = std::max((q - x[a.lo]) / (x[a.hi] - x[a.lo] + 1e-6f), 0.f);
  }
  return a;
}

struct AxisSteps {
  float ystep, rstep, estep;
};
AxisSteps axis_steps() {
  const CsfTables& t = csf_tables();
  return {(t.ylog[kN - 1] - t.ylog[0]) / float(kN - 1),
          (t.rholog[kN - 1] - t.rholog[0]) / float(kN - 1),
          (t.eccsqrt[kN - 1] - t.eccsqrt[0]) / float(kN - 1)};
}

inline Axis y_axis(const CsfTables& t, const AxisSteps& s, float L) {
  const float q = std::log2(std::min(std::max(L, t.Y[0]), t.Y[kN - 1]));
  return axis_lookup(q, t.ylog, t.ylog[0], s.ystep);
}
inline Axis rho_axis(const CsfTables& t, const AxisSteps& s, float rho) {
  const float q = std::log2(std::min(std::max(rho, t.rho[0]), t.rho[kN - 1]));
  return axis_lookup(q, t.rholog, t.rholog[0], s.rstep);
}
inline Axis ecc_axis(const CsfTables& t, const AxisSteps& s, float e) {
  const float q = std::sqrt(std::min(std::max(e, t.ecc[0]), t.ecc[kN - 1]));
  return axis_lookup(q, t.eccsqrt, t.eccsqrt[0], s.estep);
}

inline float lerp(float a, float b, float t) {
  return a * (1.f - t) + b * t;
}

// Trilinear interpolation of T_omega (interpolated over e, then rho, then Y).
inline float trilinear(const CsfTables& t, int w, const Axis& ay, const Axis& ar, const Axis& ae) {
  float yv[2];
  const int yi[2] = {ay.lo, ay.hi};
  for (int a = 0; a < 2; ++a) {
    const float r0 = lerp(t.at(w, yi[a], ar.lo, ae.lo), t.at(w, yi[a], ar.lo, ae.hi), ae.t);
    const float r1 = lerp(t.at(w, yi[a], ar.hi, ae.lo), t.at(w, yi[a], ar.hi, ae.hi), ae.t);
    yv[a] = lerp(r0, r1, ar.t);
  }
  return lerp(yv[0], yv[1], ay.t);
}

const float kSensCorr = float(std::pow(10.0, kSensitivityCorrectionDb / 20.0));

// ---------------------------------------------------------------------------------------------
// §3.1, §4: display-encoded RGB -> absolute luminance (float32, as the reference).

// The power through spec_pow (glibc's powf with fixed bits, sim/core/powf_det.h), as
// to_luminance's packet form (powf_array) computes it.
inline float srgb_lin(float v) {
  v = std::min(std::max(v, 0.f), 1.f);
  return v > 0.04045f ? spec_pow((v + 0.055f) / 1.055f, 2.4f) : v / 12.92f;
}

struct LinTable {
  float code[256], lin[256];
  LinTable() {
    for (int k = 0; k < 256; ++k) {
      code[k] = float(k) / 255.f;
      lin[k] = srgb_lin(code[k]);
    }
  }
};

// srgb_lin of n values into out, bit for bit: 8-bit codes (PNG input, 8-bit tone-mapped frames)
// through the table, the other values' powers together (powf_array). n <= 256.
void lin_run(const LinTable& t, const float* v, int n, float* out) {
  float base[256], pw[256];
  int idx[256], m = 0;
  for (int j = 0; j < n; ++j) {
    const float s = v[j] * 255.f;
    if (s >= 0.f && s <= 255.f) {
      const int k = int(s + 0.5f);
      if (t.code[k] == v[j]) {
        out[j] = t.lin[k];
        continue;
      }
    }
    const float c = std::min(std::max(v[j], 0.f), 1.f);
    if (c > 0.04045f) {
      base[m] = (c + 0.055f) / 1.055f;
      idx[m++] = j;
    } else {
      out[j] = c / 12.92f;
    }
  }
  powf_array(base, 2.4f, pw, m);
  for (int i = 0; i < m; ++i) out[idx[i]] = pw[i];
}

void to_luminance(const Image& img, const FvvdpDisplay& d, float* out) {
  static const LinTable table;
  const float range = float(d.y_peak - d.y_black), black = float(d.y_black);
  const int W = img.width, C = img.channels;
  const int cu = C >= 3 ? 3 : 1;  // channels used
  for_rows(img.height, W, [&](int y) {
    const float* p = img.row(y);
    float* o = out + size_t(y) * size_t(W);
    constexpr int kRun = 64;  // pixels per run (cu * kRun <= 256 values)
    float v[3 * kRun], lin[3 * kRun];
    for (int x0 = 0; x0 < W; x0 += kRun) {
      const int m = std::min(kRun, W - x0);
      for (int j = 0; j < m; ++j)
        for (int c = 0; c < cu; ++c) v[cu * j + c] = p[size_t(x0 + j) * size_t(C) + size_t(c)];
      lin_run(table, v, cu * m, lin);
      for (int j = 0; j < m; ++j) {
        if (cu == 3) {
          const float lr = range * lin[3 * j] + black;
          const float lg = range * lin[3 * j + 1] + black;
          const float lb = range * lin[3 * j + 2] + black;
          o[x0 + j] = 0.2126729f * lr + 0.7151522f * lg + 0.0721750f * lb;
        } else {
          o[x0 + j] = range * lin[j] + black;
        }
      }
    }
  });
}

// ---------------------------------------------------------------------------------------------
// §6 pyramid.

constexpr float kK[5] = {0.05f, 0.25f, 0.4f, 0.25f, 0.05f};

inline int mirror(int i, int n) {
  return i < 0 ? -i - 1 : (i >= n ? 2 * n - 1 - i : i);
}

// §6.3 reduce: vertical pass with half-sample symmetric borders, then the horizontal pass with
// the mirrored left border and the right border chosen by the parity of h [quirk].
void reduce(const float* in, int w, int h, float* out, std::vector<float>& tmp) {
  const int h2 = (h + 1) / 2, w2 = (w + 1) / 2;
  tmp.resize(size_t(w) * size_t(h2));
  for_rows(h2, w, [&](int i) {
    const float* r[5];
    for (int j = 0; j < 5; ++j) r[j] = in + size_t(mirror(2 * i + j - 2, h)) * size_t(w);
    float* o = tmp.data() + size_t(i) * size_t(w);
    for (int x = 0; x < w; ++x)
      o[x] =
          kK[0] * r[0][x] + kK[1] * r[1][x] + kK[2] * r[2][x] + kK[3] * r[3][x] + kK[4] * r[4][x];
  });
  const bool h_odd = (h % 2) == 1;
  for_rows(h2, w2, [&](int i) {
    const float* a = tmp.data() + size_t(i) * size_t(w);
    float* o = out + size_t(i) * size_t(w2);
    for (int j = 0; j < w2; ++j) {
      const int c = 2 * j;
      float s;
      if (c >= 2 && c + 2 < w) {
        s = kK[0] * a[c - 2] + kK[1] * a[c - 1] + kK[2] * a[c] + kK[3] * a[c + 1] +
            kK[4] * a[c + 2];
      } else {
        // Borders: mirrored on the left; zero padding on the right plus the correction below.
        float v[5];
        for (int k = 0; k < 5; ++k) {
          const int xi = c + k - 2;
          v[k] = xi < 0 ? a[-xi - 1] : (xi >= w ? 0.f : a[xi]);
        }
        s = kK[0] * v[0] + kK[1] * v[1] + kK[2] * v[2] + kK[3] * v[3] + kK[4] * v[4];
        if (j == w2 - 1) s += h_odd ? kK[3] * a[w - 1] + kK[4] * a[w - 2] : kK[4] * a[w - 1];
      }
      o[j] = s;
    }
  });
}

// §6.4 expand g (mw x mh) to w x h: out[2q] = 0.1 g[q-1] + 0.8 g[q] + 0.1 g[q+1],
// out[2q+1] = 0.5 g[q] + 0.5 g[q+1], with g[-1] = g[0] and g[m] = g[m-1]; vertical first.
void expand(const float* g, int mw, int mh, int w, int h, float* out, std::vector<float>& tmp) {
  tmp.resize(size_t(mw) * size_t(h));
  for_rows(h, mw, [&](int y) {
    const int q = y / 2;
    float* o = tmp.data() + size_t(y) * size_t(mw);
    const float* g0 = g + size_t(q) * size_t(mw);
    const float* gp = g + size_t(std::min(q + 1, mh - 1)) * size_t(mw);
    if (y % 2 == 0) {
      const float* gm = g + size_t(std::max(q - 1, 0)) * size_t(mw);
      for (int x = 0; x < mw; ++x) o[x] = 0.1f * gm[x] + 0.8f * g0[x] + 0.1f * gp[x];
    } else {
      for (int x = 0; x < mw; ++x) o[x] = 0.5f * g0[x] + 0.5f * gp[x];
    }
  });
  for_rows(h, w, [&](int y) {
    const float* a = tmp.data() + size_t(y) * size_t(mw);
    float* o = out + size_t(y) * size_t(w);
    for (int x = 0; x < w; ++x) {
      const int q = x / 2;
      const float ap = a[std::min(q + 1, mw - 1)];
      if (x % 2 == 0) {
        o[x] = 0.1f * a[std::max(q - 1, 0)] + 0.8f * a[q] + 0.1f * ap;
      } else {
        o[x] = 0.5f * a[q] + 0.5f * ap;
      }
    }
  });
}

struct Level {
  int w = 0, h = 0;
};

std::vector<Level> level_sizes(int W, int H, int nb) {
  std::vector<Level> l(size_t(nb) + 1);
  l[0] = {W, H};
  for (int i = 1; i <= nb; ++i)
    l[size_t(i)] = {(l[size_t(i) - 1].w + 1) / 2, (l[size_t(i) - 1].h + 1) / 2};
  return l;
}

// Gaussian pyramid G_0..G_nb of one plane; G_0 is the plane itself (not copied).
struct Gaussian {
  std::vector<std::vector<float>> G;  // G[l] for l >= 1
  void build(const float* plane, const std::vector<Level>& lv, std::vector<float>& tmp) {
    const int nb = int(lv.size()) - 1;
    G.resize(size_t(nb) + 1);
    for (int l = 1; l <= nb; ++l) {
      G[size_t(l)].resize(size_t(lv[size_t(l)].w) * size_t(lv[size_t(l)].h));
      const float* src = l == 1 ? plane : G[size_t(l) - 1].data();
      reduce(src, lv[size_t(l) - 1].w, lv[size_t(l) - 1].h, G[size_t(l)].data(), tmp);
    }
  }
  const float* level(const float* plane, int l) const {
    return l == 0 ? plane : G[size_t(l)].data();
  }
};

// §5.2 causal temporal filter over a ring of luminance frames (replicate padding).
struct TemporalRing {
  std::vector<std::vector<float>> ring;
  int head = -1;  // slot of the current frame
  void reset() { head = -1; }
  float* push_slot(size_t n) {
    if (ring.empty()) return nullptr;
    head = (head + 1) % int(ring.size());
    ring[size_t(head)].resize(n);
    return ring[size_t(head)].data();
  }
  // After the first frame's luminance is in its slot: replicate it into the history.
  void replicate_first() {
    for (auto& r : ring)
      if (&r != &ring[size_t(head)]) r = ring[size_t(head)];
  }
  // Both channels in one pass; per pixel the taps are summed in double in tap order.
  void filter2(const std::vector<double>& fs, const std::vector<double>& ft, int W, int H,
               float* out_s, float* out_t) const {
    const int L = int(fs.size());
    std::vector<const float*> src(static_cast<size_t>(L));
    for (int k = 0; k < L; ++k) {
      const int s = ((head - k) % L + L) % L;
      src[size_t(k)] = ring[size_t(s)].data();
    }
    for_rows(H, W, [&](int y) {
      constexpr int kChunk = 256;
      double as[kChunk], at[kChunk];
      const size_t off = size_t(y) * size_t(W);
      for (int x0 = 0; x0 < W; x0 += kChunk) {
        const int n = std::min(kChunk, W - x0);
        for (int i = 0; i < n; ++i) as[i] = at[i] = 0.0;
        for (int k = 0; k < L; ++k) {
          const float* p = src[size_t(k)] + off + size_t(x0);
          const double a = fs[size_t(k)], b = ft[size_t(k)];
          for (int i = 0; i < n; ++i) {
            const double v = double(p[i]);
            as[i] += a * v;
            at[i] += b * v;
          }
        }
        for (int i = 0; i < n; ++i) {
          out_s[off + size_t(x0 + i)] = float(as[i]);
          out_t[off + size_t(x0 + i)] = float(at[i]);
        }
      }
    });
  }
};

struct Frame {
  int W = 0, H = 0;
  bool video = false;
  TemporalRing ring;
  std::vector<float> Y, X[2];  // luminance (image: the plane itself); sustained, transient
  std::vector<Level> lv;
  Gaussian pyr[2];
  std::vector<float> tmp;

  // The sizes only: the planes are allocated by the first push(), so a test stream that scores
  // with another stream's frames (FvvdpTestStream::push with `same`) holds none.
  void init(int w, int h, bool vid, int L, int nb) {
    W = w;
    H = h;
    video = vid;
    ring.ring.assign(vid ? size_t(L) : 0, {});
    ring.reset();
    lv = level_sizes(W, H, nb);
  }
  // Luminance, temporal filtering (video) and the Gaussian pyramids of the planes.
  void push(const Image& img, const FvvdpDisplay& d, const std::vector<double>& fs,
            const std::vector<double>& ft) {
    const size_t n = size_t(W) * size_t(H);
    if (!video) {
      Y.resize(n);
      to_luminance(img, d, Y.data());
      pyr[0].build(Y.data(), lv, tmp);
      return;
    }
    for (auto& x : X) x.resize(n);  // Y is not used: the luminance goes into the ring
    const bool first = ring.head < 0;
    float* slot = ring.push_slot(n);
    to_luminance(img, d, slot);
    if (first) ring.replicate_first();
    ring.filter2(fs, ft, W, H, X[0].data(), X[1].data());
    for (int c = 0; c < 2; ++c) pyr[c].build(X[c].data(), lv, tmp);
  }
  const float* plane(int c) const { return video ? X[c].data() : Y.data(); }
  const float* level(int c, int l) const { return pyr[c].level(plane(c), l); }
};

}  // namespace

// A stream's frames: what FvvdpTestStream::push with another stream's frames reads.
struct FvvdpFrames : Frame {};

// ---------------------------------------------------------------------------------------------
// Public detail functions.

namespace fvvdp_detail {

double csf_formula(double rho, double omega, double L, double e) {
  const double sigma = kCsfSigma / rho;
  const double m_rel = std::pow(3.67 / (e + 3.67), kKcm);
  const double rho_p = rho / m_rel;
  const double area = kPiD * (sigma * m_rel) * (sigma * m_rel);
  const double R = daly_d(rho_p, omega / rho_p) / (daly_d(rho_p, 0.0 / rho_p) + 1e-5);
  return spatial_sensitivity(rho_p, area, L) * R;
}

double csf_table(double rho, double omega, double L, double e) {
  const CsfTables& t = csf_tables();
  const AxisSteps s = axis_steps();
  const int w = omega == 0 ? 0 : 1;
  return std::exp2(double(trilinear(t, w, y_axis(t, s, float(L)), rho_axis(t, s, float(rho)),
                                    ecc_axis(t, s, float(e)))));
}

int filter_length(double fps) {
  return int(std::ceil(250.0 / (1000.0 / fps)));
}

void temporal_taps(double fps, std::vector<double>& fs, std::vector<double>& ft) {
  const int L = filter_length(fps);
  if (L < 2)
    throw Error(kWhere, "frame rate " + std::to_string(fps) +
                            " Hz gives fewer than 2 temporal taps (needs fps > 4)");
  std::vector<double> t(static_cast<size_t>(L));
  for (int k = 0; k < L; ++k) t[size_t(k)] = k * (L / fps) / (L - 1);  // [quirk] §5.2
  fs.assign(size_t(L), 0.0);
  double sum = 0;
  for (int k = 0; k < L; ++k) {
    const double d = std::log(t[size_t(k)] + 1e-4) - std::log(kSustainedBeta);
    fs[size_t(k)] = std::exp(-d * d / (2.0 * kSustainedSigma * kSustainedSigma));
    sum += fs[size_t(k)];
  }
  for (auto& v : fs) v /= sum;
  ft.assign(size_t(L), 0.0);
  for (int k = 0; k + 1 < L; ++k)
    ft[size_t(k)] = kTransientK2 * (fs[size_t(k) + 1] - fs[size_t(k)]) / (t[1] - t[0]);
}

int settle_frames(double fps) {
  if (fps <= 0) return 0;
  std::vector<double> fs, ft;
  temporal_taps(fps, fs, ft);
  double cum = 0;
  for (size_t k = 0; k < fs.size(); ++k) {
    cum += fs[k];
    if (cum >= 0.95) return int(k);
  }
  return int(fs.size()) - 1;
}

std::vector<double> band_frequencies(int height, int width, double ppd) {
  const int n_max = int(std::floor(std::log2(double(std::min(height, width))))) - 1;
  int istar = 14;
  std::vector<double> f(15);
  for (int i = 0; i < 15; ++i) {
    f[size_t(i)] = ppd / 2.0 * (i == 0 ? 1.0 : 0.3228 * std::pow(2.0, -(i - 1)));
  }
  for (int i = 0; i < 15; ++i)
    if (f[size_t(i)] <= 0.5) {
      istar = i;
      break;
    }
  const int nb = std::min(istar + 1, n_max);
  if (nb < 1)
    throw Error(kWhere, "image " + std::to_string(width) + "x" + std::to_string(height) +
                            " is too small for FovVideoVDP (needs at least 4x4 pixels)");
  f.resize(size_t(nb));
  return f;
}

double torch_cpu_sum(const float* v, size_t n, int threads) {
  if (threads <= 0) {
    double s = 0;
    for (size_t i = 0; i < n; ++i) s += double(v[i]);
    return s;
  }
  // at::parallel_for(0, n, GRAIN_SIZE): min(threads, ceil(n / grain)) chunks of equal size, each
  // summed from 0 in its own float accumulator, then combined from thread 0 on. One chunk when
  // n < grain or on one thread. The adds must stay in this order (no reassociation): they are
  // the reference's rounding.
  const size_t g = size_t(kFvvdpTorchGrain);
  const size_t T = n < g ? 1 : std::min(size_t(threads), (n + g - 1) / g);
  const size_t chunk = (n + T - 1) / T;
  float total = 0.f;
  for (size_t t = 0; t < T; ++t) {
    float a = 0.f;
    const size_t end = std::min(n, (t + 1) * chunk);
    for (size_t i = t * chunk; i < end; ++i) a += v[i];
    total += a;
  }
  return double(total);
}

}  // namespace fvvdp_detail

double fvvdp_jod_from_q(double mean_q) {
  const double beta_j = std::pow(10.0, kLogJodExp);
  return 10.0 + kJodA * std::pow(mean_q, beta_j);  // §11
}

// ---------------------------------------------------------------------------------------------
// Display (§3).

namespace {
// §3.2: ppd = 1 / (2 atan(w_m / (2 W d)) 180/pi), in the reference's order of operations.
double ppd_of(double w_m, int W, double d) {
  return 1.0 / (2.0 * (std::atan(0.5 * w_m / W / d) * (180.0 / kPiD)));
}
}  // namespace

FvvdpDisplay FvvdpDisplay::from_spec(const std::string& name, int width, int height,
                                     double viewing_distance_m, double diagonal_inches,
                                     double fov_diagonal_deg, double max_luminance, double contrast,
                                     double min_luminance, double ambient_lux, double k_refl) {
  FvvdpDisplay d;
  d.name = name;
  d.width = width;
  d.height = height;
  const double a = double(width) / double(height);
  d.d_m = viewing_distance_m > 0 ? viewing_distance_m : 3.0;
  if (diagonal_inches > 0) {
    const double D_mm = diagonal_inches * 25.4;  // in mm, as the reference (same ppd bits)
    const double h_mm = std::sqrt(D_mm * D_mm / (1 + a * a));
    d.h_m = h_mm / 1000.0;
    d.w_m = a * h_mm / 1000.0;
  } else if (fov_diagonal_deg > 0) {
    const double p = std::sqrt(double(width) * width + double(height) * height) /
                     (2.0 * std::tan(fov_diagonal_deg * kPiD / 180.0 / 2.0));
    d.h_m = height * d.d_m / p;  // = 2 tan(theta_h / 2) d, theta_h = 2 atan(H / (2 p))
    d.w_m = a * d.h_m;
  } else {
    throw Error(kWhere, "display " + name + " needs a diagonal size or a diagonal FOV");
  }
  d.ppd = ppd_of(d.w_m, width, d.d_m);
  const double C =
      min_luminance > 0 ? max_luminance / min_luminance : (contrast > 0 ? contrast : 500.0);
  const double y_refl = ambient_lux / kPiD * k_refl;
  d.y_peak = max_luminance;
  d.y_black = y_refl + max_luminance / C;
  return d;
}

FvvdpDisplay FvvdpDisplay::standard(const std::string& name) {
  if (name == "standard_4k") return from_spec(name, 3840, 2160, 0.7472, 30, 0, 200, 1000, 0, 250);
  if (name == "standard_fhd") return from_spec(name, 1920, 1080, 0.6, 24, 0, 200, 1000, 0, 250);
  if (name == "standard_hmd") return from_spec(name, 1440, 1600, 3, 0, 110.0, 100, 0, 0.1, 0);
  if (name == "htc_vive_pro") return from_spec(name, 1440, 1600, 3, 0, 110.0, 133.3, 0, 0.1, 0);
  throw Error(kWhere, "unknown standard display '" + name +
                          "' (standard_4k, standard_fhd, standard_hmd, htc_vive_pro)");
}

FvvdpDisplay FvvdpDisplay::from_display(const Display& disp) {
  const double dist = disp.viewing_distance_m > 0 ? disp.viewing_distance_m : 3.0;
  FvvdpDisplay d;
  if (disp.diagonal_inches > 0 || disp.fov_diagonal_deg > 0) {
    d = from_spec(disp.name, disp.width, disp.height, dist, disp.diagonal_inches,
                  disp.fov_diagonal_deg, disp.peak_luminance, disp.contrast, disp.black_luminance,
                  disp.ambient_lux, disp.reflectivity);
  } else {
    // Geometry from the FOV (a planar screen at distance d that subtends it).
    d = from_spec(disp.name, disp.width, disp.height, dist, 0, 90.0, disp.peak_luminance,
                  disp.contrast, disp.black_luminance, disp.ambient_lux, disp.reflectivity);
    d.w_m = 2.0 * dist * std::tan(disp.fov_h_deg * kPiD / 360.0);
    d.h_m = 2.0 * dist * std::tan(disp.fov_v_deg * kPiD / 360.0);
    d.ppd = ppd_of(d.w_m, d.width, d.d_m);
  }
  return d;
}

FvvdpDisplay FvvdpDisplay::scaled_to(int w, int h) const {
  FvvdpDisplay d = *this;
  d.width = w;
  d.height = h;
  d.ppd = ppd_of(w_m, w, d_m);
  return d;
}

std::string FvvdpDisplay::describe(bool foveated) const {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "FovVideoVDP v1.2, %.1f [pix/deg], Lpeak=%g, Lblack=%.4f [cd/m^2], %s, (%s)", ppd,
                y_peak, y_black, foveated ? "foveated" : "non-foveated", name.c_str());
  return buf;
}

// ---------------------------------------------------------------------------------------------
// Reference side.

struct FvvdpBandState {
  int w = 0, h = 0;
  double rho = 0;
  float gain = 1;
  std::vector<float> La, S[2], r[2];
  // Foveated: per-column / per-row view angles (§3.4) and the rho axis of each pixel (§8.1:
  // rho_b m(alpha), independent of the gaze).
  std::vector<double> vx, vy;
  std::vector<uint8_t> rho_lo, rho_hi;
  std::vector<float> rho_t;
  float Vy[2][kN];  // non-foveated: the table at (rho_b, e = 0) along the Y axis
};

struct FvvdpReferenceStream::Impl {
  FvvdpFrames frame;
  std::vector<FvvdpBandState> bands;
  std::vector<float> E, lap;
};

FvvdpReferenceStream::FvvdpReferenceStream(const FvvdpDisplay& display, int width, int height,
                                           FvvdpOptions opt)
    : disp_(display),
      opt_(opt),
      W_(width),
      H_(height),
      video_(opt.fps > 0),
      impl_(std::make_unique<Impl>()) {
  if (width < 4 || height < 4)
    throw Error(kWhere, "image " + std::to_string(width) + "x" + std::to_string(height) +
                            " is too small for FovVideoVDP (needs at least 4x4 pixels)");
  if (!(display.ppd > 0 && std::isfinite(display.ppd)))
    throw Error(kWhere, "display ppd must be finite and > 0");
  band_freq_ = fvvdp_detail::band_frequencies(height, width, display.ppd);
  if (video_) fvvdp_detail::temporal_taps(opt.fps, fs_, ft_);
  const int nb = int(band_freq_.size());
  impl_->frame.init(width, height, video_, int(fs_.size()), nb);
  const CsfTables& t = csf_tables();
  const AxisSteps st = axis_steps();
  impl_->bands.resize(size_t(nb));
  for (int b = 0; b < nb; ++b) {
    FvvdpBandState& B = impl_->bands[size_t(b)];
    B.w = impl_->frame.lv[size_t(b)].w;
    B.h = impl_->frame.lv[size_t(b)].h;
    B.rho = band_freq_[size_t(b)];
    B.gain = b == 0 ? 1.f : 2.f;  // §6.5 band gain [quirk]
    const size_t n = size_t(B.w) * size_t(B.h);
    B.La.resize(n);
    for (int c = 0; c < channels(); ++c) {
      B.S[c].resize(n);
      B.r[c].resize(n);
    }
    if (!opt_.foveated) {
      const Axis ar = rho_axis(t, st, float(B.rho)), ae = ecc_axis(t, st, 0.f);
      for (int w = 0; w < 2; ++w)
        for (int i = 0; i < kN; ++i) {
          const float r0 = lerp(t.at(w, i, ar.lo, ae.lo), t.at(w, i, ar.lo, ae.hi), ae.t);
          const float r1 = lerp(t.at(w, i, ar.hi, ae.lo), t.at(w, i, ar.hi, ae.hi), ae.t);
          B.Vy[w][i] = lerp(r0, r1, ar.t);
        }
    } else {
      // §3.4 [quirk, v1.2.1+]: every band is mapped onto the whole physical display.
      B.vx.resize(size_t(B.w));
      B.vy.resize(size_t(B.h));
      for (int i = 0; i < B.w; ++i)
        B.vx[size_t(i)] =
            std::atan(((i + 0.5) - B.w / 2.0) * disp_.w_m / B.w / disp_.d_m) * 180.0 / kPiD;
      for (int j = 0; j < B.h; ++j)
        B.vy[size_t(j)] =
            std::atan(-((j + 0.5) - B.h / 2.0) * disp_.h_m / B.h / disp_.d_m) * 180.0 / kPiD;
      B.rho_lo.resize(n);
      B.rho_hi.resize(n);
      B.rho_t.resize(n);
      const double delta = 1.0 / (2.0 * disp_.ppd);
      const double rad = kPiD / 180.0;
      for_rows(B.h, B.w, [&](int j) {
        for (int i = 0; i < B.w; ++i) {
          const double vx = B.vx[size_t(i)], vy = B.vy[size_t(j)];
          const double alpha = std::min(std::sqrt(vx * vx + vy * vy), 89.9);
          const double m =
              (std::tan((alpha + delta) * rad) - std::tan(alpha * rad)) / std::tan(delta * rad);
          const Axis ar = rho_axis(t, st, float(B.rho * m));
          const size_t k = size_t(j) * size_t(B.w) + size_t(i);
          B.rho_lo[k] = uint8_t(ar.lo);
          B.rho_hi[k] = uint8_t(ar.hi);
          B.rho_t[k] = ar.t;
        }
      });
    }
  }
}

FvvdpReferenceStream::~FvvdpReferenceStream() = default;
FvvdpReferenceStream::FvvdpReferenceStream(FvvdpReferenceStream&&) noexcept = default;
FvvdpReferenceStream& FvvdpReferenceStream::operator=(FvvdpReferenceStream&&) noexcept = default;

void FvvdpReferenceStream::reset() {
  frames_ = 0;
  impl_->frame.ring.reset();
}

const std::vector<float>& FvvdpReferenceStream::adaptation(int b) const {
  return impl_->bands.at(size_t(b)).La;
}
const std::vector<float>& FvvdpReferenceStream::sensitivity(int b, int c) const {
  return impl_->bands.at(size_t(b)).S[c];
}

void FvvdpReferenceStream::push(const Image& ref) {
  push(ref, std::floor(W_ / 2), std::floor(H_ / 2));
}

void FvvdpReferenceStream::push(const Image& ref, double gx, double gy) {
  if (ref.width != W_ || ref.height != H_ || (ref.channels != 1 && ref.channels < 3))
    throw Error(kWhere, "reference frame is " + std::to_string(ref.width) + "x" +
                            std::to_string(ref.height) + "x" + std::to_string(ref.channels) +
                            ", the stream expects " + std::to_string(W_) + "x" +
                            std::to_string(H_) + " RGB or grey");
  Impl& I = *impl_;
  I.frame.push(ref, disp_, fs_, ft_);
  const CsfTables& t = csf_tables();
  const AxisSteps st = axis_steps();
  const int nb = bands(), nc = channels();
  // Gaze direction (§3.4): frame coordinates, at the pixel centre.
  const double vgx = std::atan(((gx + 0.5) - W_ / 2.0) * disp_.w_m / W_ / disp_.d_m) * 180.0 / kPiD;
  const double vgy =
      std::atan(-((gy + 0.5) - H_ / 2.0) * disp_.h_m / H_ / disp_.d_m) * 180.0 / kPiD;
  for (int b = 0; b < nb; ++b) {
    FvvdpBandState& B = I.bands[size_t(b)];
    const Level& up = I.frame.lv[size_t(b) + 1];
    const size_t n = size_t(B.w) * size_t(B.h);
    I.E.resize(n);
    for (int c = 0; c < nc; ++c) {
      // E_b of this plane; for the sustained plane it is also the adaptation (§7).
      expand(I.frame.level(c, b + 1), up.w, up.h, B.w, B.h, I.E.data(), I.frame.tmp);
      const float* G = I.frame.level(c, b);
      if (c == 0) {
        for_rows(B.h, B.w, [&](int y) {
          const size_t o = size_t(y) * size_t(B.w);
          for (int x = 0; x < B.w; ++x) B.La[o + size_t(x)] = std::max(I.E[o + size_t(x)], 0.1f);
        });
      }
      for_rows(B.h, B.w, [&](int y) {
        const size_t o = size_t(y) * size_t(B.w);
        const float* La = B.La.data() + o;
        float* S = B.S[c].data() + o;
        float* r = B.r[c].data() + o;
        const double vy = opt_.foveated ? B.vy[size_t(y)] : 0.0;
        for (int x = 0; x < B.w; ++x) {
          const Axis ay = y_axis(t, st, La[x]);
          float v;
          if (!opt_.foveated) {
            v = lerp(B.Vy[c][ay.lo], B.Vy[c][ay.hi], ay.t);
          } else {
            const double dx = B.vx[size_t(x)] - vgx, dy = vy - vgy;
            const Axis ae = ecc_axis(t, st, float(std::sqrt(dx * dx + dy * dy)));
            const size_t k = o + size_t(x);
            const Axis ar{B.rho_lo[k], B.rho_hi[k], B.rho_t[k]};
            v = trilinear(t, c, ay, ar, ae);
          }
          S[x] = kSensCorr * std::exp2(v);
          const float lap = G[o + size_t(x)] - I.E[o + size_t(x)];
          r[x] = B.gain * std::min(lap / La[x], 1000.f) * S[x];
        }
      });
    }
  }
  ++frames_;
}

// ---------------------------------------------------------------------------------------------
// Test side.

struct FvvdpTestStream::Impl {
  FvvdpFrames frame;  // its own test frames (no planes while it scores with another stream's)
};

namespace {

// The working planes of one score (FvvdpTestStream::score), lent for the call from a pool
// (sim/core/scratch_pool.h): as many exist as scores ran at once, not one per stream.
struct ScoreScratch {
  std::vector<float> E, up, tmp;
  std::vector<float> dpow;  // D^beta of the band's pixels in row-major order (torch_cpu_sum)
  std::vector<std::vector<float>> Dmap;  // heat map: per-band D (sustained + 0.25 transient)
  std::vector<double> row_sum;
};

ScratchPool<ScoreScratch>& score_scratch() {
  static ScratchPool<ScoreScratch> pool;
  return pool;
}

// The heat map of a score (FvvdpTestStream::enable_heatmap): the per-band D maps collapsed from
// the coarsest scored band to the frame, then to JOD-like units.
void collapse_heat(ScoreScratch& I, const std::vector<Level>& lv, int nb, Image& heat) {
  std::vector<float> acc = I.Dmap[size_t(nb) - 1];
  for (int b = nb - 2; b >= 0; --b) {
    const Level &lo = lv[size_t(b) + 1], &hi = lv[size_t(b)];
    I.up.resize(size_t(hi.w) * size_t(hi.h));
    expand(acc.data(), lo.w, lo.h, hi.w, hi.h, I.up.data(), I.tmp);
    const std::vector<float>& d = I.Dmap[size_t(b)];
    for (size_t k = 0; k < I.up.size(); ++k) I.up[k] += d[k];
    acc.swap(I.up);
  }
  heat.resize(lv[0].w, lv[0].h, 1);
  const float a = float(-kJodA), bj = float(std::pow(10.0, kLogJodExp));
  for (size_t k = 0; k < acc.size(); ++k)
    heat.data[k] = acc[k] > 0.f ? a * std::pow(acc[k], bj) : 0.f;
}

// Whether frames pushed to `a` give the same luminance, temporal filtering and pyramids as to
// `b` (FvvdpTestStream::push with another stream's frames).
bool same_planes(const FvvdpReferenceStream& a, const FvvdpReferenceStream& b) {
  const FvvdpDisplay &da = a.display(), &db = b.display();
  return a.width() == b.width() && a.height() == b.height() && a.bands() == b.bands() &&
         a.channels() == b.channels() && da.y_peak == db.y_peak && da.y_black == db.y_black &&
         a.temporal_sustained() == b.temporal_sustained() &&
         a.temporal_transient() == b.temporal_transient();
}

}  // namespace

FvvdpTestStream::FvvdpTestStream(const FvvdpReferenceStream& ref)
    : impl_(std::make_unique<Impl>()) {
  impl_->frame.init(ref.width(), ref.height(), ref.video(), int(ref.temporal_sustained().size()),
                    ref.bands());
}
FvvdpTestStream::~FvvdpTestStream() = default;
FvvdpTestStream::FvvdpTestStream(FvvdpTestStream&&) noexcept = default;
FvvdpTestStream& FvvdpTestStream::operator=(FvvdpTestStream&&) noexcept = default;

void FvvdpTestStream::reset() {
  borrowed_ = false;
  q_tc_.clear();
  last_q_.clear();
  impl_->frame.ring.reset();
}

double FvvdpTestStream::push(const Image& test, const FvvdpReferenceStream& ref,
                             const FvvdpTestStream& same, const FvvdpReferenceStream& same_ref) {
  const bool ok = &same != this && !same.borrowed_ && same.frames() == frames() + 1 &&
                  same_ref.frames() == ref.frames() && same_planes(same_ref, ref);
  if (!ok) return push(test, ref);
  borrowed_ = true;
  return score(test, ref, &same.impl_->frame);
}

double FvvdpTestStream::push(const Image& test, const FvvdpReferenceStream& ref,
                             const FvvdpReferenceStream& frames_of) {
  const bool ok = frames_of.frames() == frames() + 1 && frames_of.frames() == ref.frames() &&
                  same_planes(frames_of, ref);
  if (!ok) return push(test, ref);
  borrowed_ = true;
  return score(test, ref, &frames_of.impl_->frame);
}

double FvvdpTestStream::push(const Image& test, const FvvdpReferenceStream& ref) {
  FOVSIM_CHECK(!borrowed_,
               "FvvdpTestStream: pushed on its own after scoring with another stream's frames "
               "(its history was not kept; reset() first)");
  return score(test, ref, nullptr);
}

double FvvdpTestStream::score(const Image& test, const FvvdpReferenceStream& ref,
                              const FvvdpFrames* shared) {
  if (test.width != ref.width() || test.height != ref.height() ||
      (test.channels != 1 && test.channels < 3))
    throw Error(kWhere, "test frame is " + std::to_string(test.width) + "x" +
                            std::to_string(test.height) + "x" + std::to_string(test.channels) +
                            ", the reference is " + std::to_string(ref.width()) + "x" +
                            std::to_string(ref.height()) + " RGB or grey");
  if (ref.frames() != frames() + 1)
    throw Error(kWhere, "test frame " + std::to_string(frames()) +
                            " pushed while the reference stream is at frame " +
                            std::to_string(ref.frames() - 1) + " (push the reference first)");
  Impl& own = *impl_;
  const FvvdpReferenceStream::Impl& R = *ref.impl_;
  if (!shared)
    own.frame.push(test, ref.display(), ref.temporal_sustained(), ref.temporal_transient());
  const Frame& F = shared ? *shared : own.frame;  // the test frame's planes and pyramids
  const ScratchPool<ScoreScratch>::Lease lease = score_scratch().take();
  ScoreScratch& I = *lease;
  const int nb = ref.bands(), nc = ref.channels();
  last_q_.assign(size_t(nb), {0.0, 0.0});
  const float kM = float(std::pow(10.0, kMaskC));
  const float p = float(kMaskP), beta = float(kBeta);
  if (heat_on_) I.Dmap.resize(size_t(nb));
  for (int b = 0; b < nb; ++b) {
    const FvvdpBandState& B = R.bands[size_t(b)];
    const Level& up = F.lv[size_t(b) + 1];
    const size_t n = size_t(B.w) * size_t(B.h);
    I.E.resize(n);
    I.row_sum.assign(size_t(B.h), 0.0);
    float* dmap = nullptr;
    if (heat_on_) {
      I.Dmap[size_t(b)].assign(n, 0.f);
      dmap = I.Dmap[size_t(b)].data();
    }
    // §10 (1) as the reference accumulates it (fvvdp_detail::torch_cpu_sum); a video's D has one
    // output per channel and frame, which torch reduces one at a time.
    const int tthreads =
        ref.options().torch_threads <= 0 ? 0 : (ref.video() ? 1 : ref.options().torch_threads);
    float* dpow = nullptr;
    if (tthreads > 0) {
      I.dpow.resize(n);
      dpow = I.dpow.data();
    }
    for (int c = 0; c < nc; ++c) {
      const float wc = c == 0 ? 1.f : float(kWTransient);
      expand(F.level(c, b + 1), up.w, up.h, B.w, B.h, I.E.data(), I.tmp);
      const float* G = F.level(c, b);
      const float q = float(kMaskQ[c]);
      for_rows(B.h, B.w, [&](int y) {
        const size_t o = size_t(y) * size_t(B.w);
        const float* La = B.La.data() + o;
        const float* S = B.S[c].data() + o;
        const float* r = B.r[c].data() + o;
        const float* g = G + o;
        const float* e = I.E.data() + o;
        double acc = 0;
        // The powers of a run of the row at once (powf_array: glibc's powf with fixed bits,
        // several lanes per instruction).
        constexpr int kRun = 64;
        float dv[kRun], Mv[kRun], Pd[kRun], PM[kRun];
        for (int x0 = 0; x0 < B.w; x0 += kRun) {
          const int m = std::min(kRun, B.w - x0);
          for (int j = 0; j < m; ++j) {
            const int x = x0 + j;
            const float lap = g[x] - e[x];
            const float tv = B.gain * std::min(lap / La[x], 1000.f) * S[x];  // §7, §9
            Mv[j] = kM * std::min(std::fabs(tv), std::fabs(r[x]));
            dv[j] = std::fabs(tv - r[x]);
          }
          powf_array(dv, p, Pd, m);
          powf_array(Mv, q, PM, m);
          for (int j = 0; j < m; ++j)  // D (0 where diff is not > 0), into dv
            dv[j] = dv[j] > 0.f ? std::min(Pd[j] / (1.f + PM[j]), 1e4f) : 0.f;
          powf_array(dv, beta, Pd, m);
          for (int j = 0; j < m; ++j) {
            const float D = dv[j];
            if (D > 0.f) acc += double(Pd[j]);  // §10 (1)
            if (dpow) dpow[o + size_t(x0 + j)] = D > 0.f ? Pd[j] : 0.f;
            if (dmap) dmap[o + size_t(x0 + j)] += wc * D;
          }
        }
        I.row_sum[size_t(y)] = acc;
      });
      double sum = 0;
      if (dpow) {
        sum = fvvdp_detail::torch_cpu_sum(dpow, n, tthreads);
      } else {
        for (double v : I.row_sum) sum += v;  // row order: same bits at any thread count
      }
      last_q_[size_t(b)][size_t(c)] = std::pow(sum / double(n), 1.0 / kBeta);
    }
  }
  if (heat_on_) collapse_heat(I, F.lv, nb, heat_);
  // §10 (2), (3).
  double qsc[2] = {0, 0};
  for (int b = 0; b < nb; ++b) {
    qsc[0] += last_q_[size_t(b)][0];
    qsc[1] += kWTransient * last_q_[size_t(b)][1];
  }
  const double qtc =
      nc == 1 ? qsc[0]
              : std::pow(std::pow(qsc[0], kBetaTch) + std::pow(qsc[1], kBetaTch), 1.0 / kBetaTch);
  q_tc_.push_back(qtc);
  return qtc;
}

double FvvdpTestStream::mean_q() const {
  if (q_tc_.empty()) return 0.0;
  double s = 0;
  for (double v : q_tc_) s += v;
  return s / double(q_tc_.size());
}

double FvvdpTestStream::jod() const {
  return fvvdp_jod_from_q(mean_q());
}

// ---------------------------------------------------------------------------------------------

FvvdpResult fvvdp(const std::vector<Image>& test, const std::vector<Image>& ref,
                  const FvvdpDisplay& display, double fps, bool foveated,
                  const std::vector<std::pair<double, double>>& gaze_px, int torch_threads) {
  if (test.size() != ref.size() || ref.empty())
    throw Error(kWhere, "test has " + std::to_string(test.size()) + " frames, reference " +
                            std::to_string(ref.size()) + " (need the same count, at least 1)");
  const size_t N = ref.size();
  if (N >= 2 && !(fps > 0 && std::isfinite(fps)))
    throw Error(kWhere, "a sequence of " + std::to_string(N) + " frames needs a frame rate > 0");
  if (!gaze_px.empty() && gaze_px.size() != 1 && gaze_px.size() != N)
    throw Error(kWhere, "gaze: give one point or one per frame (" + std::to_string(N) + ")");
  FvvdpOptions opt;
  opt.fps = N >= 2 ? fps : 0.0;
  opt.foveated = foveated;
  opt.torch_threads = torch_threads;
  const int W = ref[0].width, H = ref[0].height;
  FvvdpReferenceStream rs(display, W, H, opt);
  FvvdpTestStream ts(rs);
  FvvdpResult res;
  for (size_t n = 0; n < N; ++n) {
    if (gaze_px.empty()) {
      rs.push(ref[n]);
    } else {
      const auto& g = gaze_px[gaze_px.size() == 1 ? 0 : n];
      rs.push(ref[n], g.first, g.second);
    }
    ts.push(test[n], rs);
    res.q.push_back(ts.q_bands());
  }
  res.q_tc = ts.q_per_frame();
  res.mean_q = ts.mean_q();
  res.frames = int(N);
  res.bands = rs.bands();
  res.channels = rs.channels();
  res.band_freq = rs.band_frequencies();
  res.jod = ts.jod();
  res.display_line = display.describe(foveated);
  return res;
}

// ---- In a run: the registry's sequence-metric interface (sim/metrics/registry.h) ----

namespace {

FvvdpDisplay run_display(const SequenceSetup& s) {
  return FvvdpDisplay::from_display(*s.display).scaled_to(s.width, s.height);
}

class FvvdpRunReference final : public SequenceReference {
 public:
  explicit FvvdpRunReference(const SequenceSetup& s)
      : stream(run_display(s), s.width, s.height,
               FvvdpOptions{s.fps, s.config && s.config->fvvdp_foveated}) {}
  // The run's gaze is a screen point (pixel centres at i + 0.5), the metric's a pixel index.
  void push(const Image& ref, double gx, double gy) override {
    stream.push(ref, gx - 0.5, gy - 0.5);
  }
  void reset() override { stream.reset(); }
  FvvdpReferenceStream stream;
};

class FvvdpRunTest final : public SequenceTest {
 public:
  explicit FvvdpRunTest(const SequenceReference& r)
      : stream(static_cast<const FvvdpRunReference&>(r).stream) {}
  double push(const Image& test, const SequenceReference& r, Image* heat) override {
    return scored(heat, [&] { return stream.push(test, ref_of(r)); });
  }
  double push_same(const Image& test, const SequenceReference& r, Image* heat,
                   const SequenceTest& same, const SequenceReference& same_r) override {
    const auto* s = dynamic_cast<const FvvdpRunTest*>(&same);
    const auto* sr = dynamic_cast<const FvvdpRunReference*>(&same_r);
    if (!s || !sr) return push(test, r, heat);
    return scored(heat, [&] { return stream.push(test, ref_of(r), s->stream, sr->stream); });
  }
  double push_frames_of(const Image& test, const SequenceReference& r, Image* heat,
                        const SequenceReference& frames_of) override {
    const auto* f = dynamic_cast<const FvvdpRunReference*>(&frames_of);
    if (!f) return push(test, r, heat);
    return scored(heat, [&] { return stream.push(test, ref_of(r), f->stream); });
  }
  void reset() override { stream.reset(); }
  FvvdpTestStream stream;

 private:
  static const FvvdpReferenceStream& ref_of(const SequenceReference& r) {
    return static_cast<const FvvdpRunReference&>(r).stream;
  }
  // One push with the heat map on when `heat` is given: JOD-like units per pixel (0 = no
  // visible difference), colour ramp 0 .. 1.
  template <class Push>
  double scored(Image* heat, Push push) {
    stream.enable_heatmap(heat != nullptr);
    const double q = push();
    if (heat) *heat = heatmap(stream.heatmap(), 0.f, 1.f);
    stream.enable_heatmap(false);
    return q;
  }
};

}  // namespace

const SequenceMetric& fvvdp_sequence_metric() {
  static const SequenceMetric m = [] {
    SequenceMetric x;
    x.enabled = [](const MetricsConfig& c) { return c.fvvdp; };
    x.make_reference = [](const SequenceSetup& s) -> std::unique_ptr<SequenceReference> {
      return std::make_unique<FvvdpRunReference>(s);
    };
    x.make_test = [](const SequenceReference& r) -> std::unique_ptr<SequenceTest> {
      return std::make_unique<FvvdpRunTest>(r);
    };
    x.describe = [](const SequenceSetup& s) {
      const bool fov = s.config && s.config->fvvdp_foveated;
      return Json{{"foveated", fov}, {"display", run_display(s).describe(fov)}};
    };
    // Frame: luminance, the temporal window of L = ceil(fps / 4) frames (§5.2) and the two
    // filtered planes with their Gaussian pyramids (4/3 of a plane each); the reference adds
    // per band La, S and r per channel and (foveated) the rho axis; both an E and a Laplacian /
    // upsampled plane. Plane = W x H floats.
    x.reference_bytes = [](const SequenceSetup& s) {
      const double n = double(s.width) * double(s.height), plane = 4 * n;
      const bool video = s.fps > 0;
      const double c = video ? 2 : 1;
      const double L = video ? fvvdp_detail::filter_length(s.fps) : 0;
      const double frame = plane * ((video ? L + 2 : 1) + c / 3);
      const double bands = plane * (1 + 2 * c) * 4 / 3;
      const double rho = s.config && s.config->fvvdp_foveated ? 6 * n * 4 / 3 : 0;
      return frame + bands + rho + 2 * plane;
    };
    // Frame: the temporal window of L frames and the two filtered planes (video) or the
    // luminance (image), with the Gaussian pyramids (1/3 of a plane each).
    x.test_bytes = [](const SequenceSetup& s) {
      const double plane = 4 * double(s.width) * double(s.height);
      const bool video = s.fps > 0;
      const double c = video ? 2 : 1;
      const double L = video ? fvvdp_detail::filter_length(s.fps) : 0;
      return plane * ((video ? L + 2 : 1) + c / 3);
    };
    // A score's E, D^beta and expand planes (ScoreScratch).
    x.scratch_bytes = [](const SequenceSetup& s) {
      return 4 * double(s.width) * double(s.height) * 2.5;
    };
    x.borrowing_holds_nothing = true;
    x.manifest_key = "fvvdp";
    x.settle_frames = [](double fps) { return fvvdp_detail::settle_frames(fps); };
    x.heatmap_suffix = "_fvvdp";
    return x;
  }();
  return m;
}

}  // namespace fovsim
