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

}  // namespace fovsim
