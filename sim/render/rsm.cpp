// Reflective shadow maps by ray casting from the light (Yang et al. 2021 §3 S-1). See rsm.h.
#include "sim/render/rsm.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "sim/core/error.h"
#include "sim/render/renderer.h"

namespace fovsim {

namespace {

void orthonormal_basis(const glm::vec3& n, glm::vec3& t1, glm::vec3& t2) {
  // Duff et al. 2017, branchless ONB.
  float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  t1 = glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  t2 = glm::vec3(b, sign + n.y * n.y * a, -n.y);
}

// Integral of 1/|p|^3 over a texel (midpoint rule on a 4x4 sub-grid): the exact solid-angle
// density of both the octahedral (p = (u, v, 1-|u|-|v|)) and the planar (p = (x, y, 1)) map.
template <class F>
float texel_measure(float x0, float y0, float dx, float dy, F&& pmap) {
  constexpr int kSub = 4;
  double acc = 0;
  for (int j = 0; j < kSub; ++j)
    for (int i = 0; i < kSub; ++i) {
      glm::vec3 p = pmap(x0 + (i + 0.5f) * dx / kSub, y0 + (j + 0.5f) * dy / kSub);
      double l = glm::length(glm::dvec3(p));
      acc += 1.0 / (l * l * l);
    }
  return float(acc * double(dx) * double(dy) / (kSub * kSub));
}

glm::vec3 oct_point(float u, float v) {  // unnormalised octahedron point of e in [-1,1]^2
  glm::vec3 p(u, v, 1.f - std::fabs(u) - std::fabs(v));
  if (p.z < 0.f) {
    float ox = (1.f - std::fabs(v)) * (u >= 0.f ? 1.f : -1.f);
    float oy = (1.f - std::fabs(u)) * (v >= 0.f ? 1.f : -1.f);
    p.x = ox;
    p.y = oy;
  }
  return p;
}

}  // namespace

glm::vec2 oct_encode(const glm::vec3& d) {
  float s = std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z);
  glm::vec3 p = d / (s > 0.f ? s : 1.f);
  glm::vec2 e(p.x, p.y);
  if (p.z < 0.f) {
    e = glm::vec2((1.f - std::fabs(p.y)) * (p.x >= 0.f ? 1.f : -1.f),
                  (1.f - std::fabs(p.x)) * (p.y >= 0.f ? 1.f : -1.f));
  }
  return e;
}

glm::vec3 oct_decode(glm::vec2 e) {
  return glm::normalize(oct_point(e.x, e.y));
}

LightState light_state(const Light& l, double t) {
  LightState s;
  s.type = l.type;
  s.position = l.position;
  s.direction = glm::length(l.direction) > 0.f ? glm::normalize(l.direction) : glm::vec3(0, -1, 0);
  s.radiance = l.color * l.intensity;
  s.shadows = l.shadows;
  float inner = std::min(l.spot_inner_deg, l.spot_outer_deg);
  s.cos_inner = float(std::cos(deg2rad(inner)));
  s.cos_outer = float(std::cos(deg2rad(l.spot_outer_deg)));
  if (!l.keys.empty()) {
    // Same convention as Object::transform_at: keys animate relative to the static placement.
    const Keyframe* a = &l.keys.front();
    const Keyframe* b = a;
    if (t >= l.keys.back().t) {
      a = b = &l.keys.back();
    } else if (t > l.keys.front().t) {
      auto it = std::upper_bound(l.keys.begin(), l.keys.end(), t,
                                 [](double v, const Keyframe& k) { return v < k.t; });
      b = &*it;
      a = &*(it - 1);
    }
    float w = (b != a && b->t > a->t) ? float((t - a->t) / (b->t - a->t)) : 0.f;
    glm::vec3 tr = glm::mix(a->translation, b->translation, w);
    glm::quat q = glm::slerp(a->rotation, b->rotation, w);
    s.position = l.position + tr;
    s.direction = glm::normalize(q * s.direction);
  }
  return s;
}

