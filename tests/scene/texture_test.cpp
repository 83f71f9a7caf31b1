// Filtered textures (sim/scene/texture.cpp): box filters against numeric integrals, large
// footprints -> mean albedo, point sampling unchanged, mip level selection.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/scene/scene.h"

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
