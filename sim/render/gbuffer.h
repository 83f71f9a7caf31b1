// G-buffer with channels computed only on request (docs/architecture.md "Rendering and the shared
// reference"). Also used for arbitrary sets of samples (LP-buffer, RS-buffer) gathered from the
// full-resolution G-buffer.
#pragma once
#include <cstdint>
#include <vector>

#include "sim/core/math.h"

namespace fovsim {

enum Channel : uint32_t {
  kDepth = 1u << 0,     // always filled: distance along the primary ray; +inf on a miss
  kPosition = 1u << 1,  // world-space hit point
  kNormal = 1u << 2,    // world-space shading normal (faces the viewer)
  kAlbedo = 1u << 3,    // texture-evaluated diffuse colour
  kMaterial = 1u << 4,  // material index (specular parameters)
  kObjectId = 1u << 5,  // object index, -1 on a miss
  kSubModel = 1u << 6,  // sub-model index, -1 on a miss
  kMotion = 1u << 7,    // screen motion (pixels) from the previous frame's camera+objects
  kUV = 1u << 8,
  kFootprint = 1u << 9,  // texture filter width at the sample (uv units; see render_trace.cpp)
};
// Channels the shader needs (Renderer::shade).
constexpr uint32_t kShadingChannels = kDepth | kPosition | kNormal | kAlbedo | kMaterial;

struct GBuffer {
  int width = 0, height = 0;
  uint32_t channels = 0;
  std::vector<float> depth, footprint;
  std::vector<glm::vec3> position, normal, albedo;
  std::vector<int32_t> material, object_id, submodel;
  std::vector<glm::vec2> motion, uv;

  size_t size() const { return size_t(width) * size_t(height); }
  bool has(uint32_t c) const { return (channels & c) == c; }
  bool hit(size_t i) const { return depth[i] < 3.0e38f; }
  // Allocates the requested channels (kDepth always).
  void resize(int w, int h, uint32_t ch);
  // Copies sample `src_i` of `src` into slot `dst_i` (channels present in both).
  void copy_sample(const GBuffer& src, size_t src_i, size_t dst_i);
  // Marks slot i as a miss/empty sample.
  void clear_sample(size_t i);
};

// Read-only view of samples of a G-buffer: sample i of the view (width x height) is sample
// index[i] of *g, kNone a cleared slot (a miss); index == nullptr is the G-buffer itself.
// Reduced buffers (KFR's LP-buffer, RMFR's TG-buffer, hyperbolic layers) are shaded through
// an index instead of a copy of every channel: shading a sample is a pure function of its
// channel values, so reading them through the index gives the same bits. Implicit from a
// GBuffer, so the shading entry points take either.
struct GBufferRef {
  static constexpr uint32_t kNone = ~0u;
  const GBuffer* g = nullptr;
  const uint32_t* index = nullptr;  // width * height entries, or nullptr (identity)
  int width = 0, height = 0;

  GBufferRef(const GBuffer& b) : g(&b), width(b.width), height(b.height) {}  // NOLINT: implicit
  GBufferRef(const GBuffer& b, const uint32_t* idx, int w, int h)
      : g(&b), index(idx), width(w), height(h) {}
  size_t size() const { return size_t(width) * size_t(height); }
  // Sample of *g behind slot i; only valid where hit(i) (a cleared slot has no source).
  size_t src(size_t i) const { return index ? size_t(index[i]) : i; }
  bool hit(size_t i) const {
    if (!index) return g->hit(i);
    const uint32_t s = index[i];
    return s != kNone && g->hit(s);
  }
};

}  // namespace fovsim
