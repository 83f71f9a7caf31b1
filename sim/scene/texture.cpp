// Procedural and image textures, point-sampled or band-limited over a footprint
// (docs/architecture.md §4: the reference is converged and every method shades with the same
// filtering).
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
#include <algorithm>
#include <cmath>

#include "sim/scene/scene.h"

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
          att[j] = a < 1e-4f ? 1.f : std::sin(a) / a;
        }
      float sum = 0.f;
      for (int o = 0; o < 4; ++o) {
        float co = ca * c45[o] - sa * s45[o], so = sa * c45[o] + ca * s45[o];
        float x = two_pi_f * (co * uv.x + so * uv.y);
        float s1 = std::sin(x), c1 = std::cos(x);
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

}  // namespace fovsim
