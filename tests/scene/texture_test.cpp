// Filtered textures (sim/scene/texture.cpp): box filters against numeric integrals, large
// footprints -> mean albedo, point sampling unchanged, mip level selection.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "sim/scene/texture_packet.h"

using namespace fovsim;

namespace {

// Numeric box average of f over [x - w/2, x + w/2] (midpoint rule, many samples).
template <class F>
double numeric_box(F f, double x, double w, int n = 20000) {
  double s = 0;
  for (int i = 0; i < n; ++i) s += f(x - 0.5 * w + (i + 0.5) * w / n);
  return s / n;
}

Material material(TexKind k, float scale = 4.f) {
  Material m;
  m.tex = k;
  m.scale = scale;
  m.base_color = glm::vec3(0.9f, 0.6f, 0.3f);
  m.color2 = glm::vec3(0.1f, 0.2f, 0.3f);
  return m;
}

}  // namespace

TEST(Texture, BoxSquareAndPulseMatchNumericIntegrals) {
  auto sq = [](double x) { return (int64_t(std::floor(x)) & 1) ? -1.0 : 1.0; };
  for (double x : {0.1, 0.9, 3.3, -2.7, 101.49})
    for (double w : {0.05, 0.5, 1.0, 1.7, 4.2}) {
      EXPECT_NEAR(box_square(float(x), float(w)), numeric_box(sq, x, w), 2e-4) << x << " " << w;
      auto pulse = [](double t) { return (t - std::floor(t)) < 0.06 ? 1.0 : 0.0; };
      EXPECT_NEAR(box_pulse(float(x), float(w), 0.06f), numeric_box(pulse, x, w), 2e-4);
    }
  EXPECT_EQ(box_square(0.5f, 0.f), 1.f);
  EXPECT_EQ(box_square(1.5f, 0.f), -1.f);
}

// A footprint covering many cells averages to the pattern's mean albedo.
TEST(Texture, LargeFootprintGivesMeanAlbedo) {
  Scene s;
  const glm::vec3 mean_bc = 0.5f * (glm::vec3(0.9f, 0.6f, 0.3f) + glm::vec3(0.1f, 0.2f, 0.3f));
  for (TexKind k : {TexKind::Checker, TexKind::Stripes, TexKind::Grating}) {
    Material m = material(k);
    for (glm::vec2 uv : {glm::vec2(0.13f, 0.71f), glm::vec2(5.4f, -2.2f)}) {
      glm::vec3 a = eval_albedo(s, m, uv, 1.f, 0.f, 50.f);  // 200 cells per footprint
      EXPECT_NEAR(a.x, mean_bc.x, 5e-3) << int(k);
      EXPECT_NEAR(a.y, mean_bc.y, 5e-3) << int(k);
      EXPECT_NEAR(a.z, mean_bc.z, 5e-3) << int(k);
    }
  }
  // Noise: every octave faded to its mean -> the colour at noise value 0.5.
  Material m = material(TexKind::Noise);
  glm::vec3 a = eval_albedo(s, m, {0.3f, 0.4f}, 1.f, 0.f, 50.f);
  const float wn = (0.5f * (0.5f + 0.25f + 0.125f + 0.0625f) - 0.2f) / 0.6f;
  glm::vec3 e = glm::mix(m.color2, m.base_color, wn);
  EXPECT_NEAR(a.x, e.x, 1e-5);
}

// Filtered checker over a footprint = numeric average of the point-sampled checker.
TEST(Texture, FilteredCheckerEqualsNumericAverage) {
  Scene s;
  Material m = material(TexKind::Checker, 1.f);
  const float fw = 0.37f;
  const glm::vec2 c(0.61f, 2.2f);
  glm::dvec3 sum(0.0);
  const int n = 400;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      glm::vec2 uv = c + fw * glm::vec2((i + 0.5f) / n - 0.5f, (j + 0.5f) / n - 0.5f);
      sum += glm::dvec3(eval_albedo(s, m, uv, 1.f, 0.f, 0.f));
    }
  sum /= double(n) * n;
  glm::vec3 f = eval_albedo(s, m, c, 1.f, 0.f, fw);
  EXPECT_NEAR(f.x, sum.x, 2e-3);
  EXPECT_NEAR(f.z, sum.z, 2e-3);
}

