// Scene model: animation, features, sub-model split (TWFR seed 002 §6.1) and textures.
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

// ---- procedural textures ----------------------------------------------------------------

namespace {

inline float fractf(float x) {
  return x - std::floor(x);
}

// {cos, sin} of the grating's per-orientation phase 0.7 * o.
constexpr float kGratingPhase[4][2] = {{1.f, 0.f},
                                       {0.76484219f, 0.64421769f},
                                       {0.16996714f, 0.98544973f},
                                       {-0.50484610f, 0.86320937f}};

inline uint32_t hash2(int32_t x, int32_t y) {
  uint32_t h = uint32_t(x) * 0x8da6b343u ^ uint32_t(y) * 0xd8163841u;
  h ^= h >> 13;
  h *= 0x85ebca6bu;
  h ^= h >> 16;
  return h;
}

inline float value_noise(glm::vec2 p) {
  float fx = std::floor(p.x), fy = std::floor(p.y);
  int32_t ix = int32_t(fx), iy = int32_t(fy);
  float tx = p.x - fx, ty = p.y - fy;
  tx = tx * tx * (3.f - 2.f * tx);
  ty = ty * ty * (3.f - 2.f * ty);
  const float k = 1.f / 4294967295.f;
  float a = float(hash2(ix, iy)) * k, b = float(hash2(ix + 1, iy)) * k;
  float c = float(hash2(ix, iy + 1)) * k, d = float(hash2(ix + 1, iy + 1)) * k;
  return (a + (b - a) * tx) * (1.f - ty) + (c + (d - c) * tx) * ty;
}

glm::vec3 sample_image(const TextureImage& img, glm::vec2 uv) {
  if (img.width <= 0 || img.height <= 0 || img.texels.empty()) return glm::vec3(1.f);
  // Bilinear with wrap (glTF default sampler is REPEAT); v grows downwards in the image.
  float x = fractf(uv.x) * float(img.width) - 0.5f;
  float y = fractf(uv.y) * float(img.height) - 0.5f;
  float fx = std::floor(x), fy = std::floor(y);
  float tx = x - fx, ty = y - fy;
  auto wrap = [](int i, int n) { return ((i % n) + n) % n; };
  int x0 = wrap(int(fx), img.width), x1 = wrap(int(fx) + 1, img.width);
  int y0 = wrap(int(fy), img.height), y1 = wrap(int(fy) + 1, img.height);
  auto T = [&](int xi, int yi) { return img.texels[size_t(yi) * size_t(img.width) + size_t(xi)]; };
  return glm::mix(glm::mix(T(x0, y0), T(x1, y0), tx), glm::mix(T(x0, y1), T(x1, y1), tx), ty);
}

}  // namespace

glm::vec3 eval_albedo(const Scene& scene, const Material& m, glm::vec2 uv) {
  return eval_albedo(scene, m, uv, std::cos(m.angle), std::sin(m.angle));
}

glm::vec3 eval_albedo(const Scene& scene, const Material& m, glm::vec2 uv, float ca, float sa) {
  auto rot = [ca, sa](glm::vec2 p) { return glm::vec2(ca * p.x - sa * p.y, sa * p.x + ca * p.y); };
  switch (m.tex) {
    case TexKind::Constant:
      return m.base_color;
    case TexKind::Checker: {
      glm::vec2 p = rot(uv) * m.scale;
      int32_t c = int32_t(std::floor(p.x)) + int32_t(std::floor(p.y));
      return (c & 1) ? m.color2 : m.base_color;
    }
    case TexKind::Stripes: {
      glm::vec2 p = rot(uv) * m.scale;
      return fractf(p.x) < 0.5f ? m.base_color : m.color2;
    }
    case TexKind::Grating: {
      // Sinusoids at 3 octaves (f, 2f, 4f) x 4 orientations 45 deg apart, each orientation
      // with its own phase: detail at many orientations and frequencies. One sincos per
      // orientation; the octaves follow from double-angle identities.
      const float k = 0.70710678f;  // cos 45 = sin 45
      const float c45[4] = {1.f, k, 0.f, -k}, s45[4] = {0.f, k, 1.f, k};
      const float two_pi_f = float(2.0 * kPi) * m.scale;
      float sum = 0.f;
      for (int o = 0; o < 4; ++o) {
        float co = ca * c45[o] - sa * s45[o], so = sa * c45[o] + ca * s45[o];
        float x = two_pi_f * (co * uv.x + so * uv.y);
        float s1 = std::sin(x), c1 = std::cos(x);
        float s2 = 2.f * s1 * c1, c2 = 1.f - 2.f * s1 * s1;
        float s4 = 2.f * s2 * c2, c4 = 1.f - 2.f * s2 * s2;
        // sin(2^j x + ph_o), j = 0..2, phases ph_o = 0.7 o.
        sum += (s1 + s2 + s4) * kGratingPhase[o][0] + (c1 + c2 + c4) * kGratingPhase[o][1];
      }
      float w = clamp01(0.5f + 0.5f * sum / 4.f);
      return glm::mix(m.color2, m.base_color, w);
    }
    case TexKind::Bricks: {
      glm::vec2 p = rot(uv) * m.scale;
      p.x *= 0.5f;  // bricks twice as long as high
      float row = std::floor(p.y);
      if (int32_t(row) & 1) p.x += 0.5f;
      float bx = fractf(p.x), by = fractf(p.y);
      const float mortar = 0.06f;
      if (bx < mortar * 0.5f || by < mortar) return m.color2;
      // Per-brick tint variation (deterministic hash) adds low-frequency detail.
      float v = float(hash2(int32_t(std::floor(p.x)), int32_t(row)) & 0xffff) / 65535.f;
      return m.base_color * (0.8f + 0.4f * v);
    }
    case TexKind::Noise: {
      glm::vec2 p = rot(uv) * m.scale;
      float n = 0.f, amp = 0.5f;
      for (int k = 0; k < 4; ++k, amp *= 0.5f, p *= 2.03f) n += amp * value_noise(p);
      return glm::mix(m.color2, m.base_color, clamp01((n - 0.2f) / 0.6f));
    }
    case TexKind::Radial: {
      // Spokes (angular frequency) x rings (radial frequency) about uv (0.5, 0.5).
      glm::vec2 d = uv - glm::vec2(0.5f);
      float r = glm::length(d);
      float th = std::atan2(d.y, d.x) - m.angle;
      float spokes = std::sin(th * std::round(m.scale * 4.f));
      float rings = std::sin(float(2.0 * kPi) * m.scale * r);
      return (spokes * rings >= 0.f) ? m.base_color : m.color2;
    }
    case TexKind::Image: {
      if (m.image < 0 || size_t(m.image) >= scene.images.size()) return m.base_color;
      return m.base_color * sample_image(scene.images[size_t(m.image)], uv);
    }
  }
  return m.base_color;
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
