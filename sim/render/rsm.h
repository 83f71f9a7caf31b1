// Reflective shadow maps (Dachsbacher & Stamminger 2005), rendered by casting one ray per
// texel from the light with Embree (Yang et al. 2021 §3, S-1 in its Fig. 1; 64x64 per light in §7).
// Each texel stores the first hit (position, normal facing the light, light-space depth) and
// the flux that the texel's patch reflects diffusely, from which VPLs are made (vpl.h).
//
// Parameterisation per light type (all texel solid angles/areas are exact integrals of the
// mapping, so the texels of a point light sum to 4 pi):
//  - point:       octahedral map of the whole sphere, d omega = du dv / |p|^3, p = (u, v,
//  1-|u|-|v|);
//  - spot:        perspective map over the outer cone, d omega = dx dy / |p|^3, p = (x, y, 1);
//  - directional: orthographic map over the scene bounds, texel area (extent / size)^2.
// Light-space depth (for BLSO, Yang et al. 2021 eq. 12) is the distance from the light for point
// and spot lights and the distance along the light direction for directional lights.
#pragma once
#include <cstdint>
#include <vector>

#include "sim/core/counters.h"
#include "sim/core/math.h"
#include "sim/scene/scene.h"

namespace fovsim {

class Renderer;

// A light's state at one time (moving lights interpolated), in the renderer's units.
struct LightState {
  Light::Type type = Light::Type::Point;
  glm::vec3 position{0.f};
  glm::vec3 direction{0, -1, 0};           // unit, direction light travels
  glm::vec3 radiance{1.f};                 // colour * intensity
  float cos_inner = 1.f, cos_outer = 0.f;  // spot cone
  bool shadows = true;
};
LightState light_state(const Light& l, double t);
// Spot cone falloff in [0,1] for a unit direction `dir` leaving the light (1 for others).
float spot_falloff(const LightState& l, const glm::vec3& dir);

struct RSM {
  int size = 0;    // texels per edge
  int light = -1;  // index in Scene::lights
  LightState ls;
  // Light frame: for spot/directional lights `axis` is the light direction; t1, t2 span the map.
  glm::vec3 axis{0, -1, 0}, t1{1, 0, 0}, t2{0, 0, 1};
  glm::vec3 origin{0.f};    // directional: centre of the map plane (upstream of the scene)
  float tan_outer = 1.f;    // spot: tangent of the outer cone half-angle
  float half_extent = 1.f;  // directional: half edge of the map in world units
  // Per texel (row-major, size*size); depth = +inf where the ray missed.
  std::vector<float> depth;
  std::vector<glm::vec3> position, normal, flux;
  std::vector<float> measure;  // solid angle (point/spot) or area (directional) of the texel

  size_t texels() const { return size_t(size) * size_t(size); }
  bool hit(size_t i) const { return depth[i] < 3.0e38f; }
  // Ray of texel centre (fx, fy in [0,size)), origin and unit direction.
  void texel_ray(float fx, float fy, glm::vec3& org, glm::vec3& dir) const;
  // Projects a world point into the map: continuous texel coordinates and light-space depth.
  // Returns false where the point is outside the map (behind a spot light, outside the
  // directional map's extent).
  bool project(const glm::vec3& p, glm::vec2& texel, float& light_depth) const;
  // Stored depth at the texel containing continuous coordinates (nearest; clamped).
  float depth_at(const glm::vec2& texel) const;
};

// Octahedral mapping of unit directions <-> [-1,1]^2 (Praun & Hoppe 2003 / Cigolle et al. 2014).
glm::vec2 oct_encode(const glm::vec3& dir);
glm::vec3 oct_decode(glm::vec2 e);  // unit direction

// Sets up the map geometry of light `light_index` at time t (no rays). `bounds` = world AABB
// of the scene (used by directional lights).
void setup_rsm(const Scene& scene, int light_index, double t, int size, const AABB& bounds,
               RSM& out);
// Renders the RSM of light `light_index` at the renderer's current time. Counters:
// rsm_texels (+= size^2), rsm_rays.
void render_rsm(const Renderer& r, int light_index, int size, const AABB& bounds, RSM& out,
                Counters* c = nullptr);
// World AABB of everything in the renderer's scene at its current time.
AABB scene_bounds(const Renderer& r);

}  // namespace fovsim
