#include "sim/scene/mesh_builder.h"

#include <algorithm>
#include <cmath>

namespace fovsim {

uint32_t MeshBuilder::vert(const glm::vec3& p, const glm::vec3& n, const glm::vec2& uv) {
  m_.positions.push_back(p);
  m_.normals.push_back(n);
  m_.uvs.push_back(uv);
  return uint32_t(m_.positions.size() - 1);
}

void MeshBuilder::tri(uint32_t a, uint32_t b, uint32_t c, int mat) {
  m_.triangles.emplace_back(a, b, c);
  m_.tri_material.push_back(mat);
}

void MeshBuilder::grid(const glm::vec3& origin, const glm::vec3& du, const glm::vec3& dv, int nu,
                       int nv, int mat, bool flip, glm::vec2 uv0) {
  nu = std::max(1, nu);
  nv = std::max(1, nv);
  glm::vec3 n = glm::normalize(glm::cross(du, dv));
  if (flip) n = -n;
  const float lu = glm::length(du), lv = glm::length(dv);
  const uint32_t first = uint32_t(m_.positions.size());
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) {
      float s = float(i) / float(nu), t = float(j) / float(nv);
      vert(origin + s * du + t * dv, n, uv0 + glm::vec2(s * lu, t * lv));
    }
  auto id = [&](int i, int j) { return first + uint32_t(j * (nu + 1) + i); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (flip) {
        tri(a, c, b, mat);
        tri(a, d, c, mat);
      } else {
        tri(a, b, c, mat);
        tri(a, c, d, mat);
      }
    }
}

void MeshBuilder::box(const glm::vec3& lo, const glm::vec3& hi, int mat, float cell) {
  glm::vec3 e = hi - lo;
  auto cells = [&](float len) { return std::max(1, int(std::ceil(len / cell - 1e-4f))); };
  glm::vec3 X(e.x, 0, 0), Y(0, e.y, 0), Z(0, 0, e.z);
  // cross(du, dv) points outward for each face.
  grid(lo, Z, Y, cells(e.z), cells(e.y), mat);      // -x
  grid(lo + X, Y, Z, cells(e.y), cells(e.z), mat);  // +x
  grid(lo, X, Z, cells(e.x), cells(e.z), mat);      // -y
  grid(lo + Y, Z, X, cells(e.z), cells(e.x), mat);  // +y
  grid(lo, Y, X, cells(e.y), cells(e.x), mat);      // -z
  grid(lo + Z, X, Y, cells(e.x), cells(e.y), mat);  // +z
}

void MeshBuilder::cylinder(const glm::vec3& base, float radius, float height, int facets, int segs,
                           int mat, bool caps) {
  std::vector<glm::vec2> prof;
  for (int j = 0; j <= segs; ++j) prof.emplace_back(radius, height * float(j) / float(segs));
  lathe(base, prof, facets, mat);
  if (caps) {
    for (int top = 0; top < 2; ++top) {
      glm::vec3 c = base + glm::vec3(0, top ? height : 0.f, 0);
      glm::vec3 n(0, top ? 1.f : -1.f, 0);
      uint32_t ci = vert(c, n, {0, 0});
      uint32_t first = uint32_t(m_.positions.size());
      for (int i = 0; i < facets; ++i) {
        float a = float(2.0 * kPi) * float(i) / float(facets);
        glm::vec2 d(std::cos(a), std::sin(a));
        vert(c + glm::vec3(d.x * radius, 0, d.y * radius), n, d * radius);
      }
      for (int i = 0; i < facets; ++i) {
        uint32_t a = first + uint32_t(i), b = first + uint32_t((i + 1) % facets);
        if (top)
          tri(ci, b, a, mat);
        else
          tri(ci, a, b, mat);
      }
    }
  }
}

void MeshBuilder::lathe(const glm::vec3& base, const std::vector<glm::vec2>& prof, int facets,
                        int mat) {
  const int np = int(prof.size());
  if (np < 2 || facets < 3) return;
  // Arc length along the profile for v; u is arc length around the mean circumference.
  std::vector<float> vlen(size_t(np), 0.f);
  float rmean = 0.f;
  for (int j = 0; j < np; ++j) {
    if (j)
      vlen[size_t(j)] = vlen[size_t(j - 1)] + glm::length(prof[size_t(j)] - prof[size_t(j - 1)]);
    rmean += prof[size_t(j)].x / float(np);
  }
  const uint32_t first = uint32_t(m_.positions.size());
  for (int j = 0; j < np; ++j) {
    glm::vec2 t = prof[size_t(std::min(j + 1, np - 1))] - prof[size_t(std::max(j - 1, 0))];
    glm::vec2 n2 = glm::normalize(glm::vec2(t.y, -t.x));  // outward normal in (r, y)
    for (int i = 0; i <= facets; ++i) {
      float a = float(2.0 * kPi) * float(i) / float(facets);
      float c = std::cos(a), s = std::sin(a);
      glm::vec3 p =
          base + glm::vec3(c * prof[size_t(j)].x, prof[size_t(j)].y, s * prof[size_t(j)].x);
      glm::vec3 n = glm::normalize(glm::vec3(c * n2.x, n2.y, s * n2.x));
      vert(p, n, {a * rmean, vlen[size_t(j)]});
    }
  }
  auto id = [&](int i, int j) { return first + uint32_t(j * (facets + 1) + i); };
  for (int j = 0; j + 1 < np; ++j)
    for (int i = 0; i < facets; ++i) {
      uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      tri(a, c, b, mat);
      tri(a, d, c, mat);
    }
}

