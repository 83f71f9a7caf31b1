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

// Hits on the common path, per-component arrays, lane j = the j-th such hit: N = 16 for a
// packet (FastLanes), kBatchLanes for trace_gbuffer's batches of a tile (FastBatch).
template <int N>
struct FastLanesN {
  static constexpr int kCapacity = N;
  // Arrays of a batch are padded by a cache line: at 4 KiB each, the j-th elements of all of
  // them would share one L1 set (measured: the batch pass ran 4x slower than unpadded).
  static constexpr int P = N > 16 ? N + 16 : N;
  int m = 0;
  int slot[P];  // staging slot
  int tex[P];   // index into the deferred texture inputs, or -1
  // Inputs: Embree's t, u, v; the ray direction and cone width; the triangle's world-space
  // vertices, vertex normals (hasn = 1) and uvs.
  alignas(64) float t[P], bu[P], bv[P], dx[P], dy[P], dz[P], cone[P], hasn[P];
  alignas(64) float p0x[P], p0y[P], p0z[P], p1x[P], p1y[P], p1z[P], p2x[P], p2y[P], p2z[P];
  alignas(64) float n0x[P], n0y[P], n0z[P], n1x[P], n1y[P], n1z[P], n2x[P], n2y[P], n2z[P];
  alignas(64) float u0x[P], u0y[P], u1x[P], u1y[P], u2x[P], u2y[P];
  // Results: position, normal, uv, footprint (t, bu, bv are refined in place).
  alignas(64) float Px[P], Py[P], Pz[P], Nx[P], Ny[P], Nz[P], U[P], V[P], fw[P];
};
using FastLanes = FastLanesN<16>;
// Rays of one batch of trace_gbuffer (whole 4x4 blocks of a tile, at most this many), and the
// common-path hits of a batch given their attributes together (a chunk: 64 lanes, 12 KiB of
// inputs and results, stay in L1 between the gather and the kernel; 1024 lanes, measured
// slower, do not).
constexpr int kBatchLanes = 1024;
using FastBatch = FastLanesN<64>;

// Refines lanes [0, F.m) (F.t, F.bu, F.bv become refine_hit's values, or stay Embree's where
// refine_hit keeps them) and computes their position, uv, footprint and normal. Lanes from F.m
// to the next multiple of the lane width get zero inputs and throw-away results.
// The lanes' results do not depend on m or on the other lanes.
void gbuffer_lanes(FastLanes& F, float org_x, float org_y, float org_z);
void gbuffer_lanes(FastBatch& F, float org_x, float org_y, float org_z);

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
