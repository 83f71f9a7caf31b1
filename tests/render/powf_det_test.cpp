// The shading's specular power (sim/core/powf_det.h): glibc's powf algorithm in fovsim's own
// non-FMA operations. Exact where the result is exact, within one ulp of libm elsewhere, and
// the inputs off its main path handed back to std::pow.
#include "sim/core/powf_det.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "sim/core/powf_lanes.h"

using namespace fovsim;

TEST(PowfDet, ExactValuesAndLibmWithinOneUlp) {
  float r = -1.f;
  ASSERT_TRUE(powf_det(0.5f, 2.f, r));
  EXPECT_EQ(r, 0.25f);
  ASSERT_TRUE(powf_det(1.f, 90.f, r));
  EXPECT_EQ(r, 1.f);
  ASSERT_TRUE(powf_det(0.5f, 200.f, r));  // 2^-200: underflows to +0 as glibc's powf
  EXPECT_EQ(r, 0.f);
  auto ulps = [](float a, float b) {
    int32_t ia, ib;
    std::memcpy(&ia, &a, sizeof a);
    std::memcpy(&ib, &b, sizeof b);
    return std::abs(int64_t(ia) - int64_t(ib));
  };
  for (float y : {1.5f, 8.f, 15.f, 48.f, 60.f, 90.f, 128.f})
    for (uint32_t u = 0x00800000u; u <= 0x3f800000u; u += 4099u) {
      float x;
      std::memcpy(&x, &u, sizeof x);
      ASSERT_TRUE(powf_det(x, y, r)) << x << " " << y;
      ASSERT_LE(ulps(r, std::pow(x, y)), 1) << x << " " << y;
      ASSERT_EQ(spec_pow(x, y), r);
    }
}

TEST(PowfDet, OffTheMainPathGoesToLibm) {
  float r;
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_FALSE(powf_det(0.f, 15.f, r));
  EXPECT_FALSE(powf_det(-0.5f, 2.f, r));
  EXPECT_FALSE(powf_det(1e-40f, 2.f, r));  // subnormal
  EXPECT_FALSE(powf_det(0.5f, 0.f, r));
  EXPECT_FALSE(powf_det(0.5f, inf, r));
  EXPECT_FALSE(powf_det(std::nanf(""), 2.f, r));
  EXPECT_EQ(spec_pow(0.f, 15.f), 0.f);
  EXPECT_EQ(spec_pow(0.5f, 0.f), 1.f);
}

// powf_array (sim/core/powf_lanes.h) on every lane width this CPU has: value for value
// spec_pow's bits, over positive normals of every binade, the inputs off the main path (zero,
// negative, subnormal, inf, nan: std::pow), results that overflow or underflow, exponents of
// FovVideoVDP's masking (p, q, beta) and others, and array lengths that are not a multiple of
// any width (partial blocks).
TEST(PowfLanes, EveryWidthGivesSpecPowBits) {
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> xs = {0.f, -0.f, 1.f,    -1.f,  1e-40f, -1e-40f, inf, -inf,    std::nanf(""),
                           2.f, 0.5f, 1e-38f, 3e38f, 1e30f,  1e-30f,  7.f, 123.456f};
  for (uint32_t u = 0x00800000u; u < 0x7f800000u; u += 65537u) {
    float x;
    std::memcpy(&x, &u, sizeof x);
    xs.push_back(x);
  }
  auto same = [](float a, float b) {  // bit for bit (nan: any nan)
    if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
    uint32_t ia, ib;
    std::memcpy(&ia, &a, sizeof a);
    std::memcpy(&ib, &b, sizeof b);
    return ia == ib;
  };
  std::vector<int> widths = {2};
  for (int w : {4, 8}) {
    set_powf_lane_width(w);
    if (powf_lane_width() == w) widths.push_back(w);
  }
  ASSERT_FALSE(widths.empty());
  for (int w : widths) {
    set_powf_lane_width(w);
    for (float y : {2.4f, 0.3f, 2.2f, 3.f, 0.5f, 1.f, 15.f, 128.f, 1e-3f, -1.5f, 0.f, inf})
      for (int n : {int(xs.size()), 1, 7, 63, 65}) {
        std::vector<float> out(size_t(n), -7.f);
        powf_array(xs.data(), y, out.data(), n);
        for (int k = 0; k < n; ++k)
          ASSERT_TRUE(same(out[size_t(k)], spec_pow(xs[size_t(k)], y)))
              << "width " << w << " x " << xs[size_t(k)] << " y " << y << ": " << out[size_t(k)]
              << " vs " << spec_pow(xs[size_t(k)], y);
      }
  }
  set_powf_lane_width(0);
  std::vector<float> a = {0.25f, 4.f, 0.f};  // in place
  powf_array(a.data(), 0.5f, a.data(), 3);
  EXPECT_EQ(a[0], 0.5f);
  EXPECT_EQ(a[1], 2.f);
  EXPECT_EQ(a[2], 0.f);
}