void MeshBuilder::sphere(const glm::vec3& c, float r, int nu, int nv, int mat) {
  std::vector<glm::vec2> prof;
  for (int j = 0; j <= nv; ++j) {
    float th = float(kPi) * (float(j) / float(nv) - 0.5f);
    prof.emplace_back(std::max(r * std::cos(th), 1e-6f), r * std::sin(th));
  }
  lathe(c, prof, nu, mat);
}

void MeshBuilder::torus(const glm::vec3& c, float R, float r, int nu, int nv, int mat) {
  std::vector<glm::vec2> prof;
  for (int j = 0; j <= nv; ++j) {
    float th = float(2.0 * kPi) * float(j) / float(nv) - float(kPi) * 0.5f;
    prof.emplace_back(R + r * std::cos(th), r * std::sin(th));
  }
  lathe(c, prof, nu, mat);
}

void MeshBuilder::arch_bay(float x0, float depth, float z0, float z1, float y_spring, float r,
                           float y_top, int seg, int rseg, int dseg, int mat_face,
                           int mat_intrados) {
  const float zc = 0.5f * (z0 + z1), hw = 0.5f * (z1 - z0), ht = y_top - y_spring;
  // Arc angles from pi (z0 side) to 0, plus the two angles that hit the spandrel's top
  // corners, so the outer boundary follows the rectangle exactly.
  std::vector<float> th;
  for (int i = 0; i <= seg; ++i) th.push_back(float(kPi) * (1.f - float(i) / float(seg)));
  float tc = std::atan2(ht, hw);
  th.push_back(tc);
  th.push_back(float(kPi) - tc);
  std::sort(th.begin(), th.end(), [](float a, float b) { return a > b; });
  th.erase(
      std::unique(th.begin(), th.end(), [](float a, float b) { return std::abs(a - b) < 1e-6f; }),
      th.end());
  auto outer = [&](float a) {
    float c = std::cos(a), s = std::sin(a);
    float t = 1e30f;
    if (std::abs(c) > 1e-7f) t = std::min(t, hw / std::abs(c));
    if (s > 1e-7f) t = std::min(t, ht / s);
    return glm::vec2(zc + c * t, y_spring + s * t);
  };
  for (int face = 0; face < 2; ++face) {
    float x = face ? x0 + depth : x0;
    glm::vec3 n(face ? 1.f : -1.f, 0, 0);
    const uint32_t first = uint32_t(m_.positions.size());
    for (float a : th) {
      glm::vec2 in(zc + r * std::cos(a), y_spring + r * std::sin(a)), out = outer(a);
      for (int k = 0; k <= rseg; ++k) {
        glm::vec2 p = glm::mix(in, out, float(k) / float(rseg));
        vert({x, p.y, p.x}, n, {p.x, p.y});
      }
    }
    auto id = [&](size_t i, int k) { return first + uint32_t(i * size_t(rseg + 1) + size_t(k)); };
    for (size_t i = 0; i + 1 < th.size(); ++i)
      for (int k = 0; k < rseg; ++k) {
        uint32_t a = id(i, k), b = id(i + 1, k), c = id(i + 1, k + 1), d = id(i, k + 1);
        if (face) {
          tri(a, b, c, mat_face);
          tri(a, c, d, mat_face);
        } else {
          tri(a, c, b, mat_face);
          tri(a, d, c, mat_face);
        }
      }
  }
  // Intrados: the curved underside of the arch, normals towards the arch centre.
  const uint32_t first = uint32_t(m_.positions.size());
  float arc_len = float(kPi) * r;
  for (int i = 0; i <= seg; ++i) {
    float a = float(kPi) * (1.f - float(i) / float(seg));
    glm::vec3 n(0, -std::sin(a), -std::cos(a));
    for (int k = 0; k <= dseg; ++k) {
      float x = x0 + depth * float(k) / float(dseg);
      vert({x, y_spring + r * std::sin(a), zc + r * std::cos(a)}, n,
           {arc_len * float(i) / float(seg), x - x0});
    }
  }
  for (int i = 0; i < seg; ++i)
    for (int k = 0; k < dseg; ++k) {
      uint32_t a = first + uint32_t(i * (dseg + 1) + k), b = a + uint32_t(dseg + 1);
      tri(a, b, b + 1, mat_intrados);
      tri(a, b + 1, a + 1, mat_intrados);
    }
}

}  // namespace fovsim
