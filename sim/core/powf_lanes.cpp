// powf_array (powf_lanes.h): powf_det's operations on W lanes at a time. The body below is
// compiled three times (SSE2, AVX2, AVX-512F); each lane's IEEE double operations are
// powf_det's in its order; the table lookups are per-lane loads (SSE2, AVX2) or permutes of
// the tables held in registers (AVX-512F), the same values.
#include "sim/core/powf_lanes.h"

#include <immintrin.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "sim/core/lane_choice.h"
#include "sim/core/powf_det.h"

namespace fovsim {
namespace {

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define FOVSIM_PW_WIDE 1
#else
#define FOVSIM_PW_WIDE 0
#endif

// The body: POW_LANES(name, W, attributes) defines name(x, y, out, n) for W doubles a vector.
// x's lanes are all processed in full vectors (the caller pads); lanes off the main path are
// flagged in `slow` (1) for the caller.
#define POW_LANES(NAME, WD, ATTR)                                                              \
  ATTR void NAME(const float* xs, float y, float* out, int n, uint8_t* slow) {                 \
    using namespace powf_detail;                                                               \
    typedef double D __attribute__((vector_size(8 * WD)));                                     \
    typedef uint64_t DU __attribute__((vector_size(8 * WD)));                                  \
    typedef int64_t DL __attribute__((vector_size(8 * WD)));                                   \
    typedef float F __attribute__((vector_size(4 * WD)));                                      \
    typedef uint32_t FU __attribute__((vector_size(4 * WD)));                                  \
    typedef int32_t FI __attribute__((vector_size(4 * WD)));                                   \
    const double lim = 126.0;                                                                  \
    uint64_t ul;                                                                               \
    std::memcpy(&ul, &lim, sizeof ul);                                                         \
    const D yd = D{} + double(y);                                                              \
    [[maybe_unused]] constexpr int kW = WD;                                                    \
    for (int o = 0; o < n; o += WD) {                                                          \
      FU ix;                                                                                   \
      std::memcpy(&ix, xs + o, sizeof ix);                                                     \
      /* x negative, zero, subnormal, inf or nan: off the main path */                         \
      const FI bad = ix - 0x00800000u >= 0x7f800000u - 0x00800000u;                            \
      const FU tmp = ix - 0x3f330000u;                                                         \
      const FU i = (tmp >> (23 - 4)) % 16;                                                     \
      const FU top = tmp & 0xff800000u;                                                        \
      const FU iz = ix - top;                                                                  \
      const FI k = (FI)top >> 23;                                                              \
      const D z = __builtin_convertvector((F)iz, D);                                           \
      D invc, logc;                                                                            \
      LOOKUP_LOG(i, invc, logc);                                                               \
      const D rr = z * invc - 1.0;                                                             \
      const D y0 = logc + __builtin_convertvector(k, D);                                       \
      const D r2 = rr * rr;                                                                    \
      D yy = kA[0] * rr + kA[1];                                                               \
      const D p = kA[2] * rr + kA[3];                                                          \
      const D r4 = r2 * r2;                                                                    \
      D q = kA[4] * rr + y0;                                                                   \
      q = p * r2 + q;                                                                          \
      yy = yy * r4 + q;                                                                        \
      const D ylogx = yd * yy;                                                                 \
      const DL big = (((DU)ylogx >> 47) & 0xffff) >= (ul >> 47);                               \
      const DL ovf = big & (ylogx > 0x1.fffffffd1d571p+6);                                     \
      const DL unf = big & (ylogx <= -150.0);                                                  \
      D kd = ylogx + kShift;                                                                   \
      const DU ki = (DU)kd;                                                                    \
      kd -= kShift;                                                                            \
      const D rx = ylogx - kd;                                                                 \
      DU t;                                                                                    \
      LOOKUP_EXP(ki, t);                                                                       \
      t += ki << (52 - 5);                                                                     \
      const D s = (D)t;                                                                        \
      const D zz = kC[0] * rx + kC[1];                                                         \
      const D rx2 = rx * rx;                                                                   \
      D e = kC[2] * rx + 1.0;                                                                  \
      e = zz * rx2 + e;                                                                        \
      e = e * s;                                                                               \
      F r = __builtin_convertvector(e, F);                                                     \
      r = __builtin_convertvector(ovf, FI) ? F{} + std::numeric_limits<float>::infinity() : r; \
      r = __builtin_convertvector(unf, FI) ? F{} : r;                                          \
      /* x = +0 (y > 0 here): +0 */                                                            \
      r = ix == 0u ? F{} : r;                                                                  \
      std::memcpy(out + o, &r, sizeof r);                                                      \
      for (int j = 0; j < WD; ++j) slow[o + j] = uint8_t(bad[j] && ix[j] != 0u);               \
    }                                                                                          \
  }

// Table lookups per lane (SSE2, AVX2): loads.
#define LOOKUP_LOG(i, invc, logc) \
  for (int j = 0; j < kW; ++j) {  \
    invc[j] = kLog2Tab[i[j]][0];  \
    logc[j] = kLog2Tab[i[j]][1];  \
  }
#define LOOKUP_EXP(ki, t) \
  for (int j = 0; j < kW; ++j) t[j] = kExp2Tab[ki[j] % 32];
POW_LANES(lanes2, 2, )
#if FOVSIM_PW_WIDE
// fp-contract=off: AVX-512F has FMA instructions of its own and GCC would otherwise fuse
// a * b + c (one rounding instead of two), which changes bits.
POW_LANES(lanes4, 4, __attribute__((target("avx2"), optimize("fp-contract=off"))))
#undef LOOKUP_LOG
#undef LOOKUP_EXP

// AVX-512F: the tables in registers, looked up with two-source permutes (the same values).
struct Tab512 {
  alignas(64) double invc[16], logc[16];
  alignas(64) uint64_t e[32];
  Tab512() {
    for (int k = 0; k < 16; ++k) {
      invc[k] = powf_detail::kLog2Tab[k][0];
      logc[k] = powf_detail::kLog2Tab[k][1];
    }
    for (int k = 0; k < 32; ++k) e[k] = powf_detail::kExp2Tab[k];
  }
};
const Tab512 kTab512;
#define LOOKUP_LOG(i, invc, logc)                                                \
  {                                                                              \
    const __m512i ix8 = _mm512_maskz_cvtepu32_epi64(__mmask8(0xff), (__m256i)i); \
    invc = (D)_mm512_permutex2var_pd(_mm512_load_pd(kTab512.invc), ix8,          \
                                     _mm512_load_pd(kTab512.invc + 8));          \
    logc = (D)_mm512_permutex2var_pd(_mm512_load_pd(kTab512.logc), ix8,          \
                                     _mm512_load_pd(kTab512.logc + 8));          \
  }
#define LOOKUP_EXP(ki, t)                                                               \
  {                                                                                     \
    const __m512i k5 = (__m512i)ki & _mm512_set1_epi64(31);                             \
    const __m512i lo = _mm512_permutex2var_epi64(_mm512_load_si512(kTab512.e), k5,      \
                                                 _mm512_load_si512(kTab512.e + 8));     \
    const __m512i hi = _mm512_permutex2var_epi64(_mm512_load_si512(kTab512.e + 16), k5, \
                                                 _mm512_load_si512(kTab512.e + 24));    \
    const __mmask8 up = _mm512_test_epi64_mask(k5, _mm512_set1_epi64(16));              \
    t = (DU)_mm512_mask_blend_epi64(up, lo, hi);                                        \
  }
POW_LANES(lanes8, 8, __attribute__((target("avx512f"), optimize("fp-contract=off"))))
#undef LOOKUP_LOG
#undef LOOKUP_EXP
#endif
#undef POW_LANES

// 2 (SSE2), 4 (AVX2), 8 (AVX-512F) doubles per instruction (sim/core/lane_choice.h).
LaneChoice g_lanes{2, FOVSIM_PW_WIDE ? 4 : 2, FOVSIM_PW_WIDE ? 8 : 2};

}  // namespace

int powf_lane_width() {
  return g_lanes.width();
}

void set_powf_lane_width(int w) {
  g_lanes.force(w);
}

void powf_array(const float* x, float y, float* out, int n) {
  uint32_t iy;
  std::memcpy(&iy, &y, sizeof iy);
  // y zero, inf or nan, or y < 0 (x = +0 would give inf): every lane through spec_pow.
  if (2u * iy - 1u >= 2u * 0x7f800000u - 1u || !(y > 0.f)) {
    for (int k = 0; k < n; ++k) out[k] = spec_pow(x[k], y);
    return;
  }
  constexpr int B = 64;  // lanes per block (a multiple of every width)
  alignas(64) float xb[B], rb[B];
  uint8_t slow[B];
  const int w = powf_lane_width();
  for (int k0 = 0; k0 < n; k0 += B) {
    const int m = n - k0 < B ? n - k0 : B;
    std::memcpy(xb, x + k0, sizeof(float) * size_t(m));
    for (int k = m; k < B; ++k) xb[k] = 1.f;
    const int mv = (m + 7) / 8 * 8;
#if FOVSIM_PW_WIDE
    if (w == 8)
      lanes8(xb, y, rb, mv, slow);
    else if (w == 4)
      lanes4(xb, y, rb, mv, slow);
    else
#endif
      lanes2(xb, y, rb, mv, slow);
    uint64_t any = 0;  // any lane off the main path?
    for (int k = 0; k < mv; k += 8) {
      uint64_t v;
      std::memcpy(&v, slow + k, sizeof v);
      any |= v;
    }
    if (!any) {
      std::memcpy(out + k0, rb, sizeof(float) * size_t(m));
      continue;
    }
    for (int k = 0; k < m; ++k) out[k0 + k] = slow[k] ? std::pow(xb[k], y) : rb[k];
  }
}

}  // namespace fovsim
