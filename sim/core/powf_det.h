// powf with fixed bits on every CPU (the shading's specular term, FovVideoVDP's masking through
// powf_lanes.h): glibc's powf algorithm
// (Arm optimized-routines, Nagy 2018: log2 of x from a 16-entry table and a degree-5
// polynomial in double, times y, exp2 from a 32-entry table and a degree-3 polynomial in
// double, one rounding to float) with glibc 2.36's tables and its non-FMA operations, so each
// value equals glibc's SSE2 variant (libm's FMA variants, picked at run time, can differ in the
// last bit). Only the main path is reimplemented: x a positive normal float, y finite and
// non-zero (results that overflow or underflow included); every other input returns false and
// the caller uses std::pow.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace fovsim {

namespace powf_detail {

// {1/c, log2(c)} per subinterval of [0x3f330000, 2 * 0x3f330000) (glibc's __powf_log2_data).
constexpr double kLog2Tab[16][2] = {
    {0x1.661ec79f8f3bep+0, -0x1.efec65b963019p-2}, {0x1.571ed4aaf883dp+0, -0x1.b0b6832d4fca4p-2},
    {0x1.49539f0f010b0p+0, -0x1.7418b0a1fb77bp-2}, {0x1.3c995b0b80385p+0, -0x1.39de91a6dcf7bp-2},
    {0x1.30d190c8864a5p+0, -0x1.01d9bf3f2b631p-2}, {0x1.25e227b0b8ea0p+0, -0x1.97c1d1b3b7af0p-3},
    {0x1.1bb4a4a1a343fp+0, -0x1.2f9e393af3c9fp-3}, {0x1.12358f08ae5bap+0, -0x1.960cbbf788d5cp-4},
    {0x1.0953f419900a7p+0, -0x1.a6f9db6475fcep-5}, {0x1p+0, 0x0p+0},
    {0x1.e608cfd9a47acp-1, 0x1.338ca9f24f53dp-4},  {0x1.ca4b31f026aa0p-1, 0x1.476a9543891bap-3},
    {0x1.b2036576afce6p-1, 0x1.e840b4ac4e4d2p-3},  {0x1.9c2d163a1aa2dp-1, 0x1.40645f0c6651cp-2},
    {0x1.886e6037841edp-1, 0x1.88e9c2c1b9ff8p-2},  {0x1.767dcf5534862p-1, 0x1.ce0a44eb17bccp-2}};
constexpr double kA[5] = {0x1.27616c9496e0bp-2, -0x1.71969a075c67ap-2, 0x1.ec70a6ca7baddp-2,
                          -0x1.7154748bef6c8p-1, 0x1.71547652ab82bp+0};
// 2^(i/32) with i << 47 subtracted from the bits (glibc's __exp2f_data.tab).
constexpr uint64_t kExp2Tab[32] = {
    0x3ff0000000000000, 0x3fefd9b0d3158574, 0x3fefb5586cf9890f, 0x3fef9301d0125b51,
    0x3fef72b83c7d517b, 0x3fef54873168b9aa, 0x3fef387a6e756238, 0x3fef1e9df51fdee1,
    0x3fef06fe0a31b715, 0x3feef1a7373aa9cb, 0x3feedea64c123422, 0x3feece086061892d,
    0x3feebfdad5362a27, 0x3feeb42b569d4f82, 0x3feeab07dd485429, 0x3feea47eb03a5585,
    0x3feea09e667f3bcd, 0x3fee9f75e8ec5f74, 0x3feea11473eb0187, 0x3feea589994cce13,
    0x3feeace5422aa0db, 0x3feeb737b0cdc5e5, 0x3feec49182a3f090, 0x3feed503b23e255d,
    0x3feee89f995ad3ad, 0x3feeff76f2fb5e47, 0x3fef199bdd85529c, 0x3fef3720dcef9069,
    0x3fef5818dcfba487, 0x3fef7c97337b9b5f, 0x3fefa4afa2a490da, 0x3fefd0765b6e4540};
constexpr double kC[3] = {0x1.c6af84b912394p-5, 0x1.ebfce50fac4f3p-3, 0x1.62e42ff0c52d6p-1};
constexpr double kShift = 0x1.8p+47;  // 0x1.8p+52 / 32

}  // namespace powf_detail

// x^y into r when (x, y) is on glibc's main path (see above); false otherwise.
inline bool powf_det(float x, float y, float& r) {
  using namespace powf_detail;
  uint32_t ix, iy;
  std::memcpy(&ix, &x, sizeof ix);
  std::memcpy(&iy, &y, sizeof iy);
  // x negative, zero, subnormal, inf or nan; y zero, inf or nan: glibc's special cases.
  if (ix - 0x00800000u >= 0x7f800000u - 0x00800000u || 2u * iy - 1u >= 2u * 0x7f800000u - 1u)
    return false;
  // log2_inline
  const uint32_t tmp = ix - 0x3f330000u;
  const int i = int((tmp >> (23 - 4)) % 16);
  const uint32_t top = tmp & 0xff800000u;
  const uint32_t iz = ix - top;
  const int k = int32_t(top) >> 23;
  float zf;
  std::memcpy(&zf, &iz, sizeof zf);
  const double z = zf, invc = kLog2Tab[i][0], logc = kLog2Tab[i][1];
  const double rr = z * invc - 1;
  const double y0 = logc + double(k);
  const double r2 = rr * rr;
  double yy = kA[0] * rr + kA[1];
  const double p = kA[2] * rr + kA[3];
  const double r4 = r2 * r2;
  double q = kA[4] * rr + y0;
  q = p * r2 + q;
  yy = yy * r4 + q;
  const double ylogx = double(y) * yy;
  uint64_t u;
  std::memcpy(&u, &ylogx, sizeof u);
  const double lim = 126.0;
  uint64_t ul;
  std::memcpy(&ul, &lim, sizeof ul);
  if ((u >> 47 & 0xffff) >= ul >> 47) {  // |y log2 x| >= 126: glibc's overflow / underflow
    if (ylogx > 0x1.fffffffd1d571p+6) {
      r = std::numeric_limits<float>::infinity();
      return true;
    }
    if (ylogx <= -150.0) {
      r = 0.f;
      return true;
    }
  }
  // exp2_inline, sign_bias 0
  double kd = ylogx + kShift;
  uint64_t ki;
  std::memcpy(&ki, &kd, sizeof ki);
  kd -= kShift;
  const double rx = ylogx - kd;
  uint64_t t = kExp2Tab[ki % 32];
  t += ki << (52 - 5);
  double s;
  std::memcpy(&s, &t, sizeof s);
  const double zz = kC[0] * rx + kC[1];
  const double rx2 = rx * rx;
  double e = kC[2] * rx + 1;
  e = zz * rx2 + e;
  e = e * s;
  r = float(e);
  return true;
}

// The specular power of the shading (shade_one and shade_packet alike): powf_det where it
// applies, std::pow elsewhere (0, subnormal or non-finite inputs).
inline float spec_pow(float x, float y) {
  float r;
  return powf_det(x, y, r) ? r : std::pow(x, y);
}

}  // namespace fovsim
