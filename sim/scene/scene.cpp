// Scene model: animation, features, sub-model split (TWFR Franke et al. 2021 §6.1) and textures.
#include "sim/scene/scene.h"

#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>
#include <numeric>

namespace fovsim {

glm::mat4 Object::transform_at(double t) const {
  if (keys.empty()) return transform;
  const Keyframe* a = &keys.front();
  const Keyframe* b = a;
  if (t <= keys.front().t) {
    b = a;
  } else if (t >= keys.back().t) {
    a = b = &keys.back();
  } else {
    // Keys are few per object; a binary search keeps long keyframed paths cheap.
    auto it = std::upper_bound(keys.begin(), keys.end(), t,
                               [](double v, const Keyframe& k) { return v < k.t; });
    b = &*it;
    a = &*(it - 1);
  }
  float w = 0.f;
  if (b != a && b->t > a->t) w = float((t - a->t) / (b->t - a->t));
  glm::vec3 tr = glm::mix(a->translation, b->translation, w);
  glm::quat q = glm::slerp(a->rotation, b->rotation, w);
  glm::vec3 s = glm::mix(a->scale, b->scale, w);
  glm::mat4 m =
      glm::translate(glm::mat4(1.f), tr) * glm::mat4_cast(q) * glm::scale(glm::mat4(1.f), s);
  // Keys animate relative to the static transform (which places the object's pivot).
  return transform * m;
}

size_t Scene::triangle_count() const {
  size_t n = 0;
  for (const Object& o : objects) n += meshes[size_t(o.mesh)].triangles.size();
  return n;
}

SceneFeatures Scene::features() const {
  SceneFeatures f;
  for (const Light& l : lights) {
    ++f.lights;
    if (l.shadows) {
      f.shadows = true;
      ++f.shadowed_lights;
    }
    if (l.moving()) f.moving_lights = true;
  }
  std::vector<char> used(materials.size(), 0);
  for (const Object& o : objects) {
    if (o.dynamic()) f.dynamic_objects = true;
    const Mesh& m = meshes[size_t(o.mesh)];
    if (m.tri_material.empty()) {
      if (m.material >= 0 && size_t(m.material) < used.size()) used[size_t(m.material)] = 1;
    } else {
      for (int mi : m.tri_material)
        if (mi >= 0 && size_t(mi) < used.size()) used[size_t(mi)] = 1;
    }
  }
  for (size_t i = 0; i < materials.size(); ++i) {
    if (!used[i]) continue;
    if (materials[i].transparent) f.transparency = true;
    if (materials[i].tex != TexKind::Constant) f.textures = true;
  }
  f.indirect = wants_indirect;
  f.triangles = triangle_count();
  f.submodels = submodels.size();
  return f;
}

namespace {

struct SplitRange {
  uint32_t first, count;
};

// Recursive median split on triangle centroids along the longest axis of the centroid box:
// spatially coherent chunks of <= max_faces, deterministic (stable nth_element by index).
void split_rec(std::vector<uint32_t>& order, const std::vector<glm::vec3>& cent, uint32_t first,
               uint32_t count, uint32_t max_faces, std::vector<SplitRange>& out) {
  if (count <= max_faces) {
    out.push_back({first, count});
    return;
  }
  AABB cb;
  for (uint32_t i = first; i < first + count; ++i) cb.extend(cent[order[i]]);
  glm::vec3 ext = cb.hi - cb.lo;
  int axis = (ext.x >= ext.y && ext.x >= ext.z) ? 0 : (ext.y >= ext.z ? 1 : 2);
  // Split so the left part is a multiple of max_faces where possible: fewer, fuller chunks.
  uint32_t chunks = (count + max_faces - 1) / max_faces;
  uint32_t left = ((chunks + 1) / 2) * max_faces;
  if (left >= count) left = count / 2;
  auto b = order.begin() + first;
  std::nth_element(b, b + left, b + count, [&](uint32_t a, uint32_t c) {
    float va = cent[a][axis], vc = cent[c][axis];
    return va < vc || (va == vc && a < c);
  });
  split_rec(order, cent, first, left, max_faces, out);
  split_rec(order, cent, first + left, count - left, max_faces, out);
}

}  // namespace

void Scene::build_submodels(uint32_t max_faces) {
  if (max_faces == 0) max_faces = 1;
  submodels.clear();
  // Split each mesh once in object space (objects sharing a mesh share its chunks).
  std::vector<std::vector<SplitRange>> chunks(meshes.size());
  std::vector<char> used(meshes.size(), 0);
  for (const Object& o : objects) used[size_t(o.mesh)] = 1;
  for (size_t mi = 0; mi < meshes.size(); ++mi) {
    if (!used[mi]) continue;
    Mesh& m = meshes[mi];
    const uint32_t n = uint32_t(m.triangles.size());
    std::vector<glm::vec3> cent(n);
    for (uint32_t t = 0; t < n; ++t) {
      const glm::uvec3& tri = m.triangles[t];
      cent[t] = (m.positions[tri.x] + m.positions[tri.y] + m.positions[tri.z]) * (1.f / 3.f);
    }
    std::vector<uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    if (n > 0) split_rec(order, cent, 0, n, max_faces, chunks[mi]);
    std::vector<glm::uvec3> tris(n);
    for (uint32_t t = 0; t < n; ++t) tris[t] = m.triangles[order[t]];
    m.triangles.swap(tris);
    if (!m.tri_material.empty()) {
      std::vector<int> mats(n);
      for (uint32_t t = 0; t < n; ++t) mats[t] = m.tri_material[order[t]];
      m.tri_material.swap(mats);
    }
  }
  for (size_t oi = 0; oi < objects.size(); ++oi) {
    const Mesh& m = meshes[size_t(objects[oi].mesh)];
    for (const SplitRange& r : chunks[size_t(objects[oi].mesh)]) {
      SubModel s;
      s.object = int(oi);
      s.first_tri = r.first;
      s.tri_count = r.count;
      for (uint32_t t = r.first; t < r.first + r.count; ++t)
        for (int k = 0; k < 3; ++k) s.bounds.extend(m.positions[m.triangles[t][k]]);
      submodels.push_back(s);
    }
  }
}

}  // namespace fovsim

namespace fovsim {

Json SceneFeatures::to_json() const {
  return Json{{"shadows", shadows},
              {"dynamic_objects", dynamic_objects},
              {"moving_lights", moving_lights},
              {"transparency", transparency},
              {"indirect", indirect},
              {"textures", textures},
              {"triangles", triangles},
              {"submodels", submodels},
              {"lights", lights},
              {"shadowed_lights", shadowed_lights}};
}

SceneFeatures SceneFeatures::from_json(const Json& j) {
  SceneFeatures f;
  f.shadows = j.value("shadows", false);
  f.dynamic_objects = j.value("dynamic_objects", false);
  f.moving_lights = j.value("moving_lights", false);
  f.transparency = j.value("transparency", false);
  f.indirect = j.value("indirect", false);
  f.textures = j.value("textures", false);
  f.triangles = j.value("triangles", size_t(0));
  f.submodels = j.value("submodels", size_t(0));
  f.lights = j.value("lights", 0);
  f.shadowed_lights = j.value("shadowed_lights", 0);
  return f;
}

}  // namespace fovsim
