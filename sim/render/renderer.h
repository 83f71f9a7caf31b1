// Embree 3 ray caster (docs/architecture.md "Rendering and the shared reference"): one BVH per
// scene (dynamic objects as instances), G-buffer channels on demand, deterministic Lambert +
// Blinn-Phong shading with shadow rays, tone mapping and display encoding. Parallel over tiles with
// TBB; counts rays.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "sim/core/counters.h"
#include "sim/core/image.h"
#include "sim/core/param_info.h"
#include "sim/core/params.h"
#include "sim/display/display.h"
#include "sim/render/gbuffer.h"
#include "sim/render/tonemap.h"  // ToneMap (kept reachable from here)
#include "sim/scene/scene.h"

namespace fovsim {

// render.spp's default in configs (RenderSettings::from_params), chosen by the convergence
// study; a default-constructed RenderSettings (library use, unit tests) renders 1 spp.
constexpr int kDefaultReferenceSpp = 16;

struct RenderSettings {
  bool shadows = true;  // shadow rays for lights with shadows=true
  int tile = 32;        // tile edge in pixels for TBB
  // Samples per pixel of the shared reference (render.spp, a perfect square: n x n stratified
  // jittered sub-pixel samples, box reconstruction filter over the pixel). Methods are not
  // supersampled: they shade their own samples once each.
  int spp = 1;
  static RenderSettings from_params(Params& p);
};
// The renderer's keys of the `render` block (shadows, tile, spp).
const ParamTable<RenderSettings>& render_settings_table();

// Sub-pixel position of stratum s (of n x n) of pixel (x, y): the stratum's cell, jittered by
// a fixed hash; in [0, 1)^2 (render_reference).
glm::vec2 stratified_offset(int x, int y, int s, int n);

class Renderer {
 public:
  Renderer(const Scene& scene, const RenderSettings& settings);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  const Scene& scene() const { return scene_; }
  // Moves dynamic objects/lights to time t and recommits the BVH (no-op for static scenes).
  // The transforms before this call become the "previous" ones used by kMotion.
  void set_time(double t);
  double time() const { return time_; }

  // One primary ray per pixel centre of cam (W x H). Fills `channels` (| kDepth).
  // `prev` (optional) is the previous frame's camera, for kMotion: motion = this pixel minus
  // where the same surface point (moved back with its object's previous transform) projected
  // in `prev`; 0 on misses, without `prev`, or when the point was behind the previous eye.
  // Counters: primary_rays.
  void trace_gbuffer(const Camera& cam, uint32_t channels, GBuffer& out, Counters* c = nullptr,
                     const Camera* prev = nullptr) const;
  // Primary rays through arbitrary screen points (pixels); out is resized to (n x 1).
  // `spacing`: distance between neighbouring points in pixels (their texture footprint).
  void trace_points(const Camera& cam, const std::vector<glm::vec2>& pts, uint32_t channels,
                    GBuffer& out, Counters* c = nullptr, float spacing = 1.f) const;
  // The shared reference image (linear RGB, W x H) of a frame whose pixel-centre G-buffer g1
  // (kShadingChannels) was traced with trace_gbuffer: settings().spp == 1 shades g1; otherwise
  // n x n stratified samples per pixel (jittered inside each stratum by a fixed hash of pixel
  // and stratum, footprint 1/n pixel), each shaded once, averaged with a box filter in linear
  // light (tone mapping comes after). Counters: primary_rays, shaded_samples, shadow_rays.
  void render_reference(const Camera& cam, const GBuffer& g1, Image& out,
                        Counters* c = nullptr) const;
  const RenderSettings& settings() const { return settings_; }
  // Direct lighting of every sample of g (a G-buffer, or an index view of one, which must have
  // kShadingChannels); misses and cleared slots get the background. mask (size g.size(),
  // optional): shade only where mask[i] != 0, leave others. `out` is resized to
  // g.width x g.height x 3 if its size differs. Linear RGB.
  // Counters: shaded_samples (samples written, misses included), shadow_rays.
  void shade(GBufferRef g, const glm::dvec3& eye, Image& out, const uint8_t* mask = nullptr,
             Counters* c = nullptr) const;
  // Shade a single sample (for methods that need per-sample control; no allocation).
  glm::vec3 shade_sample(const GBuffer& g, size_t i, const glm::vec3& eye) const;
  // Visibility between two world points (true = blocked). Thread-safe.
  bool occluded(const glm::vec3& from, const glm::vec3& to) const;
  // First hit along a ray (distance, or +inf), for RSM rendering from lights etc.
  float intersect(const glm::vec3& org, const glm::vec3& dir, int* object = nullptr,
                  int* prim = nullptr, glm::vec3* normal = nullptr, glm::vec2* uv = nullptr) const;

  // World-space AABB of sub-model i at the current time.
  AABB submodel_bounds_world(size_t i) const;
  uint64_t rays_traced() const { return rays_.load(); }
  void* embree_scene() const;  // RTCScene, for benchmarks

 private:
  struct Impl;
  const Scene& scene_;
  RenderSettings settings_;
  double time_ = 0;
  std::unique_ptr<Impl> impl_;
  mutable std::atomic<uint64_t> rays_{0};
};

}  // namespace fovsim
