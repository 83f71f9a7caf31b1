// 4 floats (SSE2, the x86-64 baseline) for the packet-wide G-buffer and shading paths: +, -, *,
// / and sqrt are the scalar code's IEEE operations lane by lane; comparisons give lane masks
// (-1 / 0, false on NaN as in C++), and `m ? a : b` selects per lane. The portable build has no
// FMA, so a * b + c is not contracted and the lanes keep the per-sample path's bits.
#pragma once
#include <cstdint>

namespace fovsim {

typedef float vf __attribute__((vector_size(16)));
typedef int32_t vi __attribute__((vector_size(16)));

inline vf ld4(const float* p) {
  vf v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}
inline void st4(float* p, vf v) {
  __builtin_memcpy(p, &v, sizeof v);
}
inline vi ldi4(const int32_t* p) {
  vi v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}
inline void sti4(int32_t* p, vi v) {
  __builtin_memcpy(p, &v, sizeof v);
}
inline vf splat(float x) {
  return vf{x, x, x, x};
}
inline vf vsqrt(vf x) {
  return __builtin_ia32_sqrtps(x);
}

}  // namespace fovsim
