// Packet-wide texture evaluation for the renderer's packets (sim/scene/texture.cpp), and the
// deterministic sine and cosine the procedural textures use.
#pragma once
#include "sim/scene/scene.h"

namespace fovsim {

// A packet's texture lookups: eval_albedo(scene, scene.materials[q[k].mat], q[k].uv,
// mat_cs[mat].x, mat_cs[mat].y, q[k].fw) into out[k] for k < n, bit for bit, with the lanes of a
// material evaluated together (checker and stripes: the box filters two lanes at a time;
// grating: the sines and cosines of all its lanes at once, sincos_packet). mat_cs: cos, sin of
// each material's angle.
struct TexSample {
  glm::vec2 uv;
  int mat;
  float fw;
};
void eval_albedo_packet(const Scene& scene, const glm::vec2* mat_cs, const TexSample* q, int n,
                        glm::vec3* out);
// Doubles per instruction of the packet's box filters (checker, stripes): 2 (SSE2) or 4 (AVX2,
// where the CPU has it, unless FOVSIM_SIMD=generic); both give eval_albedo's bits. The setter
// is for tests (0: automatic; a width the CPU lacks gives 2).
int texture_lane_width();
void set_texture_lane_width(int w);
// sinf and cosf of y[k] (k < n) into s[k], c[k]: glibc's algorithm (Arm optimized-routines,
// Nagy 2018: reduction by pi/2 in double, polynomials in double, one rounding to float) with its
// non-FMA operations, so the bits of glibc's SSE2 variant on every CPU (glibc's FMA variants,
// which libm may pick at run time, can differ in the last bit). The procedural textures use it
// instead of libm so that their bits do not depend on which libm variant runs.
void sincos_packet(const float* y, int n, float* s, float* c);
void sincos_det(float y, float& s, float& c);  // one value, the same bits

}  // namespace fovsim