TEST(Texture, PointFootprintIsTheUnfilteredPattern) {
  Scene s;
  for (TexKind k : {TexKind::Checker, TexKind::Stripes, TexKind::Grating, TexKind::Bricks,
                    TexKind::Noise, TexKind::Radial}) {
    Material m = material(k);
    for (glm::vec2 uv : {glm::vec2(0.13f, 0.71f), glm::vec2(5.4f, -2.2f)}) {
      glm::vec3 a = eval_albedo(s, m, uv), b = eval_albedo(s, m, uv, 1.f, 0.f, 0.f);
      EXPECT_EQ(a, b) << int(k);
      // A tiny footprint stays close to the point sample away from edges (continuity).
      glm::vec3 t = eval_albedo(s, m, uv, 1.f, 0.f, 1e-5f);
      EXPECT_NEAR(t.x, a.x, 0.05) << int(k);
    }
  }
}

TEST(Texture, MipLevelSelectionAndTopLevelMean) {
  TextureImage img;
  img.width = img.height = 64;
  img.texels.resize(64 * 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      img.texels[size_t(y * 64 + x)] = ((x + y) & 1) ? glm::vec3(1.f) : glm::vec3(0.f);
  img.build_mips();
  ASSERT_EQ(img.mips.size(), 6u);  // 32, 16, 8, 4, 2, 1
  EXPECT_EQ(img.mips.back().width, 1);
  EXPECT_FLOAT_EQ(img.mips.back().texels[0].x, 0.5f);
  EXPECT_FLOAT_EQ(mip_level(img, 0.f), 0.f);
  EXPECT_FLOAT_EQ(mip_level(img, 1.f / 64.f), 0.f);  // one texel per footprint
  EXPECT_FLOAT_EQ(mip_level(img, 4.f / 64.f), 2.f);
  EXPECT_NEAR(mip_level(img, 3.f / 64.f), std::log2(3.f), 1e-6);
  EXPECT_FLOAT_EQ(mip_level(img, 100.f), 6.f);  // clamped to the 1x1 level
  // Level 0 point lookup at a texel centre is the texel; a wide footprint is the mean.
  EXPECT_FLOAT_EQ(sample_image(img, {0.5f / 64.f, 0.5f / 64.f}).x, 0.f);
  EXPECT_NEAR(sample_image(img, {0.3f, 0.7f}, 2.f / 64.f).x, 0.5f, 1e-6);  // level 1: 2x2 mean
  EXPECT_NEAR(sample_image(img, {0.3f, 0.7f}, 100.f).x, 0.5f, 1e-6);
}

// The packet-wide lookup gives eval_albedo's bits lane for lane, for every procedural kind,
// with materials mixed inside a packet, filtered and point footprints, far-away uvs (the sines'
// large-argument reduction; point parities out of int32 range) and packets that are not a
// multiple of 16, on both widths of the box filters.
TEST(Texture, PacketEqualsPerSampleBits) {
  Scene s;
  const TexKind kinds[] = {TexKind::Constant, TexKind::Checker, TexKind::Stripes, TexKind::Grating,
                           TexKind::Bricks,   TexKind::Noise,   TexKind::Radial};
  for (TexKind k : kinds) {
    for (float scale : {4.f, 23.f}) {
      Material m = material(k, scale);
      m.angle = 0.3f * float(s.materials.size());
      s.materials.push_back(m);
    }
  }
  std::vector<glm::vec2> cs;
  for (const Material& m : s.materials) cs.emplace_back(std::cos(m.angle), std::sin(m.angle));
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> U(-3.f, 3.f), F(0.f, 0.05f);
  std::uniform_int_distribution<int> M(0, int(s.materials.size()) - 1);
  std::vector<TexSample> q(1000);
  for (size_t i = 0; i < q.size(); ++i) {
    q[i].uv = glm::vec2(U(rng), U(rng)) * (i % 5 == 0 ? 300.f : 1.f);
    q[i].mat = i % 3 == 0 ? M(rng) : int(i / 16) % int(s.materials.size());  // runs and mixes
    q[i].fw = i % 7 == 0 ? 0.f : F(rng);
  }
  q[1].uv = glm::vec2(3e9f, -3e9f);  // the point parity out of int32 range
  q[1].fw = 0.f;
  q[2].uv = glm::vec2(3e9f, 1e20f);
  for (int width : {2, 4}) {  // the box filters' SSE2 and (where the CPU has it) AVX2 paths
    set_texture_lane_width(width);
    std::vector<glm::vec3> out(q.size());
    for (size_t i0 = 0; i0 < q.size(); i0 += 13)
      eval_albedo_packet(s, cs.data(), &q[i0], int(std::min<size_t>(13, q.size() - i0)), &out[i0]);
    for (size_t i = 0; i < q.size(); ++i) {
      const Material& m = s.materials[size_t(q[i].mat)];
      const glm::vec3 e =
          eval_albedo(s, m, q[i].uv, cs[size_t(q[i].mat)].x, cs[size_t(q[i].mat)].y, q[i].fw);
      ASSERT_EQ(std::memcmp(&e, &out[i], sizeof e), 0)
          << "width " << texture_lane_width() << " sample " << i << " kind " << int(m.tex) << " fw "
          << q[i].fw;
    }
  }
  set_texture_lane_width(0);
}

// sincos_packet: the same bits as sincos_det, within one ulp of libm everywhere (glibc's
// algorithm; the last bit can differ from libm's FMA variants), glibc's special cases.
TEST(Texture, DeterministicSinCos) {
  std::vector<float> x;
  for (uint32_t u = 0; u < 0xff800000u; u += 0x10001u) {  // every exponent, both signs
    float f;
    std::memcpy(&f, &u, sizeof f);
    x.push_back(f);
  }
  std::vector<float> s(x.size()), c(x.size());
  sincos_packet(x.data(), int(x.size()), s.data(), c.data());
  auto ulp_diff = [](float a, float b) {
    int32_t ia, ib;
    std::memcpy(&ia, &a, sizeof a);
    std::memcpy(&ib, &b, sizeof b);
    if (ia < 0) ia = INT32_MIN - ia;
    if (ib < 0) ib = INT32_MIN - ib;
    return std::abs(int64_t(ia) - int64_t(ib));
  };
  for (size_t i = 0; i < x.size(); ++i) {
    float s1, c1;
    sincos_det(x[i], s1, c1);
    ASSERT_EQ(std::memcmp(&s1, &s[i], sizeof s1), 0) << x[i];
    ASSERT_EQ(std::memcmp(&c1, &c[i], sizeof c1), 0) << x[i];
    if (!std::isfinite(x[i])) {
      ASSERT_TRUE(std::isnan(s[i]) && std::isnan(c[i])) << x[i];
      continue;
    }
    ASSERT_LE(ulp_diff(s[i], std::sin(x[i])), 1) << x[i];
    ASSERT_LE(ulp_diff(c[i], std::cos(x[i])), 1) << x[i];
  }
  float sv, cv;
  sincos_det(0x1p-13f, sv, cv);
  EXPECT_EQ(sv, 0x1p-13f);
  EXPECT_EQ(cv, 1.f);
  sincos_det(std::numeric_limits<float>::infinity(), sv, cv);
  EXPECT_TRUE(std::isnan(sv) && std::isnan(cv));
  sincos_det(std::numeric_limits<float>::quiet_NaN(), sv, cv);
  EXPECT_TRUE(std::isnan(sv) && std::isnan(cv));
}
