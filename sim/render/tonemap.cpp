// ToneMap::apply over an image (tonemap.h holds the curve).
//
// The per-element curve (display_encode) is branch-free, but GCC 12 does not if-convert its
// nested float selects, so a plain loop over it stays scalar (18.8 ns per value on an AMD EPYC,
// 8.1 ms per 360x400 RGB image, one thread). Here the same operations, in the same order, run
// on 4 floats at a time with GCC/Clang vector extensions (SSE2, the portable baseline; no FMA
// on any build): 5.6 ns per value, 2.4 ms per image, bit-identical to display_encode for every
// input (tests/render/tonemap_test.cpp). 8-wide vectors lowered to SSE2 pairs ran slower
// (11.6 ns), and two 4-wide chains per iteration gave nothing. Compiled for AVX2 too (8 lanes) and
// picked at run time, the same source runs twice as fast where the CPU has it (bench/README.md).
#include "sim/render/tonemap.h"

#include <tbb/parallel_for.h>

#include "sim/core/lane_choice.h"

namespace fovsim {

namespace {

#if defined(__GNUC__) && !defined(__clang__)
// The 32-byte vector helpers below are internal and inlined; no ABI crosses a translation unit.
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

// N floats per vector: 4 (SSE2, the baseline) or 8 (AVX2), picked at run time (FOVSIM_SIMD as
// the other lane kernels); the operations per lane are the same on both widths and none is
// contracted into an FMA (fp-contract=off on the AVX2 path), so both give display_encode's
// bits. 16 lanes (AVX-512F) measured slower than 4 on an AVX-512 Xeon (5.9 against 4.7 ns per
// value, bench_tonemap apply/360), 8 lanes 2.4 ns.
template <int N>
struct Lanes {
  typedef float vf __attribute__((vector_size(4 * N)));
  typedef int32_t vi __attribute__((vector_size(4 * N)));
  typedef uint32_t vu __attribute__((vector_size(4 * N)));
};
#define FOVSIM_TM_INL inline __attribute__((always_inline))

template <int N>
FOVSIM_TM_INL typename Lanes<N>::vf splat(float f) {
  return typename Lanes<N>::vf{} + f;
}
// m ? a : b per lane (m: all ones or zero, as vector comparisons give).
template <int N>
FOVSIM_TM_INL typename Lanes<N>::vf sel(typename Lanes<N>::vi m, typename Lanes<N>::vf a,
                                        typename Lanes<N>::vf b) {
  using vi = typename Lanes<N>::vi;
  using vf = typename Lanes<N>::vf;
  return (vf)(((vi)a & m) | ((vi)b & ~m));
}

// tonemap_detail::pow_inv24, lane-wise.
template <int N>
FOVSIM_TM_INL typename Lanes<N>::vf pow_inv24(typename Lanes<N>::vf x) {
  using vf = typename Lanes<N>::vf;
  using vi = typename Lanes<N>::vi;
  using vu = typename Lanes<N>::vu;
  const vu b = (vu)x;
  const vf e = __builtin_convertvector((vi)(b >> 23u) - 127, vf);
  const vf t = (vf)((b & 0x007fffffu) | 0x3f800000u) - 1.f;
  vf p = splat<N>(tonemap_detail::kLog2Poly[0]);
  for (int i = 1; i < 9; ++i) p = p * t + tonemap_detail::kLog2Poly[i];
  const vf z = (e + t * p) * (1.f / 2.4f);
  const vi ki = __builtin_convertvector(z + 8.f, vi) - 8;  // truncation, as int32_t(float)
  const vf k = __builtin_convertvector(ki, vf);
  const vf f = z - k;
  vf q = splat<N>(tonemap_detail::kExp2Poly[0]);
  for (int i = 1; i < 7; ++i) q = q * f + tonemap_detail::kExp2Poly[i];
  return q * (vf)((vu)(ki + 127) << 23u);
}

// srgb_encode, lane-wise.
template <int N>
FOVSIM_TM_INL typename Lanes<N>::vf srgb_encode_v(typename Lanes<N>::vf y) {
  using vf = typename Lanes<N>::vf;
  const vf one = splat<N>(1.f), zero = splat<N>(0.f), lo = splat<N>(0.0031308f);
  y = sel<N>(y > 0.f, sel<N>(y < 1.f, y, one), zero);
  const vf lin = 12.92f * y;
  const vf p = 1.055f * pow_inv24<N>(sel<N>(y > 0.0031308f, y, lo)) - 0.055f;
  const vf r = sel<N>(y <= 0.0031308f, lin, p);
  return sel<N>(y >= 1.f, one, sel<N>(r < 1.f, r, one));
}

template <ToneCurve C, int N>
FOVSIM_TM_INL typename Lanes<N>::vf display_encode_v(typename Lanes<N>::vf x) {
  using vf = typename Lanes<N>::vf;
  const vf big = splat<N>(1e9f);
  x = sel<N>(x > kToneMapBlack, x, splat<N>(0.f));
  vf y;
  if constexpr (C == ToneCurve::Reinhard) {
    x = sel<N>(x < 1e9f, x, big);
    y = x / (1.f + x);
  } else if constexpr (C == ToneCurve::Aces) {
    x = sel<N>(x < 1e9f, x, big);
    y = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
    y = sel<N>(y < 1.f, y, splat<N>(1.f));
  } else {
    y = x;
  }
  return srgb_encode_v<N>(y);
}

template <ToneCurve C, int N>
FOVSIM_TM_INL void encode_lanes(const float* in, float* out, size_t n, float ex) {
  using vf = typename Lanes<N>::vf;
  size_t i = 0;
  for (; i + N <= n; i += N) {
    vf x;
    __builtin_memcpy(&x, in + i, sizeof x);
    const vf y = display_encode_v<C, N>(x * ex);
    __builtin_memcpy(out + i, &y, sizeof y);
  }
  for (; i < n; ++i) out[i] = display_encode<C>(in[i] * ex);
}

template <ToneCurve C>
void encode4(const float* in, float* out, size_t n, float ex) {
  encode_lanes<C, 4>(in, out, n, ex);
}
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define FOVSIM_TM_WIDE 1
template <ToneCurve C>
__attribute__((target("avx2"), optimize("fp-contract=off"))) void encode8(const float* in,
                                                                          float* out, size_t n,
                                                                          float ex) {
  encode_lanes<C, 8>(in, out, n, ex);
}
#else
#define FOVSIM_TM_WIDE 0
#endif

// 4 (SSE2) or 8 (AVX2, also on AVX-512F CPUs) floats per instruction (sim/core/lane_choice.h).
LaneChoice g_lanes{4, FOVSIM_TM_WIDE ? 8 : 4, FOVSIM_TM_WIDE ? 8 : 4};

template <ToneCurve C>
void encode_range(const float* in, float* out, size_t n, float ex) {
#if FOVSIM_TM_WIDE
  if (g_lanes.width() == 8) return encode8<C>(in, out, n, ex);
#endif
  encode4<C>(in, out, n, ex);
}

}  // namespace

int tonemap_lane_width() {
  return g_lanes.width();
}
void set_tonemap_lane_width(int w) {
  g_lanes.force(w);
}

void ToneMap::apply(const Image& linear, Image& display) const {
  if (display.width != linear.width || display.height != linear.height ||
      display.channels != linear.channels)
    display.resize(linear.width, linear.height, linear.channels);
  const float ex = float(exposure);
  const Curve cv = curve;
  const float* in = linear.data.data();
  float* out = display.data.data();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, linear.data.size(), 1 << 14),
                    [&](const tbb::blocked_range<size_t>& r) {
                      const size_t b = r.begin(), n = r.end() - r.begin();
                      switch (cv) {
                        case Curve::Reinhard:
                          encode_range<ToneCurve::Reinhard>(in + b, out + b, n, ex);
                          break;
                        case Curve::Aces:
                          encode_range<ToneCurve::Aces>(in + b, out + b, n, ex);
                          break;
                        default:
                          encode_range<ToneCurve::Clamp>(in + b, out + b, n, ex);
                          break;
                      }
                    });
}

}  // namespace fovsim
