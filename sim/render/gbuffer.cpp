#include "sim/render/gbuffer.h"

#include <limits>
#include <type_traits>

namespace fovsim {

void GBuffer::resize(int w, int h, uint32_t ch) {
  width = w;
  height = h;
  channels = ch | kDepth;
  const size_t n = size();
  // Channels not requested are released (not merely left stale): "only what is needed".
  auto fit = [n](auto& v, bool on) {
    using V = std::decay_t<decltype(v)>;
    if (on)
      v.resize(n);
    else
      V().swap(v);
  };
  fit(depth, true);
  fit(position, has(kPosition));
  fit(normal, has(kNormal));
  fit(albedo, has(kAlbedo));
  fit(material, has(kMaterial));
  fit(object_id, has(kObjectId));
  fit(submodel, has(kSubModel));
  fit(motion, has(kMotion));
  fit(uv, has(kUV));
  fit(footprint, has(kFootprint));
}

void GBuffer::copy_sample(const GBuffer& src, size_t s, size_t d) {
  depth[d] = src.depth[s];
  const uint32_t both = channels & src.channels;
  if (both & kPosition) position[d] = src.position[s];
  if (both & kNormal) normal[d] = src.normal[s];
  if (both & kAlbedo) albedo[d] = src.albedo[s];
  if (both & kMaterial) material[d] = src.material[s];
  if (both & kObjectId) object_id[d] = src.object_id[s];
  if (both & kSubModel) submodel[d] = src.submodel[s];
  if (both & kMotion) motion[d] = src.motion[s];
  if (both & kUV) uv[d] = src.uv[s];
  if (both & kFootprint) footprint[d] = src.footprint[s];
}

void GBuffer::clear_sample(size_t i) {
  depth[i] = std::numeric_limits<float>::infinity();
  if (channels & kPosition) position[i] = glm::vec3(0.f);
  if (channels & kNormal) normal[i] = glm::vec3(0.f);
  if (channels & kAlbedo) albedo[i] = glm::vec3(0.f);
  if (channels & kMaterial) material[i] = -1;
  if (channels & kObjectId) object_id[i] = -1;
  if (channels & kSubModel) submodel[i] = -1;
  if (channels & kMotion) motion[i] = glm::vec2(0.f);
  if (channels & kUV) uv[i] = glm::vec2(0.f);
  if (channels & kFootprint) footprint[i] = 0.f;
}

}  // namespace fovsim
