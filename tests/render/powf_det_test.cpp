// The shading's specular power (sim/render/powf_det.h): glibc's powf algorithm in fovsim's own
// non-FMA operations. Exact where the result is exact, within one ulp of libm elsewhere, and
// the inputs off its main path handed back to std::pow.
#include "sim/render/powf_det.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

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
