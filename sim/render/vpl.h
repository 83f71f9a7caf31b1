// Virtual point lights from reflective shadow maps and single-bounce diffuse shading with
// them (Keller 1997 instant radiosity; Yang et al. 2021 §3 S-2 and S-7).
//
// Units follow the renderer's direct shading, where a point light of intensity I gives
// albedo * I * cos / d^2 (i.e. BRDF albedo/pi and a light of pi*I): a VPL made from an RSM
// texel of solid angle Omega then has flux Phi = albedo_y * I * Omega (times the spot
// falloff) and adds, at a receiver x with albedo rho_x,
//     L(x) = rho_x * sum_v w_v * Phi_v * cos(theta_v) * cos(theta_x) / (pi * max(d^2, d_min^2))
// where w_v is the VPL's weight after culling (1 without culling) and d_min a clamp against
// the 1/d^2 singularity. Visibility between VPL and receiver is optional (exact Embree rays).
#pragma once
#include <cstdint>
#include <vector>

#include "sim/core/counters.h"
#include "sim/core/image.h"
#include "sim/core/math.h"
#include "sim/render/gbuffer.h"
#include "sim/render/rsm.h"

namespace fovsim {

class Renderer;

struct VPL {
  glm::vec3 position{0.f};
  glm::vec3 normal{0, 1, 0};
  glm::vec3 flux{0.f};
  int light = -1;  // source light
  int texel = -1;  // RSM texel index
};

// Appends one VPL per RSM texel that hit a surface with non-zero flux.
void vpls_from_rsm(const RSM& rsm, std::vector<VPL>& out);

// Structure-of-arrays copy of a weighted VPL subset for the shading loop (vectorisable).
struct VplSoA {
  std::vector<float> px, py, pz, nx, ny, nz, fr, fg, fb;  // flux already multiplied by weight / pi
  size_t size() const { return px.size(); }
  void clear();
  void push(const VPL& v, float weight);
};
// Builds the SoA of vpls[idx[k]] weighted by weight[k] (weights may be empty -> 1).
VplSoA make_soa(const std::vector<VPL>& vpls, const std::vector<uint32_t>& idx,
                const std::vector<float>& weight);
VplSoA make_soa(const std::vector<VPL>& vpls);

struct VplShading {
  float min_dist = 0.01f;    // world units; d is clamped to at least this (singularity guard)
  bool visibility = false;   // exact shadow rays VPL -> receiver (Renderer::occluded)
  float ray_offset = 1e-3f;  // shadow-ray end points are pushed this far along their normals
  int tile = 32;
};

// Indirect light at one receiver (position p, unit normal n facing the viewer, albedo a),
// summed over all VPLs of v and scaled by `scale` (interleaved sampling uses one SoA per
// group). `r` is needed only when s.visibility; `rays` (optional) counts shadow rays.
glm::vec3 shade_vpls_point(const VplSoA& v, const glm::vec3& p, const glm::vec3& n,
                           const glm::vec3& a, const VplShading& s, const Renderer* r = nullptr,
                           float scale = 1.f, uint64_t* rays = nullptr);

// Indirect light of every G-buffer sample (needs kPosition|kNormal|kAlbedo) into `out`
// (W x H x 3, linear; misses get 0). mask (optional): shade only where mask[i] != 0 (others 0).
// Counters: shaded_samples (+= samples shaded), shaded_sample_vpls (+= samples * VPLs),
// vpl_shadow_rays.
void shade_indirect(const GBuffer& g, const VplSoA& v, const VplShading& s, Image& out,
                    const Renderer* r = nullptr, const uint8_t* mask = nullptr,
                    Counters* c = nullptr);

}  // namespace fovsim
