// The one display encoding (sim/render/tonemap.h) against the formulas it replaces.
#include "sim/render/tonemap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace fovsim {
namespace {

// The former per-value encoding (std::pow, exact formulas) as reference.
double srgb_exact(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}
double aces_exact(double x) {
  return std::clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

TEST(ToneMapEncode, SrgbWithinDocumentedBoundOfPow) {
  double worst = 0;
  for (int i = 0; i <= 2000000; ++i) {
    const float y = float(i) / 2000000.f;
    worst = std::max(worst, std::fabs(double(srgb_encode(y)) - srgb_exact(y)));
  }
  EXPECT_LE(worst, 1e-6);  // documented bound 1e-5 (tonemap.h)
  EXPECT_EQ(srgb_encode(1.f), 1.f);
  EXPECT_EQ(srgb_encode(0.f), 0.f);
  EXPECT_EQ(srgb_encode(2.f), 1.f);
  EXPECT_EQ(srgb_encode(-1.f), 0.f);
  EXPECT_EQ(srgb_encode(std::numeric_limits<float>::quiet_NaN()), 0.f);
}

TEST(ToneMapEncode, CurvesMatchFormulasAndEdgeValues) {
  double worst = 0;
  for (int i = 0; i <= 200000; ++i) {
    const float x = float(i) / 10000.f;  // [0, 20]
    worst = std::max(
        worst, std::fabs(double(display_encode<ToneCurve::Aces>(x)) - srgb_exact(aces_exact(x))));
    worst = std::max(worst, std::fabs(double(display_encode<ToneCurve::Reinhard>(x)) -
                                      srgb_exact(double(x) / (1.0 + x))));
  }
  EXPECT_LE(worst, 1e-5);
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(display_encode<ToneCurve::Aces>(inf), 1.f);
  EXPECT_EQ(display_encode<ToneCurve::Reinhard>(inf), 1.f);
  EXPECT_EQ(display_encode<ToneCurve::Clamp>(inf), 1.f);
  EXPECT_EQ(display_encode<ToneCurve::Aces>(-inf), 0.f);
  EXPECT_EQ(display_encode<ToneCurve::Aces>(std::numeric_limits<float>::quiet_NaN()), 0.f);
}

TEST(ToneMapEncode, ApplyUsesTheSameCurve) {
  Image lin(4, 1, 3), out;
  for (size_t i = 0; i < lin.data.size(); ++i) lin.data[i] = float(i) * 0.3f;
  ToneMap tm;
  tm.exposure = 1.5;
  tm.apply(lin, out);
  for (size_t i = 0; i < lin.data.size(); ++i)
    EXPECT_EQ(out.data[i], display_encode<ToneCurve::Aces>(lin.data[i] * 1.5f));
}

}  // namespace
}  // namespace fovsim
