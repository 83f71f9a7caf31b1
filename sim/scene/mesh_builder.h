// Small mesh construction helpers for the procedural scenes (tessellated quads, boxes,
// cylinders, arches, spheres, tori, lathed profiles). UVs are in metres along the surface,
// so a material's `scale` is in cycles per metre.
#pragma once
#include <vector>

#include "sim/scene/scene.h"

namespace fovsim {

class MeshBuilder {
 public:
  explicit MeshBuilder(Mesh& m) : m_(m) {}

  uint32_t vert(const glm::vec3& p, const glm::vec3& n, const glm::vec2& uv);
  void tri(uint32_t a, uint32_t b, uint32_t c, int mat);
  // Parallelogram origin + s*du + t*dv (s,t in [0,1]) split into nu x nv cells; normal along
  // cross(du, dv) (or its opposite when flip). uv = (s*|du|, t*|dv|) + uv0.
  void grid(const glm::vec3& origin, const glm::vec3& du, const glm::vec3& dv, int nu, int nv,
            int mat, bool flip = false, glm::vec2 uv0 = glm::vec2(0.f));
  // Axis-aligned box with outward faces, each face a grid of cells of edge <= cell.
  void box(const glm::vec3& lo, const glm::vec3& hi, int mat, float cell = 1e9f);
  // Vertical cylinder (y up), smooth normals, open ends unless caps.
  void cylinder(const glm::vec3& base, float radius, float height, int facets, int segs, int mat,
                bool caps = false);
  // Surface of revolution about the vertical axis through `base`: profile (r, y) points
  // from bottom to top; smooth normals from the profile.
  void lathe(const glm::vec3& base, const std::vector<glm::vec2>& profile, int facets, int mat);
  void sphere(const glm::vec3& c, float r, int nu, int nv, int mat);
  void torus(const glm::vec3& c, float R, float r, int nu, int nv, int mat);
  // Arcade bay: a wall slab between z0 and z1 (along +z), faces at x = x0 and x0 + depth,
  // with a semicircular opening springing at y_spring, inner radius r (centred in the bay),
  // spandrel up to y_top. `seg` arc segments, `rseg` radial segments on the faces, `dseg`
  // depth segments on the intrados. Materials: faces, intrados.
  void arch_bay(float x0, float depth, float z0, float z1, float y_spring, float r, float y_top,
                int seg, int rseg, int dseg, int mat_face, int mat_intrados);

 private:
  Mesh& m_;
};

}  // namespace fovsim
