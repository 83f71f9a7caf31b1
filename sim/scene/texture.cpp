// Procedural and image textures, point-sampled or band-limited over a footprint
// (docs/architecture.md "Rendering and the shared reference": the reference is converged and every
// method shades with the same filtering).
//
// Filtering model: a sample's footprint is an isotropic box of width `fw` in uv units (the
// renderer derives it from a ray cone, sim/render/render_trace.cpp). Each texture is
// averaged over that box, analytically where the pattern allows it:
//   checker, stripes  exact box filter of the square wave per axis (integral = triangle wave);
//                     the box is taken axis-aligned in the pattern's rotated frame
//   grating           each sinusoid octave attenuated by the box's transfer function sinc
//   bricks            exact box filter of the mortar pulse trains per axis, brick tint
//                     faded to its mean once the footprint covers a brick
//   noise             each fBm octave faded to the noise mean (0.5) between half and one
//                     lattice cell per footprint (band limiting)
//   radial            square waves of rings and spokes box-filtered at their local frequency
//   image             mip pyramid (2x2 box) built at load, trilinear between the two levels
//                     around log2(fw * max(width, height))
// fw <= kPointFw evaluates the unfiltered pattern, bit for bit the former point sampling.
// eval_albedo_packet (texture_packet.h) evaluates a renderer packet's lookups together, a
// material's lanes at a time, with eval_albedo's operations; the grating's sines and cosines
// come from sincos_det / sincos_packet (below), not libm.
#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "sim/core/lane_choice.h"
#include "sim/scene/texture_packet.h"

