#include "sim/scene/scene_hash.h"

#include "sim/core/hash.h"

namespace fovsim {

namespace {

void add(ContentHasher& h, const Keyframe& k) {
  h.pod(k.t).pod(k.translation).pod(k.rotation).pod(k.scale);
}

void add(ContentHasher& h, const std::vector<Keyframe>& ks) {
  h.pod(uint64_t(ks.size()));
  for (auto& k : ks) add(h, k);
}

}  // namespace

// Field by field (structs with padding are never hashed as bytes). A field added to Scene or
// its parts belongs here too; the key also holds the scene's config and the code version.
uint64_t scene_content_hash(const Scene& s) {
  ContentHasher h;
  h.str("scene v1").str(s.name);
  h.pod(uint64_t(s.meshes.size()));
  for (auto& m : s.meshes) {
    h.str(m.name).vec(m.positions).vec(m.normals).vec(m.uvs).vec(m.triangles).vec(m.tri_material);
    h.pod(m.material);
  }
  h.pod(uint64_t(s.materials.size()));
  for (auto& m : s.materials) {
    h.str(m.name).pod(m.base_color).pod(m.color2).pod(uint8_t(m.tex)).pod(m.scale).pod(m.angle);
    h.pod(m.specular).pod(m.shininess).pod(m.emission).pod(uint8_t(m.transparent)).pod(m.image);
    h.pod(m.alpha).pod(m.alpha_cutoff).pod(m.normal_image).pod(m.normal_scale);
  }
  h.pod(uint64_t(s.images.size()));
  for (auto& im : s.images) {
    h.pod(im.width).pod(im.height).vec(im.texels).vec(im.alpha);
    h.pod(uint64_t(im.mips.size()));
    for (auto& l : im.mips) h.pod(l.width).pod(l.height).vec(l.texels);
  }
  h.pod(uint64_t(s.objects.size()));
  for (auto& o : s.objects) {
    h.str(o.name).pod(o.mesh).pod(o.transform);
    add(h, o.keys);
  }
  h.pod(uint64_t(s.lights.size()));
  for (auto& l : s.lights) {
    h.pod(uint8_t(l.type)).pod(l.position).pod(l.direction).pod(l.color).pod(l.intensity);
    h.pod(l.spot_inner_deg).pod(l.spot_outer_deg).pod(uint8_t(l.shadows));
    add(h, l.keys);
  }
  h.pod(uint64_t(s.submodels.size()));
  for (auto& m : s.submodels)
    h.pod(m.object).pod(m.first_tri).pod(m.tri_count).pod(m.bounds.lo).pod(m.bounds.hi);
  h.pod(s.ambient).pod(s.background).pod(uint8_t(s.wants_indirect));
  h.pod(s.vpl.rsm_size).pod(s.vpl.min_dist).pod(uint8_t(s.vpl.shadow_rays));
  h.pod(s.exposure).pod(s.default_eye);
  return h.value();
}

}  // namespace fovsim
