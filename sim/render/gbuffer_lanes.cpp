#include "sim/render/gbuffer_lanes.h"

#include <immintrin.h>

#include <cmath>
#include <cstdint>

#include "sim/core/lane_choice.h"

namespace fovsim {
namespace {

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define FOVSIM_GB_WIDE 1
#else
#define FOVSIM_GB_WIDE 0
#endif

// SSE2 (the build's baseline).
#define FOVSIM_GB_W 4
#define FOVSIM_GB_NS w4
#define FOVSIM_GB_ATTR
#include "sim/render/gbuffer_lanes.inc"
#undef FOVSIM_GB_W
#undef FOVSIM_GB_NS
#undef FOVSIM_GB_ATTR

#if FOVSIM_GB_WIDE
// AVX2 and AVX-512F. fp-contract=off: AVX-512F has FMA instructions of its own and GCC would
// otherwise fuse a * b + c (one rounding instead of two), which changes bits.
#define FOVSIM_GB_W 8
#define FOVSIM_GB_NS w8
#define FOVSIM_GB_ATTR __attribute__((target("avx2"), optimize("fp-contract=off")))
#include "sim/render/gbuffer_lanes.inc"
#undef FOVSIM_GB_W
#undef FOVSIM_GB_NS
#undef FOVSIM_GB_ATTR

#define FOVSIM_GB_W 16
#define FOVSIM_GB_NS w16
#define FOVSIM_GB_ATTR __attribute__((target("avx512f"), optimize("fp-contract=off")))
#include "sim/render/gbuffer_lanes.inc"
#undef FOVSIM_GB_W
#undef FOVSIM_GB_NS
#undef FOVSIM_GB_ATTR
#endif

// 4 (SSE2), 8 (AVX2), 16 (AVX-512F) floats per instruction (sim/core/lane_choice.h).
LaneChoice g_lanes{4, FOVSIM_GB_WIDE ? 8 : 4, FOVSIM_GB_WIDE ? 16 : 4};

}  // namespace

std::vector<int> gbuffer_lane_widths() {
  std::vector<int> v{4};
  for (int w : {8, 16})
    if (g_lanes.runs(w)) v.push_back(w);
  return v;
}

int gbuffer_lane_width() {
  return g_lanes.width();
}

void set_gbuffer_lane_width(int w) {
  g_lanes.force(w);
}

namespace {
template <class L>
void lanes_any(L& F, float org_x, float org_y, float org_z) {
#if FOVSIM_GB_WIDE
  switch (gbuffer_lane_width()) {
    case 16:
      return w16::lanes(F, org_x, org_y, org_z);
    case 8:
      return w8::lanes(F, org_x, org_y, org_z);
    default:
      break;
  }
#endif
  w4::lanes(F, org_x, org_y, org_z);
}
}  // namespace

void gbuffer_lanes(FastLanes& F, float org_x, float org_y, float org_z) {
  lanes_any(F, org_x, org_y, org_z);
}

void gbuffer_lanes(FastBatch& F, float org_x, float org_y, float org_z) {
  lanes_any(F, org_x, org_y, org_z);
}

void gbuffer_block_rays(const double* hx, const double* hx2, const double* hy, const double* hy2,
                        const double* R, double cone1, float* dx, float* dy, float* dz,
                        float* cone) {
#if FOVSIM_GB_WIDE
  switch (gbuffer_lane_width()) {
    case 16:
      return w16::block_rays(hx, hx2, hy, hy2, R, cone1, dx, dy, dz, cone);
    case 8:
      return w8::block_rays(hx, hx2, hy, hy2, R, cone1, dx, dy, dz, cone);
    default:
      break;
  }
#endif
  w4::block_rays(hx, hx2, hy, hy2, R, cone1, dx, dy, dz, cone);
}

}  // namespace fovsim