namespace fovsim {

namespace {

constexpr float kPointFw = 1e-6f;

inline float fractf(float x) {
  return x - std::floor(x);
}

// {cos, sin} of the grating's per-orientation phase 0.7 * o.
constexpr float kGratingPhase[4][2] = {{1.f, 0.f},
                                       {0.76484219f, 0.64421769f},
                                       {0.16996714f, 0.98544973f},
                                       {-0.50484610f, 0.86320937f}};

inline uint32_t hash2(int32_t x, int32_t y) {
  uint32_t h = uint32_t(x) * 0x8da6b343u ^ uint32_t(y) * 0xd8163841u;
  h ^= h >> 13;
  h *= 0x85ebca6bu;
  h ^= h >> 16;
  return h;
}

inline float value_noise(glm::vec2 p) {
  float fx = std::floor(p.x), fy = std::floor(p.y);
  int32_t ix = int32_t(fx), iy = int32_t(fy);
  float tx = p.x - fx, ty = p.y - fy;
  tx = tx * tx * (3.f - 2.f * tx);
  ty = ty * ty * (3.f - 2.f * ty);
  const float k = 1.f / 4294967295.f;
  float a = float(hash2(ix, iy)) * k, b = float(hash2(ix + 1, iy)) * k;
  float c = float(hash2(ix, iy + 1)) * k, d = float(hash2(ix + 1, iy + 1)) * k;
  return (a + (b - a) * tx) * (1.f - ty) + (c + (d - c) * tx) * ty;
}

// Integral from 0 to x of the square wave s (+1 on [0, 1), -1 on [1, 2), period 2): a
// triangle wave in [0, 1]. Computed in double: x may be hundreds of periods from 0.
inline double square_integral(double x) {
  const double f = x - 2.0 * std::floor(0.5 * x);
  return 1.0 - std::fabs(1.0 - f);
}

}  // namespace

// ---- deterministic sinf / cosf, packet-wide -----------------------------------------------------
// The algorithm of glibc's sinf / cosf / sincosf (sysdeps/ieee754/flt-32, from Arm's
// optimized-routines: Szabolcs Nagy 2018): the argument is reduced by pi/2 in double (a product
// with 2/pi for |x| < 120, a 4/pi bit table beyond), then a degree-8 even and a degree-7 odd
// polynomial in double, rounded to float once. Written here with the same coefficients and the
// same IEEE double operations in the same order (the portable build has no FMA), so each lane
// gives the bits of glibc's non-FMA (SSE2) variant on every CPU and ISA path; glibc's own
// FMA variants, which the native libm picks at run time, can differ from it in the last bit.
// The polynomials run two lanes at a time (SSE2 doubles); the reduction is per lane.
namespace {

typedef double vd2 __attribute__((vector_size(16)));

// sign[4], then per table the cos coefficients c0..c4 and the sin coefficients s1..s3. The
// second table (quadrants with n & 2) negates every c: its cosine polynomial is exactly the
// negation of the first's, so it is computed as that (IEEE negation and round-to-nearest are
// symmetric).
constexpr double kHpiInv = 0x1.45f306dc9c883p+23;  // 2/pi * 2^24
constexpr double kHpi = 0x1.921fb54442d18p+0;      // pi/2
constexpr double kPi63 = 0x1.921fb54442d18p-62;    // pi/2 * 2^-62 (glibc: pi63)
constexpr double kC0 = 0x1p0, kC1 = -0x1.ffffffd0c621cp-2, kC2 = 0x1.55553e1068f19p-5,
                 kC3 = -0x1.6c087e89a359dp-10, kC4 = 0x1.99343027bf8c3p-16;
constexpr double kS1 = -0x1.555545995a603p-3, kS2 = 0x1.1107605230bc4p-7,
                 kS3 = -0x1.994eb3774cf24p-13;
constexpr double kSign[4] = {1.0, -1.0, -1.0, 1.0};
// 4/pi in 32-bit windows 8 bits apart (glibc's __inv_pio4).
constexpr uint32_t kInvPio4[24] = {
    0xa2,       0xa2f9,     0xa2f983,   0xa2f9836e, 0xf9836e4e, 0x836e4e44, 0x6e4e4415, 0x4e441529,
    0x441529fc, 0x1529fc27, 0x29fc2757, 0xfc2757d1, 0x2757d1f5, 0x57d1f534, 0xd1f534dd, 0xf534ddc0,
    0x34ddc0db, 0xddc0db62, 0xc0db6295, 0xdb629599, 0x6295993c, 0x95993c43, 0x993c4390, 0x3c439041};

inline uint32_t asuint(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}
inline uint32_t abstop12(float x) {
  return (asuint(x) >> 20) & 0x7ff;
}

// One lane's reduction: the polynomial argument xs (sign applied), x2, whether sin and cos
// swap (n & 1) and whether the cosine polynomial is negated (the second table). Returns false
// for the lanes the polynomial does not compute: |y| < 2^-12 (sin = y, cos = 1) and inf / NaN.
inline bool reduce(float y, double& xs, double& x2, bool& swap, bool& cneg) {
  const double x = y;
  const uint32_t t = abstop12(y);
  if (t < abstop12(0x1.921fb6p-1f)) {  // |y| < pi/4 (glibc's test on the top 12 bits)
    xs = x;
    x2 = x * x;
    swap = cneg = false;
    return !(t < abstop12(0x1p-12f));
  }
  if (t < abstop12(120.f)) {
    const double r = x * kHpiInv;
    const int n = (int32_t(r) + 0x800000) >> 24;
    const double xr = x - n * kHpi;
    xs = xr * kSign[n & 3];
    x2 = xr * xr;
    swap = (n & 1) != 0;
    cneg = (n & 2) != 0;
    return true;
  }
  if (t < abstop12(std::numeric_limits<float>::infinity())) {
    uint32_t xi = asuint(y);
    const int sign = int(xi >> 31);
    const uint32_t* arr = &kInvPio4[(xi >> 26) & 15];
    const int shift = (xi >> 23) & 7;
    xi = (xi & 0xffffff) | 0x800000;
    xi <<= shift;
    uint64_t res0 = xi * arr[0];
    const uint64_t res1 = uint64_t(xi) * arr[4];
    const uint64_t res2 = uint64_t(xi) * arr[8];
    res0 = (res2 >> 32) | (res0 << 32);
    res0 += res1;
    const uint64_t n = (res0 + (1ull << 61)) >> 62;
    res0 -= n << 62;
    const double xr = double(int64_t(res0)) * kPi63;
    const int ns = int(n) + sign;
    xs = xr * kSign[ns & 3];
    x2 = xr * xr;
    swap = (n & 1) != 0;
    cneg = (ns & 2) != 0;
    return true;
  }
  return false;
}

inline vd2 vsplat(double v) {
  return vd2{v, v};
}

}  // namespace

void sincos_packet(const float* y, int n, float* s, float* c) {
  constexpr int B = 64;
  alignas(16) double xs[B], x2[B];
  bool swap[B], cneg[B], poly[B];
  for (int i0 = 0; i0 < n; i0 += B) {
    const int m = std::min(B, n - i0);
    for (int k = 0; k < m; ++k) {
      poly[k] = reduce(y[i0 + k], xs[k], x2[k], swap[k], cneg[k]);
      if (!poly[k]) xs[k] = x2[k] = 0.0;
    }
    if (m & 1) xs[m] = x2[m] = 0.0;
    for (int k = 0; k < m; k += 2) {
      vd2 x, xx;
      std::memcpy(&x, xs + k, sizeof x);
      std::memcpy(&xx, x2 + k, sizeof xx);
      // glibc's sincosf_poly, operation for operation.
      const vd2 x4 = xx * xx, x3 = xx * x;
      const vd2 c2 = vsplat(kC3) + xx * vsplat(kC4);
      const vd2 s1 = vsplat(kS2) + xx * vsplat(kS3);
      const vd2 c1 = vsplat(kC0) + xx * vsplat(kC1);
      const vd2 x5 = x3 * xx, x6 = x4 * xx;
      const vd2 sv = x + x3 * vsplat(kS1);
      const vd2 cv = c1 + x4 * vsplat(kC2);
      const vd2 so = sv + x5 * s1, co = cv + x6 * c2;
      for (int j = 0; j < 2 && k + j < m; ++j) {
        const int i = i0 + k + j;
        if (!poly[k + j]) {
          const float v = y[i];
          const bool tiny = abstop12(v) < abstop12(0x1p-12f);
          s[i] = tiny ? v : (v - v) / (v - v);
          c[i] = tiny ? 1.f : (v - v) / (v - v);
          continue;
        }
        const double cc = cneg[k + j] ? -co[j] : co[j];
        s[i] = float(swap[k + j] ? cc : so[j]);
        c[i] = float(swap[k + j] ? so[j] : cc);
      }
    }
  }
}

// One value (eval_albedo's per-sample path): the same reduction and polynomial, in scalars.
void sincos_det(float y, float& s, float& c) {
  double xs, x2;
  bool swap, cneg;
  if (!reduce(y, xs, x2, swap, cneg)) {
    const bool tiny = abstop12(y) < abstop12(0x1p-12f);
    s = tiny ? y : (y - y) / (y - y);
    c = tiny ? 1.f : (y - y) / (y - y);
    return;
  }
  const double x4 = x2 * x2, x3 = x2 * xs;
  const double c2 = kC3 + x2 * kC4;
  const double s1 = kS2 + x2 * kS3;
  const double c1 = kC0 + x2 * kC1;
  const double x5 = x3 * x2, x6 = x4 * x2;
  const double sv = xs + x3 * kS1;
  const double cv = c1 + x4 * kC2;
  const double so = sv + x5 * s1, co = cv + x6 * c2;
  const double cc = cneg ? -co : co;
  s = float(swap ? cc : so);
  c = float(swap ? so : cc);
}

float box_square(float x, float w) {
  if (!(w > kPointFw)) return (int32_t(std::floor(x)) & 1) ? -1.f : 1.f;
  const double h = 0.5 * double(w);
  return float((square_integral(double(x) + h) - square_integral(double(x) - h)) / double(w));
}

float box_pulse(float x, float w, float a) {
  if (!(w > kPointFw)) return fractf(x) < a ? 1.f : 0.f;
  // Integral of the pulse train (1 on [k, k + a)): floor(x) a + min(fract(x), a).
  auto P = [a](double t) {
    const double f = std::floor(t);
    return f * a + std::min(t - f, double(a));
  };
  const double h = 0.5 * double(w);
  return float(std::clamp((P(double(x) + h) - P(double(x) - h)) / double(w), 0.0, 1.0));
}

// ---- image textures --------------------------------------------------------------------------

void TextureImage::build_mips() {
  mips.clear();
  int w = width, h = height;
  const std::vector<glm::vec3>* src = &texels;
  while (w > 1 || h > 1) {
    MipLevel L;
    L.width = std::max(1, w / 2);
    L.height = std::max(1, h / 2);
    L.texels.resize(size_t(L.width) * size_t(L.height));
    for (int y = 0; y < L.height; ++y)
      for (int x = 0; x < L.width; ++x) {
        // 2x2 box (a trailing odd row/column is dropped, as a GPU's floor-sized chain does).
        const int x0 = std::min(2 * x, w - 1), x1 = std::min(2 * x + 1, w - 1);
        const int y0 = std::min(2 * y, h - 1), y1 = std::min(2 * y + 1, h - 1);
        auto T = [&](int xi, int yi) { return (*src)[size_t(yi) * size_t(w) + size_t(xi)]; };
        L.texels[size_t(y) * size_t(L.width) + size_t(x)] =
            0.25f * (T(x0, y0) + T(x1, y0) + T(x0, y1) + T(x1, y1));
      }
    mips.push_back(std::move(L));
    w = mips.back().width;
    h = mips.back().height;
    src = &mips.back().texels;
  }
}

namespace {

glm::vec3 bilinear(const std::vector<glm::vec3>& tex, int width, int height, glm::vec2 uv) {
  // Bilinear with wrap (glTF default sampler is REPEAT); v grows downwards in the image.
  float x = fractf(uv.x) * float(width) - 0.5f;
  float y = fractf(uv.y) * float(height) - 0.5f;
  float fx = std::floor(x), fy = std::floor(y);
  float tx = x - fx, ty = y - fy;
  auto wrap = [](int i, int n) { return ((i % n) + n) % n; };
  int x0 = wrap(int(fx), width), x1 = wrap(int(fx) + 1, width);
  int y0 = wrap(int(fy), height), y1 = wrap(int(fy) + 1, height);
  auto T = [&](int xi, int yi) { return tex[size_t(yi) * size_t(width) + size_t(xi)]; };
  return glm::mix(glm::mix(T(x0, y0), T(x1, y0), tx), glm::mix(T(x0, y1), T(x1, y1), tx), ty);
}

}  // namespace

float mip_level(const TextureImage& img, float fw) {
  if (!(fw > kPointFw) || img.mips.empty()) return 0.f;
  const float texels = fw * float(std::max(img.width, img.height));
  return std::clamp(std::log2(std::max(texels, 1e-30f)), 0.f, float(img.mips.size()));
}

glm::vec3 sample_image(const TextureImage& img, glm::vec2 uv, float fw) {
  if (img.width <= 0 || img.height <= 0 || img.texels.empty()) return glm::vec3(1.f);
  const float lvl = mip_level(img, fw);
  auto level = [&](int k) {
    if (k == 0) return bilinear(img.texels, img.width, img.height, uv);
    const MipLevel& L = img.mips[size_t(k - 1)];
    return bilinear(L.texels, L.width, L.height, uv);
  };
  const int k0 = int(std::floor(lvl));
  const float t = lvl - float(k0);
  if (t <= 0.f || k0 >= int(img.mips.size())) return level(k0);
  return glm::mix(level(k0), level(k0 + 1), t);
}

float material_alpha(const Scene& scene, const Material& m, glm::vec2 uv) {
  float a = m.alpha;
  if (m.image >= 0 && size_t(m.image) < scene.images.size()) {
    const TextureImage& img = scene.images[size_t(m.image)];
    if (!img.alpha.empty() && img.width > 0 && img.height > 0) {
      // Bilinear on the alpha channel (same wrap and orientation as the colour lookup).
      float x = fractf(uv.x) * float(img.width) - 0.5f, y = fractf(uv.y) * float(img.height) - 0.5f;
      float fx = std::floor(x), fy = std::floor(y), tx = x - fx, ty = y - fy;
      auto wrap = [](int i, int n) { return ((i % n) + n) % n; };
      int x0 = wrap(int(fx), img.width), x1 = wrap(int(fx) + 1, img.width);
      int y0 = wrap(int(fy), img.height), y1 = wrap(int(fy) + 1, img.height);
      auto A = [&](int xi, int yi) {
        return img.alpha[size_t(yi) * size_t(img.width) + size_t(xi)];
      };
      a *= (A(x0, y0) * (1 - tx) + A(x1, y0) * tx) * (1 - ty) +
           (A(x0, y1) * (1 - tx) + A(x1, y1) * tx) * ty;
    }
  }
  return a;
}

// ---- evaluation --------------------------------------------------------------------------------

glm::vec3 eval_albedo(const Scene& scene, const Material& m, glm::vec2 uv) {
  return eval_albedo(scene, m, uv, std::cos(m.angle), std::sin(m.angle), 0.f);
}

glm::vec3 eval_albedo(const Scene& scene, const Material& m, glm::vec2 uv, float ca, float sa,
                      float fw) {
  auto rot = [ca, sa](glm::vec2 p) { return glm::vec2(ca * p.x - sa * p.y, sa * p.x + ca * p.y); };
  const bool point = !(fw > kPointFw);
  const float w = fw * m.scale;  // footprint in pattern cells
  switch (m.tex) {
    case TexKind::Constant:
      return m.base_color;
    case TexKind::Checker: {
      glm::vec2 p = rot(uv) * m.scale;
      if (point) {
        int32_t c = int32_t(std::floor(p.x)) + int32_t(std::floor(p.y));
        return (c & 1) ? m.color2 : m.base_color;
      }
      // Cell parity = product of two square waves (+1 on even cells).
      const float s = box_square(p.x, w) * box_square(p.y, w);
      return glm::mix(m.color2, m.base_color, 0.5f + 0.5f * s);
    }
    case TexKind::Stripes: {
      glm::vec2 p = rot(uv) * m.scale;
      if (point) return fractf(p.x) < 0.5f ? m.base_color : m.color2;
      return glm::mix(m.color2, m.base_color, 0.5f + 0.5f * box_square(2.f * p.x, 2.f * w));
    }
    case TexKind::Grating: {
      // Sinusoids at 3 octaves (f, 2f, 4f) x 4 orientations 45 deg apart, each orientation
      // with its own phase: detail at many orientations and frequencies. One sincos per
      // orientation; the octaves follow from double-angle identities.
      const float k = 0.70710678f;  // cos 45 = sin 45
      const float c45[4] = {1.f, k, 0.f, -k}, s45[4] = {0.f, k, 1.f, k};
      const float two_pi_f = float(2.0 * kPi) * m.scale;
      // Box transfer function per octave: sinc(pi f fw) (1 for a point sample).
      float att[3] = {1.f, 1.f, 1.f};
      if (!point)
        for (int j = 0; j < 3; ++j) {
          const float a = float(kPi) * w * float(1 << j);
          float sa_, ca_;
          sincos_det(a, sa_, ca_);
          att[j] = a < 1e-4f ? 1.f : sa_ / a;
        }
      float sum = 0.f;
      for (int o = 0; o < 4; ++o) {
        float co = ca * c45[o] - sa * s45[o], so = sa * c45[o] + ca * s45[o];
        float x = two_pi_f * (co * uv.x + so * uv.y);
        float s1, c1;
        sincos_det(x, s1, c1);
        float s2 = 2.f * s1 * c1, c2 = 1.f - 2.f * s1 * s1;
        float s4 = 2.f * s2 * c2, c4 = 1.f - 2.f * s2 * s2;
        // sin(2^j x + ph_o), j = 0..2, phases ph_o = 0.7 o.
        if (point)
          sum += (s1 + s2 + s4) * kGratingPhase[o][0] + (c1 + c2 + c4) * kGratingPhase[o][1];
        else
          sum += (att[0] * s1 + att[1] * s2 + att[2] * s4) * kGratingPhase[o][0] +
                 (att[0] * c1 + att[1] * c2 + att[2] * c4) * kGratingPhase[o][1];
      }
      float wt = clamp01(0.5f + 0.5f * sum / 4.f);
      return glm::mix(m.color2, m.base_color, wt);
    }
    case TexKind::Bricks: {
      glm::vec2 p = rot(uv) * m.scale;
      p.x *= 0.5f;  // bricks twice as long as high
      float row = std::floor(p.y);
      if (int32_t(row) & 1) p.x += 0.5f;
      const float mortar = 0.06f;
      // Per-brick tint variation (deterministic hash) adds low-frequency detail.
      float v = float(hash2(int32_t(std::floor(p.x)), int32_t(row)) & 0xffff) / 65535.f;
      if (point) {
        float bx = fractf(p.x), by = fractf(p.y);
        if (bx < mortar * 0.5f || by < mortar) return m.color2;
        return m.base_color * (0.8f + 0.4f * v);
      }
      const float wx = 0.5f * w, wy = w;
      const float brick =
          (1.f - box_pulse(p.x, wx, mortar * 0.5f)) * (1.f - box_pulse(p.y, wy, mortar));
      const float tint = glm::mix(0.8f + 0.4f * v, 1.f, clamp01(std::max(wx, wy)));  // mean 1
      return glm::mix(m.color2, m.base_color * tint, brick);
    }
    case TexKind::Noise: {
      glm::vec2 p = rot(uv) * m.scale;
      float n = 0.f, amp = 0.5f, wk = w;
      for (int k = 0; k < 4; ++k, amp *= 0.5f, p *= 2.03f, wk *= 2.03f) {
        // Octave k kept below half a lattice cell per footprint, gone from one cell on.
        const float keep = point ? 1.f : clamp01(2.f - 2.f * wk);
        if (keep >= 1.f)
          n += amp * value_noise(p);
        else if (keep > 0.f)
          n += amp * (0.5f + keep * (value_noise(p) - 0.5f));
        else
          n += amp * 0.5f;
      }
      return glm::mix(m.color2, m.base_color, clamp01((n - 0.2f) / 0.6f));
    }
    case TexKind::Radial: {
      // Spokes (angular frequency) x rings (radial frequency) about uv (0.5, 0.5).
      glm::vec2 d = uv - glm::vec2(0.5f);
      float r = glm::length(d);
      float th = std::atan2(d.y, d.x) - m.angle;
      const float n_spokes = std::round(m.scale * 4.f);
      if (point) {
        float spokes = std::sin(th * n_spokes);
        float rings = std::sin(float(2.0 * kPi) * m.scale * r);
        return (spokes * rings >= 0.f) ? m.base_color : m.color2;
      }
      // sign(sin(2 pi f r)) = s(2 f r); sign(sin(n th)) = s(n th / pi); the box's width in th
      // is fw / r (arc length).
      const float rings = box_square(2.f * m.scale * r, 2.f * w);
      const float spokes =
          box_square(th * n_spokes / float(kPi), n_spokes * fw / (float(kPi) * std::max(r, 1e-6f)));
      return glm::mix(m.color2, m.base_color, 0.5f + 0.5f * spokes * rings);
    }
    case TexKind::Image: {
      if (m.image < 0 || size_t(m.image) >= scene.images.size()) return m.base_color;
      return m.base_color * sample_image(scene.images[size_t(m.image)], uv, fw);
    }
  }
  return m.base_color;
}

// ---- packet-wide evaluation ------------------------------------------------------------------

namespace {

typedef int64_t vl2 __attribute__((vector_size(16)));

// std::floor on two doubles with SSE2 operations, exact: below 2^52 in magnitude the value is
// rounded to an integer by adding and subtracting 2^52 (round to nearest, sign restored), then
// lowered by one where that rounded up; from 2^52 on (and inf) every double is an integer. NaN
// stays NaN; -0 stays -0.
inline vd2 vfloor(vd2 t) {
  const vl2 sign = vl2{INT64_MIN, INT64_MIN};
  const vd2 big = vsplat(0x1p52);
  const vd2 a = (vd2)((vl2)t & ~sign);  // |t|
  vd2 r = (a + big) - big;
  r = (vd2)((vl2)r | ((vl2)t & sign));  // sign of t
  r = r > t ? r - vsplat(1.0) : r;
  return a >= big ? t : r;
}
inline vd2 vfabs(vd2 t) {
  return (vd2)((vl2)t & ~vl2{INT64_MIN, INT64_MIN});
}
// square_integral, two lanes.
inline vd2 vsquare_integral(vd2 x) {
  const vd2 f = x - vsplat(2.0) * vfloor(vsplat(0.5) * x);
  return vsplat(1.0) - vfabs(vsplat(1.0) - f);
}

// box_square(x[k], w[k]) for k < n, two lanes at a time (the same double operations).
void box_square_sse2(const float* x, const float* w, int n, float* out) {
  for (int k = 0; k < n; k += 2) {
    const int k1 = k + 1 < n ? k + 1 : k;
    const vd2 xd = {double(x[k]), double(x[k1])}, wd = {double(w[k]), double(w[k1])};
    const vd2 h = vsplat(0.5) * wd;
    const vd2 r = (vsquare_integral(xd + h) - vsquare_integral(xd - h)) / wd;
    for (int j = 0; j < 2 && k + j < n; ++j) {
      const float wj = w[k + j];
      out[k + j] = (wj > kPointFw) ? float(r[j]) : box_square(x[k + j], wj);
    }
  }
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define FOVSIM_TEX_AVX2 1
// box_square_sse2 four lanes at a time (AVX2; fp-contract=off: no FMA), branch-free: the
// filtered value in double and the point value (box_square's !(w > kPointFw) branch: the
// parity of int32_t(floor(x)), truncation giving INT32_MIN out of range as the scalar
// conversion does) in float, then the lane's choice. The same operations per lane.
__attribute__((target("avx2"), optimize("fp-contract=off"))) void box_square_avx2(const float* x,
                                                                                  const float* w,
                                                                                  int n,
                                                                                  float* out) {
  auto body = [](__m128 xf, __m128 wf) {
    const __m256d xd = _mm256_cvtps_pd(xf), wd = _mm256_cvtps_pd(wf);
    const __m256d h = _mm256_mul_pd(_mm256_set1_pd(0.5), wd);
    const __m256d one = _mm256_set1_pd(1.0), two = _mm256_set1_pd(2.0);
    const __m256d half = _mm256_set1_pd(0.5), sign = _mm256_set1_pd(-0.0);
    auto sq = [&](__m256d t) {  // square_integral
      const __m256d f = _mm256_sub_pd(
          t, _mm256_mul_pd(two, _mm256_round_pd(_mm256_mul_pd(half, t),
                                                _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)));
      return _mm256_sub_pd(one, _mm256_andnot_pd(sign, _mm256_sub_pd(one, f)));
    };
    const __m256d r =
        _mm256_div_pd(_mm256_sub_pd(sq(_mm256_add_pd(xd, h)), sq(_mm256_sub_pd(xd, h))), wd);
    const __m128i odd =
        _mm_and_si128(_mm_cvttps_epi32(_mm_round_ps(xf, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)),
                      _mm_set1_epi32(1));
    const __m128 point = _mm_blendv_ps(_mm_set1_ps(1.f), _mm_set1_ps(-1.f),
                                       _mm_castsi128_ps(_mm_cmpeq_epi32(odd, _mm_set1_epi32(1))));
    return _mm_blendv_ps(point, _mm256_cvtpd_ps(r), _mm_cmpgt_ps(wf, _mm_set1_ps(kPointFw)));
  };
  int k = 0;
  for (; k + 4 <= n; k += 4) _mm_storeu_ps(out + k, body(_mm_loadu_ps(x + k), _mm_loadu_ps(w + k)));
  if (k < n) {
    alignas(16) float xb[4] = {0.f, 0.f, 0.f, 0.f}, wb[4] = {1.f, 1.f, 1.f, 1.f}, ob[4];
    for (int j = 0; k + j < n; ++j) {
      xb[j] = x[k + j];
      wb[j] = w[k + j];
    }
    _mm_store_ps(ob, body(_mm_load_ps(xb), _mm_load_ps(wb)));
    for (int j = 0; k + j < n; ++j) out[k + j] = ob[j];
  }
}
#else
#define FOVSIM_TEX_AVX2 0
#endif

// 2 (SSE2) or 4 (AVX2, also on AVX-512F CPUs) doubles per instruction of the box filters
// (sim/core/lane_choice.h).
LaneChoice g_box_lanes{2, FOVSIM_TEX_AVX2 ? 4 : 2, FOVSIM_TEX_AVX2 ? 4 : 2};

void box_square_packet(const float* x, const float* w, int n, float* out) {
#if FOVSIM_TEX_AVX2
  if (texture_lane_width() == 4) return box_square_avx2(x, w, n, out);
#endif
  box_square_sse2(x, w, n, out);
}

// box_pulse(x[k], w[k], a) for k < n, two lanes at a time (the same double operations).
void box_pulse_packet(const float* x, const float* w, float a, int n, float* out) {
  const vd2 ad = vsplat(double(a));
  auto P = [ad](vd2 t) {  // floor(t) a + min(t - floor(t), a)
    const vd2 f = vfloor(t), d = t - f;
    return f * ad + (ad < d ? ad : d);
  };
  for (int k = 0; k < n; k += 2) {
    const int k1 = k + 1 < n ? k + 1 : k;
    const vd2 xd = {double(x[k]), double(x[k1])}, wd = {double(w[k]), double(w[k1])};
    const vd2 h = vsplat(0.5) * wd;
    vd2 r = (P(xd + h) - P(xd - h)) / wd;
    r = r < vsplat(0.0) ? vsplat(0.0) : (vsplat(1.0) < r ? vsplat(1.0) : r);  // std::clamp
    for (int j = 0; j < 2 && k + j < n; ++j) {
      const float wj = w[k + j];
      out[k + j] = (wj > kPointFw) ? float(r[j]) : box_pulse(x[k + j], wj, a);
    }
  }
}

}  // namespace

int texture_lane_width() {
  return g_box_lanes.width();
}

void set_texture_lane_width(int w) {
  g_box_lanes.force(w);
}

// Long because: it is one switch over the texture kinds, each case the packet-wide form of
// eval_albedo's case (same IEEE operations per lane, so the same bits); keeping the cases side
// by side keeps each next to the per-sample code it must match.
void eval_albedo_packet(const Scene& scene, const glm::vec2* mat_cs, const TexSample* q, int n,
                        glm::vec3* out) {
  constexpr int B = 16;
  for (int b0 = 0; b0 < n; b0 += B) {
    const int nb = std::min(B, n - b0);
    bool done[B] = {};
    for (int k0 = 0; k0 < nb; ++k0) {
      if (done[k0]) continue;
      // The lanes of this block with k0's material (in lane order).
      const int mat = q[b0 + k0].mat;
      int lane[B], L = 0;
      for (int k = k0; k < nb; ++k)
        if (!done[k] && q[b0 + k].mat == mat) {
          done[k] = true;
          lane[L++] = b0 + k;
        }
      const Material& m = scene.materials[size_t(mat)];
      const float ca = mat_cs[size_t(mat)].x, sa = mat_cs[size_t(mat)].y;
      auto rot = [ca, sa](glm::vec2 p) {
        return glm::vec2(ca * p.x - sa * p.y, sa * p.x + ca * p.y);
      };
      switch (m.tex) {
        case TexKind::Checker: {
          // eval_albedo's filtered checker: box_square of both pattern axes; point samples
          // (w <= kPointFw) take box_square's point branch, then the scalar path below.
          float x[2 * B], w[2 * B], s[2 * B];
          for (int j = 0; j < L; ++j) {
            const glm::vec2 p = rot(q[lane[j]].uv) * m.scale;
            x[2 * j] = p.x;
            x[2 * j + 1] = p.y;
            w[2 * j] = w[2 * j + 1] = q[lane[j]].fw * m.scale;
          }
          box_square_packet(x, w, 2 * L, s);
          for (int j = 0; j < L; ++j) {
            const TexSample& t = q[lane[j]];
            out[lane[j]] = !(t.fw > kPointFw) ? eval_albedo(scene, m, t.uv, ca, sa, t.fw)
                                              : glm::mix(m.color2, m.base_color,
                                                         0.5f + 0.5f * (s[2 * j] * s[2 * j + 1]));
          }
          break;
        }
        case TexKind::Stripes: {
          float x[B], w[B], s[B];
          for (int j = 0; j < L; ++j) {
            const glm::vec2 p = rot(q[lane[j]].uv) * m.scale;
            x[j] = 2.f * p.x;
            w[j] = 2.f * (q[lane[j]].fw * m.scale);
          }
          box_square_packet(x, w, L, s);
          for (int j = 0; j < L; ++j) {
            const TexSample& t = q[lane[j]];
            out[lane[j]] = !(t.fw > kPointFw)
                               ? eval_albedo(scene, m, t.uv, ca, sa, t.fw)
                               : glm::mix(m.color2, m.base_color, 0.5f + 0.5f * s[j]);
          }
          break;
        }
        case TexKind::Grating: {
          // eval_albedo's grating with its 4 sincos per lane and 3 sines of the octaves' box
          // transfer functions evaluated for the lanes together (sincos_packet).
          const float k = 0.70710678f;
          const float c45[4] = {1.f, k, 0.f, -k}, s45[4] = {0.f, k, 1.f, k};
          const float two_pi_f = float(2.0 * kPi) * m.scale;
          float co[4], so[4];
          for (int o = 0; o < 4; ++o) {
            co[o] = ca * c45[o] - sa * s45[o];
            so[o] = sa * c45[o] + ca * s45[o];
          }
          float X[4 * B], S[4 * B], C[4 * B], A[3 * B], SA[3 * B], CA[3 * B];
          for (int j = 0; j < L; ++j) {
            const TexSample& t = q[lane[j]];
            const float w = t.fw * m.scale;
            for (int o = 0; o < 4; ++o) X[4 * j + o] = two_pi_f * (co[o] * t.uv.x + so[o] * t.uv.y);
            for (int i = 0; i < 3; ++i) A[3 * j + i] = float(kPi) * w * float(1 << i);
          }
          sincos_packet(X, 4 * L, S, C);
          sincos_packet(A, 3 * L, SA, CA);
          for (int j = 0; j < L; ++j) {
            const TexSample& t = q[lane[j]];
            if (!(t.fw > kPointFw)) {
              out[lane[j]] = eval_albedo(scene, m, t.uv, ca, sa, t.fw);
              continue;
            }
            float att[3];
            for (int i = 0; i < 3; ++i) {
              const float a = A[3 * j + i];
              att[i] = a < 1e-4f ? 1.f : SA[3 * j + i] / a;
            }
            float sum = 0.f;
            for (int o = 0; o < 4; ++o) {
              const float s1 = S[4 * j + o], c1 = C[4 * j + o];
              const float s2 = 2.f * s1 * c1, c2 = 1.f - 2.f * s1 * s1;
              const float s4 = 2.f * s2 * c2, c4 = 1.f - 2.f * s2 * s2;
              sum += (att[0] * s1 + att[1] * s2 + att[2] * s4) * kGratingPhase[o][0] +
                     (att[0] * c1 + att[1] * c2 + att[2] * c4) * kGratingPhase[o][1];
            }
            const float wt = clamp01(0.5f + 0.5f * sum / 4.f);
            out[lane[j]] = glm::mix(m.color2, m.base_color, wt);
          }
          break;
        }
        case TexKind::Bricks: {
          // eval_albedo's filtered bricks: the mortar pulse trains of both axes two lanes at a
          // time; tint and mix per lane.
          const float mortar = 0.06f;
          float px[B], py[B], wx[B], wy[B], v[B], bx[B], by[B];
          for (int j = 0; j < L; ++j) {
            const TexSample& t = q[lane[j]];
            glm::vec2 p = rot(t.uv) * m.scale;
            p.x *= 0.5f;
            const float row = std::floor(p.y);
            if (int32_t(row) & 1) p.x += 0.5f;
            v[j] = float(hash2(int32_t(std::floor(p.x)), int32_t(row)) & 0xffff) / 65535.f;
            px[j] = p.x;
            py[j] = p.y;
            const float w = t.fw * m.scale;
            wx[j] = 0.5f * w;
            wy[j] = w;
          }
          box_pulse_packet(px, wx, mortar * 0.5f, L, bx);
          box_pulse_packet(py, wy, mortar, L, by);
          for (int j = 0; j < L; ++j) {
            const TexSample& t = q[lane[j]];
            if (!(t.fw > kPointFw)) {
              out[lane[j]] = eval_albedo(scene, m, t.uv, ca, sa, t.fw);
              continue;
            }
            const float brick = (1.f - bx[j]) * (1.f - by[j]);
            const float tint =
                glm::mix(0.8f + 0.4f * v[j], 1.f, clamp01(std::max(wx[j], wy[j])));  // mean 1
            out[lane[j]] = glm::mix(m.color2, m.base_color * tint, brick);
          }
          break;
        }
        default:
          for (int j = 0; j < L; ++j) {
            const TexSample& t = q[lane[j]];
            out[lane[j]] = eval_albedo(scene, m, t.uv, ca, sa, t.fw);
          }
      }
    }
  }
}

}  // namespace fovsim
