// The one display encoding (sim/render/tonemap.h) against the formulas it replaces.
#include "sim/render/tonemap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>
#if defined(__x86_64__)
#include <xmmintrin.h>
#endif

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

// ToneMap::apply runs the curve 4 or 8 floats at a time (tonemap.cpp): on every width this
// CPU has, bit for bit what
// display_encode gives per value, for every curve, over a dense sweep of magnitudes, the sRGB
// threshold's neighbourhood, denormals, huge values, negatives, infinities and NaN, and a
// length that leaves a scalar tail.
TEST(ToneMapEncode, VectorApplyIsBitIdenticalToThePerValueCurve) {
  // Run after rendering tests in this binary, TBB workers may carry FTZ/DAZ while this thread
  // does not: the curve is built so that the mode does not matter (kToneMapBlack).
  std::vector<float> v;
  for (uint32_t b = 0; b < 0x7f800000u; b += 4099u) {  // every exponent, spread mantissas
    float f;
    std::memcpy(&f, &b, 4);
    v.push_back(f);
    v.push_back(-f);
  }
  for (int i = -2000; i <= 2000; ++i) v.push_back(0.0031308f + float(i) * 1e-9f);
  for (int i = 0; i <= 100000; ++i) v.push_back(float(i) / 50000.f);  // [0, 2]
  const float inf = std::numeric_limits<float>::infinity();
  for (float f : {inf, -inf, std::numeric_limits<float>::quiet_NaN(), 1e9f, 1e10f, 1.f,
                  std::nextafter(1.f, 0.f), std::numeric_limits<float>::denorm_min(), 0.f, -0.f})
    v.push_back(f);
  while (v.size() % 3) v.push_back(0.5f);
  v.push_back(0.25f);  // odd length, not a multiple of 8: the tail runs the scalar curve
  v.push_back(0.75f);
  v.push_back(0.125f);
  Image lin(int(v.size() / 3), 1, 3), out;
  lin.data = v;
  std::vector<int> widths;  // every lane width this CPU has (4 always)
  for (int w : {4, 8}) {
    set_tonemap_lane_width(w);
    if (tonemap_lane_width() == w) widths.push_back(w);
  }
  ASSERT_FALSE(widths.empty());
  ASSERT_EQ(widths[0], 4);
  for (int w : widths)
    for (ToneCurve c : {ToneCurve::Aces, ToneCurve::Reinhard, ToneCurve::Clamp})
      for (double ex : {1.0, 0.37}) {
        set_tonemap_lane_width(w);
        ToneMap tm;
        tm.curve = c;
        tm.exposure = ex;
        tm.apply(lin, out);
        ASSERT_EQ(out.data.size(), v.size());
        size_t bad = 0;
        for (size_t i = 0; i < v.size(); ++i) {
          const float x = v[i] * float(ex);  // (this thread: IEEE, denormals kept)
          const float want = c == ToneCurve::Aces       ? display_encode<ToneCurve::Aces>(x)
                             : c == ToneCurve::Reinhard ? display_encode<ToneCurve::Reinhard>(x)
                                                        : display_encode<ToneCurve::Clamp>(x);
          uint32_t a, b;
          std::memcpy(&a, &out.data[i], 4);
          std::memcpy(&b, &want, 4);
          if (a != b && ++bad <= 5)
            ADD_FAILURE() << "width " << w << " curve " << int(c) << " exposure " << ex << " x "
                          << v[i] << ": " << out.data[i] << " vs " << want;
        }
        EXPECT_EQ(bad, 0u);
      }
  set_tonemap_lane_width(0);
}

TEST(ToneMapEncode, TinyAndDenormalInputsAreBlackWhateverTheFpMode) {
  const float den = std::numeric_limits<float>::denorm_min() * 1000.f;
  for (float x : {den, 1e-38f, 1e-31f, kToneMapBlack})
    EXPECT_EQ(display_encode<ToneCurve::Aces>(x), 0.f) << x;
  EXPECT_GT(display_encode<ToneCurve::Aces>(1e-29f), 0.f);
#if defined(__SSE__) || defined(__x86_64__)
  const unsigned csr = _mm_getcsr();
  _mm_setcsr(csr | 0x8040u);  // FTZ | DAZ on this thread, as on a worker after Embree work
  const float a = display_encode<ToneCurve::Aces>(den), b = display_encode<ToneCurve::Aces>(1e-29f);
  _mm_setcsr(csr);
  EXPECT_EQ(a, 0.f);
  EXPECT_EQ(b, display_encode<ToneCurve::Aces>(1e-29f));
#endif
}

}  // namespace
}  // namespace fovsim