float spot_falloff(const LightState& l, const glm::vec3& dir) {
  if (l.type != Light::Type::Spot) return 1.f;
  float c = glm::dot(dir, l.direction);
  if (c >= l.cos_inner) return 1.f;
  if (c <= l.cos_outer) return 0.f;
  float x = (c - l.cos_outer) / std::max(1e-6f, l.cos_inner - l.cos_outer);
  return x * x * (3.f - 2.f * x);  // smoothstep
}

void RSM::texel_ray(float fx, float fy, glm::vec3& org, glm::vec3& dir) const {
  const float u = 2.f * fx / float(size) - 1.f, v = 2.f * fy / float(size) - 1.f;
  switch (ls.type) {
    case Light::Type::Point:
      org = ls.position;
      dir = oct_decode(glm::vec2(u, v));
      break;
    case Light::Type::Spot:
      org = ls.position;
      dir = glm::normalize(axis + t1 * (u * tan_outer) + t2 * (v * tan_outer));
      break;
    case Light::Type::Directional:
      org = origin + t1 * (u * half_extent) + t2 * (v * half_extent);
      dir = axis;
      break;
  }
}

bool RSM::project(const glm::vec3& p, glm::vec2& texel, float& light_depth) const {
  glm::vec2 e;
  switch (ls.type) {
    case Light::Type::Point: {
      glm::vec3 d = p - ls.position;
      light_depth = glm::length(d);
      if (!(light_depth > 0.f)) return false;
      e = oct_encode(d / light_depth);
      break;
    }
    case Light::Type::Spot: {
      glm::vec3 d = p - ls.position;
      float z = glm::dot(d, axis);
      if (!(z > 1e-6f)) return false;
      light_depth = glm::length(d);
      e = glm::vec2(glm::dot(d, t1), glm::dot(d, t2)) / (z * tan_outer);
      break;
    }
    case Light::Type::Directional:
    default: {
      glm::vec3 d = p - origin;
      light_depth = glm::dot(d, axis);
      e = glm::vec2(glm::dot(d, t1), glm::dot(d, t2)) / half_extent;
      break;
    }
  }
  if (!(std::fabs(e.x) <= 1.f && std::fabs(e.y) <= 1.f)) return false;
  texel = (e + 1.f) * (0.5f * float(size));
  return true;
}

float RSM::depth_at(const glm::vec2& texel) const {
  int x = std::clamp(int(texel.x), 0, size - 1), y = std::clamp(int(texel.y), 0, size - 1);
  return depth[size_t(y) * size_t(size) + size_t(x)];
}

AABB scene_bounds(const Renderer& r) {
  AABB b;
  const Scene& s = r.scene();
  if (!s.submodels.empty()) {
    for (size_t i = 0; i < s.submodels.size(); ++i) {
      AABB sb = r.submodel_bounds_world(i);
      if (!sb.empty()) {
        b.extend(sb.lo);
        b.extend(sb.hi);
      }
    }
    return b;
  }
  for (const Object& o : s.objects) {
    glm::mat4 m = o.transform_at(r.time());
    for (const glm::vec3& p : s.meshes[size_t(o.mesh)].positions)
      b.extend(glm::vec3(m * glm::vec4(p, 1.f)));
  }
  return b;
}

