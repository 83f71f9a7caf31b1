// SIMD code paths of fovsim's own hot loops (the mapping methods' angle row and Gaussian taps).
// Each kernel is compiled for a generic x86-64 baseline (SSE2) and for AVX2; one path is
// chosen at run time. Results are bit-identical across paths (no FMA, the same IEEE operations
// in the same order), which tests check by running every path the CPU has. FOVSIM_SIMD=generic
// or avx2 forces a path (tests/isa/run_isa_tests.sh runs the suite under each); unset or
// "native" picks the best the CPU supports.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace fovsim {

enum class SimdPath { Generic, Avx2 };

const char* simd_path_name(SimdPath p);
std::vector<SimdPath> simd_paths_available();  // Generic first
// The active path: set_simd_path's, else FOVSIM_SIMD, else the best available. Throws Error
// naming FOVSIM_SIMD for an unknown value or a path the CPU lacks.
SimdPath simd_path();
void set_simd_path(SimdPath p);  // for tests; throws if the CPU lacks it

// v[i] = angle_0_2pi(dy, i + 0.5 - gx) * v_per_rad for i < n (see mapping.h).
void simd_polar_angle_row(double* v, int n, double gx, double dy, double v_per_rad);
// o[j] = sum_{i<n} k[i] * rows[i][j] for j < len, summed in order i = 0..n-1 from 0.
void simd_weighted_rows(float* o, const float* const* rows, const float* k, int n, size_t len);
// KFR's inverse map in float (lp_reconstruct), one screen row: u[i], v[i] = LP coordinates of
// pixel i (eq. 2.10) at dx = dxs[i] and the row's dy, t = min(ln(r^2) half_inv_L, 1) (0 for
// r <= 1), u = t^4 w when pow4 (else u = t: the caller applies K), v = angle * v_per_rad in
// [0, h) (Cephes logf/atanf in float, ~2 ulp).
void simd_lp_uv_row(float* u, float* v, const float* dxs, int n, float dy, float half_inv_L,
                    float w, float v_per_rad, float h, bool pow4);
// out[3i..3i+2] = bilinear RGB sample of lp (lw x lh, 3 floats per pixel) at (u[i], v[i]),
// u in [0, lw], v in [0, lh): x clamped at the borders, y wrapping. Float weights.
void simd_bilinear_wrap_row(float* out, const float* u, const float* v, int n, const float* lp,
                            int lw, int lh);

}  // namespace fovsim
