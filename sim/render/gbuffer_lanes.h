// The packet-wide arithmetic of the G-buffer's common path (static objects with per-vertex uvs
// and no normal map; render_trace.cpp gathers those hits of a packet into FastLanes): the hit
// refinement (refine_hit's double-precision Moller-Trumbore), position, uv, ray-cone footprint
// and shading normal, with the per-sample code's IEEE operations in its order, W lanes at a
// time. W is 4 (SSE2, the x86-64 baseline), 8 (AVX2) or 16 (AVX-512F), chosen at run time;
// no path contracts a * b + c, so every path gives the per-sample code's bits (tests compare
// them lane for lane). Private to sim/render.
#pragma once
#include <vector>

namespace fovsim {

// Hits of a packet on the common path. Per-component arrays, lane j = the j-th such hit.
struct FastLanes {
  int m = 0;
  int slot[16];  // staging slot (packet lane)
  int tex[16];   // index into the packet's deferred texture inputs, or -1
  // Inputs: Embree's t, u, v; the ray direction and cone width; the triangle's world-space
  // vertices, vertex normals (hasn = 1) and uvs.
  alignas(64) float t[16], bu[16], bv[16], dx[16], dy[16], dz[16], cone[16], hasn[16];
  alignas(64) float p0x[16], p0y[16], p0z[16], p1x[16], p1y[16], p1z[16], p2x[16], p2y[16], p2z[16];
  alignas(64) float n0x[16], n0y[16], n0z[16], n1x[16], n1y[16], n1z[16], n2x[16], n2y[16], n2z[16];
  alignas(64) float u0x[16], u0y[16], u1x[16], u1y[16], u2x[16], u2y[16];
  // Results: position, normal, uv, footprint (t, bu, bv are refined in place).
  alignas(64) float Px[16], Py[16], Pz[16], Nx[16], Ny[16], Nz[16], U[16], V[16], fw[16];
};

// Refines lanes [0, F.m) (F.t, F.bu, F.bv become refine_hit's values, or stay Embree's where
// refine_hit keeps them) and computes their position, uv, footprint and normal. Lanes from F.m
// to the next multiple of the lane width get zero inputs and throw-away results.
void gbuffer_lanes(FastLanes& F, float org_x, float org_y, float org_z);

// The 16 primary rays of a full 4x4 pixel block (lane j: column j % 4, row j / 4), as
// trace_gbuffer computes them one pair at a time: s = 1 / sqrt((hx2 + hy2) + 1), direction
// R * (hx s, hy s, -s) rounded to float (Camera::dir_world), cone width cone1 s sqrt(s) rounded to
// float (cone_width). hx, hx2: the block's 4 columns' terms; hy, hy2: its 4 rows'; R: the 3x3
// rotation, column-major (R[3 c + r] = glm's R[c][r]).
void gbuffer_block_rays(const double* hx, const double* hx2, const double* hy, const double* hy2,
                        const double* R, double cone1, float* dx, float* dy, float* dz,
                        float* cone);

// The lane widths this CPU can run (4 first), the active one, and a way for tests to force one
// (0: automatic: FOVSIM_SIMD=generic gives 4, =avx2 gives 8, otherwise the widest available).
std::vector<int> gbuffer_lane_widths();
int gbuffer_lane_width();
void set_gbuffer_lane_width(int w);

}  // namespace fovsim