void setup_rsm(const Scene& scene, int light_index, double t, int size, const AABB& bounds,
               RSM& out) {
  FOVSIM_CHECK(light_index >= 0 && size_t(light_index) < scene.lights.size(),
               "setup_rsm: light index " + std::to_string(light_index) + " out of range");
  if (size < 1) throw Error("rsm", "RSM size must be >= 1, got " + std::to_string(size));
  out.size = size;
  out.light = light_index;
  out.ls = light_state(scene.lights[size_t(light_index)], t);
  const size_t n = out.texels();
  out.depth.assign(n, std::numeric_limits<float>::infinity());
  out.position.assign(n, glm::vec3(0.f));
  out.normal.assign(n, glm::vec3(0.f));
  out.flux.assign(n, glm::vec3(0.f));
  out.measure.assign(n, 0.f);
  out.axis = out.ls.direction;
  orthonormal_basis(out.axis, out.t1, out.t2);
  const float du = 2.f / float(size);
  if (out.ls.type == Light::Type::Spot) {
    float outer = std::acos(std::clamp(out.ls.cos_outer, -1.f, 1.f));
    out.tan_outer = std::tan(std::min(outer, float(deg2rad(89.0))));
  }
  if (out.ls.type == Light::Type::Directional) {
    glm::vec3 c = bounds.empty() ? glm::vec3(0.f) : 0.5f * (bounds.lo + bounds.hi);
    float radius = bounds.empty() ? 1.f : 0.5f * glm::length(bounds.hi - bounds.lo);
    radius = std::max(radius, 1e-3f);
    out.half_extent = radius;
    out.origin = c - out.axis * (2.f * radius);
  }
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const float u0 = -1.f + x * du, v0 = -1.f + y * du;
      float m = 0.f;
      switch (out.ls.type) {
        case Light::Type::Point:
          m = texel_measure(u0, v0, du, du, [](float u, float v) { return oct_point(u, v); });
          break;
        case Light::Type::Spot: {
          const float T = out.tan_outer;
          m = texel_measure(u0 * T, v0 * T, du * T, du * T,
                            [](float a, float b) { return glm::vec3(a, b, 1.f); });
          break;
        }
        case Light::Type::Directional:
          m = (du * out.half_extent) * (du * out.half_extent);
          break;
      }
      out.measure[size_t(y) * size_t(size) + size_t(x)] = m;
    }
}

constexpr float kTexelJitterX = 0.5f + 0.0123457f, kTexelJitterY = 0.5f - 0.0098765f;

void render_rsm(const Renderer& r, int light_index, int size, const AABB& bounds, RSM& out,
                Counters* c) {
  const Scene& scene = r.scene();
  setup_rsm(scene, light_index, r.time(), size, bounds, out);
  tbb::parallel_for(0, size, [&](int y) {
    for (int x = 0; x < size; ++x) {
      const size_t i = size_t(y) * size_t(size) + size_t(x);
      glm::vec3 org, dir;
      // Texel "centres" are offset by a small irrational-looking fraction: a regular grid of
      // rays through exact texel centres over axis-aligned geometry at round coordinates hits
      // edges and corners exactly, where which of two triangles Embree reports depends on its
      // ISA path (BVH width, traversal order). Off the exact centre such ties have measure zero.
      out.texel_ray(x + kTexelJitterX, y + kTexelJitterY, org, dir);
      int obj = -1, prim = -1;
      glm::vec3 n(0.f);
      glm::vec2 uv(0.f);
      float t = r.intersect(org, dir, &obj, &prim, &n, &uv);
      if (!(t < 3.0e38f) || obj < 0) continue;
      const Object& o = scene.objects[size_t(obj)];
      const Mesh& mesh = scene.meshes[size_t(o.mesh)];
      int mi = mesh.material;
      if (prim >= 0 && size_t(prim) < mesh.tri_material.size())
        mi = mesh.tri_material[size_t(prim)];
      const Material& mat =
          scene.materials[size_t(std::clamp(mi, 0, int(scene.materials.size()) - 1))];
      if (glm::dot(n, n) > 0.f) n = glm::normalize(n);
      if (glm::dot(n, dir) > 0.f) n = -n;  // face the light
      out.depth[i] = out.ls.type == Light::Type::Directional
                         ? glm::dot(org + t * dir - out.origin, out.axis)
                         : t;
      out.position[i] = org + t * dir;
      out.normal[i] = n;
      if (mat.transparent) continue;  // no diffuse bounce off glass
      // Flux reaching the patch = I * Omega (E * area for directional), reflected with albedo.
      const glm::vec3 albedo = eval_albedo(scene, mat, uv);
      out.flux[i] = albedo * out.ls.radiance * (out.measure[i] * spot_falloff(out.ls, dir));
    }
  });
  if (c) {
    c->add(Counter::rsm_texels, double(out.texels()));
    c->add(Counter::rsm_rays, double(out.texels()));
  }
}

}  // namespace fovsim
