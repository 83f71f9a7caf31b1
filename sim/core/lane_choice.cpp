#include "sim/core/lane_choice.h"

#include <cstdlib>
#include <cstring>
#include <initializer_list>

namespace fovsim {

bool cpu_has(LaneIsa isa) {
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)  // the kernels' wide paths
  __builtin_cpu_init();
  if (isa == LaneIsa::avx2) return __builtin_cpu_supports("avx2");
  if (isa == LaneIsa::avx512f) return __builtin_cpu_supports("avx512f");
  return true;
#else
  return isa == LaneIsa::sse2;
#endif
}

LaneIsa auto_lane_isa() {
  static const LaneIsa a = [] {
    const char* v = std::getenv("FOVSIM_SIMD");
    if (v && std::strcmp(v, "generic") == 0) return LaneIsa::sse2;
    if (v && std::strcmp(v, "avx2") == 0)
      return cpu_has(LaneIsa::avx2) ? LaneIsa::avx2 : LaneIsa::sse2;
    return cpu_has(LaneIsa::avx512f) ? LaneIsa::avx512f
           : cpu_has(LaneIsa::avx2)  ? LaneIsa::avx2
                                     : LaneIsa::sse2;
  }();
  return a;
}

int LaneChoice::width() const {
  const int f = forced_.load(std::memory_order_relaxed);
  return f ? f : w_[int(auto_lane_isa())];
}

bool LaneChoice::runs(int w) const {
  for (LaneIsa i : {LaneIsa::sse2, LaneIsa::avx2, LaneIsa::avx512f})
    if (w_[int(i)] == w && cpu_has(i)) return true;
  return false;
}

void LaneChoice::force(int w) {
  forced_.store(w == 0 || runs(w) ? w : w_[0], std::memory_order_relaxed);
}

}  // namespace fovsim
