// powf over arrays with fixed bits on every CPU: out[k] = spec_pow(x[k], y) (powf_det.h: glibc's
// powf algorithm with its non-FMA operations, std::pow off its main path), several lanes per
// instruction. W doubles per vector: 2 (SSE2, the x86-64 baseline), 4 (AVX2) or 8 (AVX-512F),
// chosen at run time like the G-buffer's lane kernels; no path contracts a * b + c, so every
// path gives powf_det's bits (tests compare them value for value).
#pragma once

namespace fovsim {

// out[k] = x[k]^y for k < n (out may equal x). Lanes off powf_det's main path take std::pow,
// except x = +0 with y > 0, which is +0 in the lanes (IEEE pow).
void powf_array(const float* x, float y, float* out, int n);

// The lane widths (doubles per vector) this CPU can run (2 first) and a way for tests to force
// one (0: automatic: FOVSIM_SIMD=generic gives 2, =avx2 gives 4, otherwise the widest).
int powf_lane_width();
void set_powf_lane_width(int w);

}  // namespace fovsim
