// Tone mapping and display encoding (docs/architecture.md "Rendering and the shared reference":
// metrics are computed on display-encoded values, as the papers do). ONE implementation, used by
// ToneMap::apply and by every method that needs display values itself (TWFR's contrast confidence,
// Franke et al. 2021 §5.2).
//
// The curve is branch-free float arithmetic (selects, no table, no libm call); ToneMap::apply
// runs the same operations 4 lanes at a time (tonemap.cpp: GCC does not vectorise this scalar
// form by itself), bit-identical to display_encode. sRGB's x^(1/2.4) is exp2(log2(x) / 2.4) with
// polynomial log2/exp2 (Chebyshev fits: |log2 error| < 3.1e-8 on the mantissa, exp2 relative error
// < 2.6e-9). Against the former std::pow encoding the largest difference over every float in [0, 1]
// is below 1e-6 (tests/render/tonemap_test.cpp checks <= 1e-6; documented bound 1e-5).
#pragma once
#include <cstdint>
#include <cstring>

#include "sim/core/image.h"

namespace fovsim {

enum class ToneCurve { Reinhard, Aces, Clamp };

namespace tonemap_detail {

inline float bits_to_float(uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}
inline uint32_t float_to_bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

// The polynomials of pow_inv24 (here and lane-wise in tonemap.cpp), Horner order from the
// highest degree: log2(1 + t) / t for the mantissa t in [0, 1), and 2^f for f in [0, 1).
inline constexpr float kLog2Poly[9] = {0.00758054546f, -0.0426933035f, 0.113062905f,
                                       -0.197295566f,  0.275725247f,   -0.358430199f,
                                       0.480695752f,   -0.721340349f,  1.442695f};
inline constexpr float kExp2Poly[7] = {0.000218775114f,
                                       0.00123878263f,
                                       0.00968457898f,
                                       0.0554804277f,
                                       0.240230501f,
                                       0.693146929f,
                                       1.f};

// x^(1/2.4) for x in [0.0031308, 1] (normal floats).
inline float pow_inv24(float x) {
  const uint32_t b = float_to_bits(x);
  const float e = float(int32_t(b >> 23) - 127);
  const float t = bits_to_float((b & 0x007fffffu) | 0x3f800000u) - 1.f;  // mantissa - 1
  float p = kLog2Poly[0];
  for (int i = 1; i < 9; ++i) p = p * t + kLog2Poly[i];
  const float z = (e + t * p) * (1.f / 2.4f);   // log2(x) / 2.4, in [-3.5, 0]
  const float k = float(int32_t(z + 8.f) - 8);  // floor(z) (z > -8)
  const float f = z - k;                        // [0, 1)
  float q = kExp2Poly[0];
  for (int i = 1; i < 7; ++i) q = q * f + kExp2Poly[i];
  return q * bits_to_float(uint32_t(int32_t(k) + 127) << 23);  // * 2^k
}

}  // namespace tonemap_detail

// Linear light in [0, 1] -> sRGB OETF (IEC 61966-2-1), clamped to [0, 1]; 1 maps to exactly 1.
inline float srgb_encode(float y) {
  y = y > 0.f ? (y < 1.f ? y : 1.f) : 0.f;  // also NaN -> 0
  const float lin = 12.92f * y;
  const float p = 1.055f * tonemap_detail::pow_inv24(y > 0.0031308f ? y : 0.0031308f) - 0.055f;
  const float r = y <= 0.0031308f ? lin : p;
  return y >= 1.f ? 1.f : (r < 1.f ? r : 1.f);
}

// Narkowicz 2015 fit of the ACES filmic curve, clamped to [0, 1]; x >= 0 (inf -> 1).
inline float aces_curve(float x) {
  x = x < 1e9f ? x : 1e9f;  // the curve is 1 long before; keeps x*x finite
  const float y = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
  return y < 1.f ? y : 1.f;
}

// Linear values at or below this encode as black. It keeps every intermediate of the curves a
// normal float, so the result does not depend on the thread's flush-to-zero / denormals-are-zero
// mode (TBB workers that have run Embree work carry FTZ/DAZ, the main thread does not: a
// denormal input gave 0 on one and ~1e-41 on the other). Its display value would be < 1e-29.
constexpr float kToneMapBlack = 1e-30f;

// Linear HDR value (already times exposure) -> display-encoded value in [0, 1].
// Negatives, NaN and values <= kToneMapBlack are black, +inf is white.
template <ToneCurve C>
inline float display_encode(float x) {
  x = x > kToneMapBlack ? x : 0.f;
  float y;
  if constexpr (C == ToneCurve::Reinhard) {
    x = x < 1e9f ? x : 1e9f;
    y = x / (1.f + x);
  } else if constexpr (C == ToneCurve::Aces) {
    y = aces_curve(x);
  } else {
    y = x;
  }
  return srgb_encode(y);
}

// The lane width ToneMap::apply runs (floats per vector: 4 SSE2, 8 AVX2; both give
// display_encode's bits) and a way for tests to force one (0: automatic: FOVSIM_SIMD=generic
// gives 4, otherwise 8 where the CPU has AVX2).
int tonemap_lane_width();
void set_tonemap_lane_width(int w);

struct ToneMap {
  double exposure = 1.0;  // linear scale before the curve
  using Curve = ToneCurve;
  Curve curve = Curve::Aces;
  // Linear HDR RGB -> display-encoded sRGB in [0,1] (what metrics are computed on).
  void apply(const Image& linear, Image& display) const;
};

}  // namespace fovsim
