#include "sim/foveation/simd_kernels.h"

#include <atomic>
#include <cstdint>
#include <cstdlib>

#include "sim/core/error.h"
#include "sim/core/lane_choice.h"  // FOVSIM_HAVE_AVX2_PATH

namespace fovsim {
namespace {

#define FOVSIM_KERNEL(name) name##_generic
#define FOVSIM_KERNEL_ATTR
#if defined(__GNUC__) && !defined(__clang__)
#define FOVSIM_KERNEL_ATTR_NTM __attribute__((optimize("no-trapping-math")))
#else
#define FOVSIM_KERNEL_ATTR_NTM
#endif
#include "sim/foveation/simd_kernels.inc"
#undef FOVSIM_KERNEL
#undef FOVSIM_KERNEL_ATTR
#undef FOVSIM_KERNEL_ATTR_NTM

#if FOVSIM_HAVE_AVX2_PATH
#define FOVSIM_KERNEL(name) name##_avx2
#define FOVSIM_KERNEL_ATTR __attribute__((target("avx2")))
#define FOVSIM_KERNEL_ATTR_NTM __attribute__((target("avx2"), optimize("no-trapping-math")))
#include "sim/foveation/simd_kernels.inc"
#undef FOVSIM_KERNEL
#undef FOVSIM_KERNEL_ATTR
#undef FOVSIM_KERNEL_ATTR_NTM
#endif

bool cpu_has_avx2() {
#if FOVSIM_HAVE_AVX2_PATH
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

std::atomic<int> g_override{-1};

SimdPath from_env() {
  const char* v = std::getenv("FOVSIM_SIMD");
  if (!v || !*v || std::string(v) == "native")
    return cpu_has_avx2() ? SimdPath::Avx2 : SimdPath::Generic;
  const std::string s(v);
  if (s == "generic") return SimdPath::Generic;
  if (s == "avx2") {
    if (!cpu_has_avx2())
      throw Error("FOVSIM_SIMD", "this CPU has no AVX2 (allowed here: native, generic)");
    return SimdPath::Avx2;
  }
  throw Error("FOVSIM_SIMD", "unknown SIMD path \"" + s + "\" (allowed: native, generic, avx2)");
}

}  // namespace

const char* simd_path_name(SimdPath p) {
  return p == SimdPath::Avx2 ? "avx2" : "generic";
}

std::vector<SimdPath> simd_paths_available() {
  std::vector<SimdPath> v = {SimdPath::Generic};
  if (cpu_has_avx2()) v.push_back(SimdPath::Avx2);
  return v;
}

SimdPath simd_path() {
  const int o = g_override.load(std::memory_order_relaxed);
  if (o >= 0) return SimdPath(o);
  static const SimdPath p = from_env();  // a bad value throws here (and again on retry)
  return p;
}

void set_simd_path(SimdPath p) {
  if (p == SimdPath::Avx2 && !cpu_has_avx2()) throw Error("set_simd_path", "this CPU has no AVX2");
  g_override.store(int(p));
}

void simd_polar_angle_row(double* v, int n, double gx, double dy, double v_per_rad) {
#if FOVSIM_HAVE_AVX2_PATH
  if (simd_path() == SimdPath::Avx2) return polar_angle_row_avx2(v, n, gx, dy, v_per_rad);
#endif
  polar_angle_row_generic(v, n, gx, dy, v_per_rad);
}

void simd_weighted_rows(float* o, const float* const* rows, const float* k, int n, size_t len) {
#if FOVSIM_HAVE_AVX2_PATH
  if (simd_path() == SimdPath::Avx2) return weighted_rows_avx2(o, rows, k, n, len);
#endif
  weighted_rows_generic(o, rows, k, n, len);
}

void simd_lp_uv_row(float* u, float* v, const float* dxs, int n, float dy, float half_inv_L,
                    float w, float v_per_rad, float h, bool pow4) {
#if FOVSIM_HAVE_AVX2_PATH
  if (simd_path() == SimdPath::Avx2)
    return pow4 ? lp_uv_row_avx2<true>(u, v, dxs, n, dy, half_inv_L, w, v_per_rad, h)
                : lp_uv_row_avx2<false>(u, v, dxs, n, dy, half_inv_L, w, v_per_rad, h);
#endif
  pow4 ? lp_uv_row_generic<true>(u, v, dxs, n, dy, half_inv_L, w, v_per_rad, h)
       : lp_uv_row_generic<false>(u, v, dxs, n, dy, half_inv_L, w, v_per_rad, h);
}

void simd_bilinear_wrap_row(float* out, const float* u, const float* v, int n, const float* lp,
                            int lw, int lh) {
#if FOVSIM_HAVE_AVX2_PATH
  if (simd_path() == SimdPath::Avx2) return bilinear_wrap_row_avx2(out, u, v, n, lp, lw, lh);
#endif
  bilinear_wrap_row_generic(out, u, v, n, lp, lw, lh);
}

}  // namespace fovsim
