#include <gtest/gtest.h>

#include <cmath>

#include "metrics_test_util.h"
#include "sim/core/error.h"
#include "sim/metrics/metrics.h"

using namespace fovsim;

TEST(MetricsPsnr, ConstantOffsetHasKnownValue) {
  Image a = testutil::pattern(40, 30, 3, 1, 0.0);
  for (float& v : a.data) v = 0.2f + 0.5f * v;  // stay in range after the offset
  Image b = a;
  for (float& v : b.data) v += 0.1f;
  EXPECT_NEAR(mse(a, b), 0.01, 1e-8);
  EXPECT_NEAR(psnr(a, b), 20.0, 1e-5);  // 10 log10(1 / 0.1^2)
  // Offset in one channel only: MSE is the mean over channels.
  Image c = a;
  for (size_t i = 0; i < c.pixels(); ++i) c.data[3 * i + 1] += 0.3f;
  EXPECT_NEAR(mse(a, c), 0.09 / 3, 1e-7);
  EXPECT_NEAR(psnr(a, c), 10 * std::log10(3 / 0.09), 1e-5);
}

TEST(MetricsPsnr, IdenticalImagesArePlusInfinity) {
  Image a = testutil::pattern(16, 16, 3, 2);
  EXPECT_EQ(mse(a, a), 0.0);
  EXPECT_TRUE(std::isinf(psnr(a, a)));
  EXPECT_GT(psnr(a, a), 0);
}

TEST(MetricsPsnr, SizeMismatchThrowsWithLocation) {
  Image a(10, 10, 3), b(10, 11, 3), c(10, 10, 1);
  try {
    psnr(a, b);
    FAIL() << "no throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.where(), "metrics.psnr");
    EXPECT_NE(std::string(e.what()).find("10x10x3 vs 10x11x3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(mse(a, c), Error);
  EXPECT_THROW(mse(Image(), Image()), Error);
}
