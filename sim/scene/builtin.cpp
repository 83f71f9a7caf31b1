// Built-in procedural scenes and the make_scene factory. Their keys are declared in
// scene_keys.cpp (one table per scene type; configs/README.md is generated from them).
#include "sim/scene/builtin.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/core/error.h"
#include "sim/core/limits.h"
#include "sim/scene/mesh_builder.h"
#include "sim/scene/scene_keys.h"

namespace fovsim {

namespace {

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

int add_material(Scene& s, Material m) {
  s.materials.push_back(std::move(m));
  return int(s.materials.size() - 1);
}

Material mat(const std::string& name, TexKind tex, glm::vec3 c1, glm::vec3 c2, float scale,
             float angle_deg, float spec = 0.04f, float shin = 32.f) {
  Material m;
  m.name = name;
  m.tex = tex;
  m.base_color = c1;
  m.color2 = c2;
  m.scale = scale;
  m.angle = float(deg2rad(angle_deg));
  m.specular = spec;
  m.shininess = shin;
  return m;
}

// Adds a mesh and one static object instancing it (identity transform).
int add_object(Scene& s, Mesh&& m, const std::string& name, glm::mat4 xf = glm::mat4(1.f)) {
  m.name = name;
  s.meshes.push_back(std::move(m));
  Object o;
  o.name = name;
  o.mesh = int(s.meshes.size() - 1);
  o.transform = xf;
  s.objects.push_back(std::move(o));
  return int(s.objects.size() - 1);
}

glm::vec3 dir_from_angles(double elev_deg, double azim_deg) {
  // Direction the light travels: from the sky (elevation above the horizon, azimuth from -z
  // towards +x) down into the scene.
  double e = deg2rad(elev_deg), a = deg2rad(azim_deg);
  glm::dvec3 to_sun(std::cos(e) * std::sin(a), std::sin(e), -std::cos(e) * std::cos(a));
  return glm::vec3(-glm::normalize(to_sun));
}

}  // namespace

void add_spin_keys(std::vector<Keyframe>& keys, double duration, double period,
                   const glm::vec3& translation, double bob_amplitude) {
  // 16 keys per revolution keep slerp close to a uniform rotation (22.5 deg per key).
  double dt = period / 16.0;
  int n = std::max(2, int(std::ceil(duration / dt)) + 1);
  for (int i = 0; i < n; ++i) {
    Keyframe k;
    k.t = i * dt;
    double a = 2.0 * kPi * k.t / period;
    k.rotation = glm::angleAxis(float(a), glm::vec3(0, 1, 0));
    k.translation = translation + glm::vec3(0, float(bob_amplitude * std::sin(a)), 0);
    keys.push_back(k);
  }
}

AtriumTess atrium_tess(int c) {
  static const AtriumTess t[kAtriumMaxComplexity] = {
      {8, 1, 8, 1, 1, 6, 4.f},     {12, 2, 12, 2, 1, 8, 2.f},     {24, 4, 24, 3, 2, 12, 1.f},
      {40, 8, 40, 5, 3, 16, 0.5f}, {72, 20, 72, 9, 5, 28, 0.35f}, {128, 48, 128, 16, 8, 48, 0.25f},
  };
  c = std::clamp(c, 1, kAtriumMaxComplexity);
  return t[c - 1];
}

// ---- atrium -------------------------------------------------------------------------------
// A two-storey arcaded interior court: checker floor, brick side walls, a back wall with a
// grating, two arcades of columns and semicircular arches per side, a balustraded gallery,
// a coffered ceiling with a skylight through which the sun casts the columns' shadows, a
// pedestal with a (optionally rotating) sculpture, a warm point light under the left arcade
// and a spot light on the sculpture.
// Long because: it is scene data: one block per architectural element
// (materials, floor and walls, arcades, gallery, ceiling, sculpture, lights), each placing
// geometry in metres in the order the triangle counts and goldens depend on. Splitting it
// would only move the coordinates away from the element they describe.
Scene make_atrium(Params& p) {
  const AtriumKeys k = atrium_table().read(p);
  const int complexity = k.complexity;
  const bool dynamic = k.dynamic, moving_light = k.moving_light, indirect = k.indirect;
  const bool sun = k.sun;
  const double sun_elev = k.sun_elevation_deg, sun_azim = k.sun_azimuth_deg;
  const double sun_int = k.sun_intensity, lamp_int = k.lamp_intensity;
  const double spot_int = k.spot_intensity, duration = k.anim_duration, period = k.anim_period;
  const double tex_scale = k.texture_scale;
  p.ignore("comment");

  const AtriumTess ts = atrium_tess(complexity);
  Scene s;
  s.name = "atrium";
  const float ks = float(tex_scale);
  const int m_floor = add_material(s, mat("floor_tiles", TexKind::Checker, {0.75f, 0.72f, 0.66f},
                                          {0.18f, 0.16f, 0.15f}, 1.25f * ks, 45.f, 0.25f, 64.f));
  const int m_wall_l = add_material(s, mat("brick_left", TexKind::Bricks, {0.62f, 0.33f, 0.24f},
                                           {0.82f, 0.80f, 0.74f}, 4.f * ks, 0.f));
  const int m_wall_r = add_material(s, mat("brick_right", TexKind::Bricks, {0.55f, 0.40f, 0.30f},
                                           {0.85f, 0.83f, 0.78f}, 5.f * ks, 90.f));
  const int m_back = add_material(s, mat("back_grating", TexKind::Grating, {0.85f, 0.80f, 0.70f},
                                         {0.25f, 0.22f, 0.20f}, 1.5f * ks, 15.f));
  const int m_front = add_material(s, mat("front_stripes", TexKind::Stripes, {0.80f, 0.78f, 0.70f},
                                          {0.30f, 0.25f, 0.22f}, 3.f * ks, 60.f));
  const int m_col = add_material(s, mat("column_flutes", TexKind::Stripes, {0.90f, 0.88f, 0.82f},
                                        {0.45f, 0.43f, 0.40f}, 12.f * ks, 0.f, 0.3f, 48.f));
  const int m_col2 = add_material(s, mat("column_rings", TexKind::Stripes, {0.86f, 0.84f, 0.78f},
                                         {0.35f, 0.30f, 0.28f}, 8.f * ks, 90.f, 0.3f, 48.f));
  const int m_stone = add_material(s, mat("arch_stone", TexKind::Noise, {0.85f, 0.82f, 0.74f},
                                          {0.45f, 0.42f, 0.38f}, 3.f * ks, 0.f));
  const int m_spandrel =
      add_material(s, mat("spandrel_grating", TexKind::Grating, {0.82f, 0.76f, 0.64f},
                          {0.35f, 0.30f, 0.26f}, 2.5f * ks, 60.f));
  const int m_intrados =
      add_material(s, mat("intrados_checker", TexKind::Checker, {0.80f, 0.30f, 0.22f},
                          {0.90f, 0.86f, 0.78f}, 4.f * ks, 0.f));
  const int m_slab = add_material(s, mat("cornice_stripes", TexKind::Stripes, {0.88f, 0.86f, 0.80f},
                                         {0.40f, 0.36f, 0.32f}, 6.f * ks, -30.f));
  const int m_ceil = add_material(s, mat("ceiling_coffers", TexKind::Checker, {0.70f, 0.66f, 0.58f},
                                         {0.40f, 0.30f, 0.22f}, 1.f * ks, 0.f));
  const int m_bal = add_material(s, mat("baluster_marble", TexKind::Noise, {0.95f, 0.94f, 0.90f},
                                        {0.60f, 0.62f, 0.66f}, 8.f * ks, 30.f, 0.5f, 96.f));
  const int m_ped = add_material(s, mat("pedestal_radial", TexKind::Radial, {0.90f, 0.88f, 0.80f},
                                        {0.15f, 0.14f, 0.20f}, 6.f * ks, 0.f));
  const int m_sculpt =
      add_material(s, mat("sculpture_bronze", TexKind::Checker, {0.75f, 0.50f, 0.20f},
                          {0.20f, 0.12f, 0.05f}, 3.f * ks, 30.f, 0.6f, 128.f));

  // Hall extents (metres). The viewer stands near z = 2 looking down -z.
  const float X = 9.f, Z0 = -24.f, Z1 = 3.f, H = 11.f;
  const float kGap = 1e-3f;  // 1 mm between touching parts (no coplanar overlaps)
  const float xa = 5.f;      // arcade column line at x = +-xa
  const float bay = 3.f, z_first = 1.5f;
  const int bays = 8;
  auto cells = [&](float len) { return std::max(1, int(std::ceil(len / ts.grid_cell))); };

  {  // floor, walls, ceiling with a skylight
    Mesh m;
    MeshBuilder b(m);
    b.grid({-X, 0, Z1}, {2 * X, 0, 0}, {0, 0, Z0 - Z1}, cells(2 * X), cells(Z1 - Z0), m_floor,
           true);
    add_object(s, std::move(m), "floor");
  }
  {
    Mesh m;
    MeshBuilder b(m);
    b.grid({-X, 0, Z0}, {0, 0, Z1 - Z0}, {0, H + 0.3f, 0}, cells(Z1 - Z0), cells(H), m_wall_l);
    add_object(s, std::move(m), "wall_left");
  }
  {
    Mesh m;
    MeshBuilder b(m);
    b.grid({X, 0, Z1}, {0, 0, Z0 - Z1}, {0, H + 0.3f, 0}, cells(Z1 - Z0), cells(H), m_wall_r);
    add_object(s, std::move(m), "wall_right");
  }
  {
    Mesh m;
    MeshBuilder b(m);
    b.grid({-X, 0, Z0}, {2 * X, 0, 0}, {0, H + 0.3f, 0}, cells(2 * X), cells(H), m_back, true);
    add_object(s, std::move(m), "wall_back");
  }
  {
    Mesh m;
    MeshBuilder b(m);
    b.grid({-X, 0, Z1}, {2 * X, 0, 0}, {0, H + 0.3f, 0}, cells(2 * X), cells(H), m_front);
    add_object(s, std::move(m), "wall_front");
  }
  {
    Mesh m;
    MeshBuilder b(m);
    const float sx = 3.5f, sz0 = -17.f, sz1 = -4.f, c = std::max(ts.grid_cell, 0.5f);
    // Boxes stop kGap short of the walls: a face coplanar with a wall makes which surface a
    // ray reports depend on Embree's ISA path (z-fighting), i.e. on the CPU.
    const float x = X - kGap, z0 = Z0 + kGap, z1 = Z1 - kGap;
    b.box({-x, H, z0}, {-sx, H + 0.3f, z1}, m_ceil, c);
    b.box({sx, H, z0}, {x, H + 0.3f, z1}, m_ceil, c);
    b.box({-sx, H, sz1}, {sx, H + 0.3f, z1}, m_ceil, c);
    b.box({-sx, H, z0}, {sx, H + 0.3f, sz0}, m_ceil, c);
    add_object(s, std::move(m), "ceiling");
  }

  // Two storeys of arcades on each side.
  struct Storey {
    float y0, col_h, col_r, y_top, depth;
  };
  const Storey storeys[2] = {{0.f, 4.f, 0.3f, 5.6f, 0.6f}, {5.9f, 3.f, 0.22f, 10.4f, 0.44f}};
  for (int side = 0; side < 2; ++side) {
    const float sgn = side ? 1.f : -1.f;
    for (int st = 0; st < 2; ++st) {
      const Storey& S = storeys[st];
      Mesh cols;
      MeshBuilder cb(cols);
      for (int k = 0; k <= bays; ++k) {
        float z = z_first - bay * float(k);
        glm::vec3 base(sgn * xa, S.y0, z);
        float pl = S.col_r * 1.35f;  // plinth and capital half-size
        cb.box(base + glm::vec3(-pl, 0, -pl), base + glm::vec3(pl, 0.25f, pl), m_stone);
        cb.cylinder(base + glm::vec3(0, 0.25f, 0), S.col_r, S.col_h - 0.5f, ts.column_facets,
                    ts.column_segs, st ? m_col2 : m_col);
        cb.box(base + glm::vec3(-pl, S.col_h - 0.25f, -pl), base + glm::vec3(pl, S.col_h, pl),
               m_stone);
      }
      add_object(s, std::move(cols),
                 std::string(side ? "right" : "left") + "_columns_" + std::to_string(st));
      Mesh arches;
      MeshBuilder ab(arches);
      const float r = 0.5f * bay - S.col_r;
      for (int k = 0; k < bays; ++k) {
        float z1 = z_first - bay * float(k), z0 = z1 - bay;
        ab.arch_bay(sgn * xa - 0.5f * S.depth, S.depth, z0, z1, S.y0 + S.col_h, r, S.y_top,
                    ts.arch_segs, ts.arch_rsegs, ts.arch_dsegs, m_spandrel, m_intrados);
      }
      // Entablature / gallery floor slab behind the arches, wall to wall along z.
      float xin = sgn * xa - sgn * 0.5f * S.depth;
      // kGap short of the walls and the ceiling (no coplanar faces; see the ceiling above).
      float lo = std::min(xin, sgn * (X - kGap)), hi = std::max(xin, sgn * (X - kGap));
      float slab_top = st ? H - kGap : S.y_top + 0.3f;
      ab.box({lo, S.y_top, Z0 + kGap}, {hi, slab_top, Z1 - kGap}, m_slab,
             std::max(ts.grid_cell, 0.5f));
      add_object(s, std::move(arches),
                 std::string(side ? "right" : "left") + "_arcade_" + std::to_string(st));
    }
    // Balustrade along the gallery edge, between the upper columns.
    Mesh bal;
    MeshBuilder bb(bal);
    const float yb = storeys[1].y0;
    std::vector<glm::vec2> prof = {{0.055f, 0.f},  {0.055f, 0.06f}, {0.04f, 0.08f},
                                   {0.035f, 0.2f}, {0.06f, 0.32f},  {0.075f, 0.42f},
                                   {0.06f, 0.52f}, {0.035f, 0.62f}, {0.03f, 0.68f},
                                   {0.05f, 0.72f}, {0.055f, 0.78f}, {0.055f, 0.8f}};
    for (int k = 0; k < bays; ++k) {
      float z1 = z_first - bay * float(k) - storeys[1].col_r - 0.15f;
      float z0 = z_first - bay * float(k + 1) + storeys[1].col_r + 0.15f;
      int n = int(std::floor((z1 - z0) / 0.22f)) + 1;
      for (int i = 0; i < n; ++i) {
        float z = z0 + (z1 - z0) * (float(i) + 0.5f) / float(n);
        bb.lathe({sgn * xa, yb, z}, prof, ts.baluster_facets, m_bal);
      }
      bb.box({sgn * xa - 0.09f, yb + 0.8f, z0 - 0.1f}, {sgn * xa + 0.09f, yb + 0.9f, z1 + 0.1f},
             m_bal);
    }
    add_object(s, std::move(bal), std::string(side ? "right" : "left") + "_balustrade");
  }

  // Pedestal and sculpture in the middle of the court.
  const glm::vec3 centre(0.f, 0.f, -10.5f);
  {
    Mesh m;
    MeshBuilder b(m);
    b.box(centre + glm::vec3(-0.7f, 0, -0.7f), centre + glm::vec3(0.7f, 1.0f, 0.7f), m_ped);
    add_object(s, std::move(m), "pedestal");
  }
  {
    Mesh m;
    MeshBuilder b(m);
    int f = std::max(12, ts.column_facets);
    b.torus({0, 0, 0}, 0.55f, 0.16f, f, std::max(8, f / 2), m_sculpt);
    b.sphere({0, 0, 0}, 0.28f, f, std::max(6, f / 2), m_sculpt);
    glm::vec3 pos = centre + glm::vec3(0, 1.75f, 0);
    // Tilted so the spin about +y is visible as motion everywhere on the torus.
    glm::mat4 tilt = glm::mat4_cast(glm::angleAxis(float(deg2rad(25.0)), glm::vec3(1, 0, 0)));
    int oi = add_object(s, std::move(m), "sculpture");
    Object& o = s.objects[size_t(oi)];
    if (dynamic) {
      o.transform = glm::mat4(1.f);
      add_spin_keys(o.keys, duration, period, pos, 0.15);
      // Keys rotate about y; apply the tilt in object space by baking it into the mesh.
      Mesh& mm = s.meshes[size_t(o.mesh)];
      for (auto& v : mm.positions) v = glm::vec3(tilt * glm::vec4(v, 1.f));
      for (auto& n : mm.normals) n = glm::vec3(tilt * glm::vec4(n, 0.f));
    } else {
      glm::mat4 tr(1.f);
      tr[3] = glm::vec4(pos, 1.f);
      o.transform = tr * tilt;
    }
  }

  // Lights.
  if (sun) {
    Light l;
    l.type = Light::Type::Directional;
    l.direction = dir_from_angles(sun_elev, sun_azim);
    l.color = {1.0f, 0.95f, 0.85f};
    l.intensity = float(sun_int);
    l.shadows = true;
    s.lights.push_back(l);
  }
  {
    Light l;
    l.type = Light::Type::Point;
    l.position = {-7.f, 3.6f, -9.f};
    l.color = {1.0f, 0.75f, 0.45f};
    l.intensity = float(lamp_int);
    l.shadows = true;
    if (moving_light) {
      // Walks along the left arcade and back (period anim_period * 2).
      double T = 2.0 * period;
      int n = std::max(2, int(std::ceil(duration / (T / 8.0))) + 1);
      for (int i = 0; i < n; ++i) {
        Keyframe k;
        k.t = i * T / 8.0;
        double ph = std::sin(2.0 * kPi * k.t / T);
        k.translation = glm::vec3(0, 0, float(8.0 * ph));
        l.keys.push_back(k);
      }
    }
    s.lights.push_back(l);
  }
  {
    Light l;
    l.type = Light::Type::Spot;
    l.position = centre + glm::vec3(2.5f, 9.5f, 3.f);
    l.direction = glm::normalize(centre + glm::vec3(0, 1.5f, 0) - l.position);
    l.color = {0.85f, 0.9f, 1.0f};
    l.intensity = float(spot_int);
    l.spot_inner_deg = 10.f;
    l.spot_outer_deg = 16.f;
    l.shadows = true;
    s.lights.push_back(l);
  }
  s.ambient = glm::vec3(0.05f, 0.05f, 0.06f);
  s.background = glm::vec3(0.55f, 0.7f, 0.95f);  // sky through the skylight
  s.wants_indirect = indirect;
  s.exposure = 1.0;
  s.default_eye = {0.f, 1.6f, 2.0f};
  return s;
}

// ---- patterns -----------------------------------------------------------------------------
// RMFR's rotating-patterns test (Ye et al. 2022 §6.1, Fig. 12): a plane filling the view, facing
// the viewer at `distance`, with a high-frequency pattern rotated by `angle` degrees about
// the view axis. The paper's three pattern images are not published; `pattern` selects a
// procedural stand-in (stripes ~ (a), checker ~ (b), grating ~ (c)).
Scene make_patterns(Params& p) {
  const PatternsKeys keys = patterns_table().read(p);
  const double angle = keys.angle, freq = keys.frequency, dist = keys.distance, size = keys.size;
  const double contrast = keys.contrast;
  const std::string& pattern = keys.pattern;
  p.ignore("comment");

  Scene s;
  s.name = "patterns";
  TexKind k = TexKind::Stripes;
  if (pattern == "checker")
    k = TexKind::Checker;
  else if (pattern == "grating")
    k = TexKind::Grating;
  else if (pattern == "bricks")
    k = TexKind::Bricks;
  else if (pattern == "noise")
    k = TexKind::Noise;
  else if (pattern == "radial")
    k = TexKind::Radial;
  float c = float(contrast);
  glm::vec3 hi(0.5f + 0.45f * c), lo(0.5f - 0.45f * c);
  Material m = mat("pattern_" + pattern, k, hi, lo, float(freq), float(angle), 0.f, 1.f);
  if (k == TexKind::Radial) m.scale = float(freq) / 4.f;
  int mi = add_material(s, m);
  s.default_eye = {0.f, 1.6f, 0.f};
  // Large enough to fill a 120-degree view with head motion to spare.
  float half = size > 0 ? float(size) * 0.5f : float(dist) * 4.f;
  Mesh mesh;
  MeshBuilder b(mesh);
  glm::vec3 ctr = s.default_eye + glm::vec3(0, 0, -float(dist));
  // uv origin at the plane centre (+0.5 so the radial pattern is centred there).
  b.grid(ctr + glm::vec3(-half, -half, 0), {2 * half, 0, 0}, {0, 2 * half, 0}, 8, 8, mi, false,
         glm::vec2(0.5f - half));
  add_object(s, std::move(mesh), "pattern_plane");
  Light l;
  l.type = Light::Type::Directional;
  l.direction = {0, 0, -1};
  l.intensity = 1.f;
  l.shadows = false;
  s.lights.push_back(l);
  s.ambient = glm::vec3(0.f);
  s.background = glm::vec3(0.5f);
  return s;
}

// ---- cornell ------------------------------------------------------------------------------
Scene make_cornell(Params& p, double max_triangles) {
  const CornellKeys k = cornell_table().read(p);
  const double light_int = k.light_intensity, tess = k.cell;
  const std::string& light_type = k.light;
  const bool textured = k.textured;
  p.ignore("comment");
  {
    // Counted before anything is tessellated: five 2 m walls and two boxes of 1.2 m at most
    // per side, two triangles per cell.
    const double w = std::max(1.0, std::ceil(2.0 / tess)), b = std::max(1.0, std::ceil(1.2 / tess));
    const double estimate = 2.0 * (5.0 * w * w + 12.0 * b * b);
    if (estimate > max_triangles)
      p.fail("cell", "cell " + num(tess) + " m tessellates the scene into about " + num(estimate) +
                         " triangles, over scene.max_triangles = " + num(max_triangles) +
                         " (use a larger cell or raise scene.max_triangles)");
  }

  Scene s;
  s.name = "cornell";
  const int m_white =
      add_material(s, mat("white", TexKind::Constant, glm::vec3(0.73f), {}, 1, 0, 0.02f));
  const int m_red =
      add_material(s, mat("red", TexKind::Constant, {0.63f, 0.065f, 0.05f}, {}, 1, 0, 0.02f));
  const int m_green =
      add_material(s, mat("green", TexKind::Constant, {0.14f, 0.45f, 0.09f}, {}, 1, 0, 0.02f));
  int m_box = m_white;
  if (textured)
    m_box = add_material(s, mat("box_checker", TexKind::Checker, glm::vec3(0.75f), glm::vec3(0.2f),
                                8.f, 20.f, 0.02f));
  Material em = mat("light", TexKind::Constant, glm::vec3(0.78f), {}, 1, 0, 0.f);
  em.emission = glm::vec3(float(light_int) * 2.f);
  const int m_emit = add_material(s, em);

  const float c = float(tess);
  auto n = [&](float len) { return std::max(1, int(std::ceil(len / c))); };
  {
    Mesh m;
    MeshBuilder b(m);
    b.grid({-1, 0, 0}, {2, 0, 0}, {0, 0, -2}, n(2), n(2), m_white, true);  // floor
    b.grid({-1, 2, -2}, {2, 0, 0}, {0, 0, 2}, n(2), n(2), m_white, true);  // ceiling
    b.grid({-1, 0, -2}, {2, 0, 0}, {0, 2, 0}, n(2), n(2), m_white);        // back
    add_object(s, std::move(m), "white_walls");
  }
  {
    Mesh m;
    MeshBuilder b(m);
    b.grid({-1, 0, 0}, {0, 0, -2}, {0, 2, 0}, n(2), n(2), m_red);
    add_object(s, std::move(m), "red_wall");
  }
  {
    Mesh m;
    MeshBuilder b(m);
    b.grid({1, 0, -2}, {0, 0, 2}, {0, 2, 0}, n(2), n(2), m_green);
    add_object(s, std::move(m), "green_wall");
  }
  auto box_obj = [&](const std::string& name, glm::vec3 half, glm::vec3 pos, float rot_deg) {
    Mesh m;
    MeshBuilder b(m);
    b.box(-half + glm::vec3(0, half.y, 0), half + glm::vec3(0, half.y, 0), m_box, c);
    glm::mat4 xf(1.f);
    xf[3] = glm::vec4(pos, 1.f);
    xf = xf * glm::mat4_cast(glm::angleAxis(float(deg2rad(rot_deg)), glm::vec3(0, 1, 0)));
    add_object(s, std::move(m), name, xf);
  };
  box_obj("tall_box", {0.3f, 0.6f, 0.3f}, {-0.35f, 0.f, -1.3f}, 17.f);
  box_obj("short_box", {0.3f, 0.3f, 0.3f}, {0.35f, 0.f, -0.75f}, -17.f);
  {
    Mesh m;
    MeshBuilder b(m);
    b.grid({-0.25f, 1.999f, -1.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}, 1, 1, m_emit, true);
    add_object(s, std::move(m), "light_panel");
  }
  Light l;
  l.type = light_type == "spot" ? Light::Type::Spot : Light::Type::Point;
  l.position = {0.f, 1.9f, -1.0f};
  l.direction = {0, -1, 0};
  l.spot_inner_deg = 50.f;
  l.spot_outer_deg = 70.f;
  l.intensity = float(light_int);
  l.shadows = true;
  s.lights.push_back(l);
  s.ambient = glm::vec3(0.01f);
  s.background = glm::vec3(0.f);
  s.wants_indirect = true;
  s.default_eye = {0.f, 1.f, 0.9f};
  return s;
}

// ---- checks -------------------------------------------------------------------------------
namespace {

// Every vertex of every object in world space finite and within kMaxCoordinateM; triangles
// of zero area counted (a scene with nothing else renders blank). Keyframed objects are
// checked at their keys.
void check_geometry(const Scene& s, Params& p, const std::string& key) {
  size_t zero_area = 0, total = 0;
  AABB bounds;
  for (const Object& o : s.objects) {
    const Mesh& m = s.meshes[size_t(o.mesh)];
    std::vector<glm::mat4> xfs{o.transform};
    for (const Keyframe& k : o.keys) xfs.push_back(o.transform_at(k.t));
    for (const glm::mat4& xf : xfs)
      for (size_t i = 0; i < m.positions.size(); ++i) {
        const glm::vec3 w = glm::vec3(xf * glm::vec4(m.positions[i], 1.f));
        for (int c = 0; c < 3; ++c) {
          const glm::vec3 local = m.positions[i];
          if (!std::isfinite(local[c]) || !std::isfinite(w[c]))
            p.fail(key, "object \"" + o.name + "\": vertex " + std::to_string(i) +
                            " has a non-finite coordinate (" + num(local[c]) + " in the mesh, " +
                            num(w[c]) + " in the world)");
          if (!(std::fabs(w[c]) <= kMaxCoordinateM))
            p.fail(key, "object \"" + o.name + "\": vertex " + std::to_string(i) + " is at " +
                            num(w[c]) + " m in the world, beyond the coordinate bound +-1e5 m");
        }
      }
    // Areas after the object's transform: a node scale of 0 or a scene.scale that rounds to
    // 0 in single precision (1e-300) flattens triangles that have area in the mesh.
    for (const glm::uvec3& t : m.triangles) {
      ++total;
      const glm::vec3 a = xfs[0] * glm::vec4(m.positions[t.x], 1.f),
                      b = xfs[0] * glm::vec4(m.positions[t.y], 1.f),
                      c = xfs[0] * glm::vec4(m.positions[t.z], 1.f);
      if (!(glm::length(glm::cross(b - a, c - a)) > 0.f)) ++zero_area;
      bounds.extend(a);
      bounds.extend(b);
      bounds.extend(c);
    }
  }
  if (total > 0 && zero_area == total)
    p.fail(key, "all " + std::to_string(total) +
                    " triangles have zero area in the world, after every transform (nothing "
                    "would be rendered; check scene.scale and the model's node scales)");
  const double extent = total > 0 ? double(glm::length(bounds.hi - bounds.lo)) : 1.0;
  if (!(extent >= kMinSceneExtentM))
    p.fail(key, "the scene is " + num(extent) + " m across after every transform, under " +
                    num(kMinSceneExtentM) +
                    " m (degenerate: check scene.scale and the model's node scales)");
}

// Colours and lights as the renderer will use them: every component finite and in
// [0, kMaxColorValue] (a glTF factor of 1e39 overflows a float to infinity, an OBJ Kd may be
// "nan"); lights finite with a non-negative intensity.
void check_materials_and_lights(const Scene& s, Params& p, const std::string& key) {
  auto bad = [](float v) { return !(v >= 0.f && v <= float(kMaxColorValue)); };
  for (size_t i = 0; i < s.materials.size(); ++i) {
    const Material& m = s.materials[i];
    const std::string name =
        "material " + std::to_string(i) + (m.name.empty() ? "" : " \"" + m.name + "\"");
    const std::pair<const char*, glm::vec3> colours[] = {
        {"base colour", m.base_color}, {"second colour", m.color2}, {"emission", m.emission}};
    for (const auto& [what, c] : colours)
      for (int k = 0; k < 3; ++k)
        if (bad(c[k]))
          p.fail(key, name + ": " + what + " component " + num(c[k]) +
                          " is not a finite value in [0, " + num(kMaxColorValue) + "]");
    for (const auto& [what, v] : {std::pair<const char*, float>{"specular", m.specular},
                                  {"shininess", m.shininess},
                                  {"alpha", m.alpha},
                                  {"normal scale", std::fabs(m.normal_scale)}})
      if (bad(v))
        p.fail(key, name + ": " + what + " " + num(v) + " is not a finite value in [0, " +
                        num(kMaxColorValue) + "]");
  }
  for (size_t i = 0; i < s.lights.size(); ++i) {
    const Light& l = s.lights[i];
    bool ok = std::isfinite(l.intensity) && l.intensity >= 0.f && std::isfinite(l.spot_inner_deg) &&
              std::isfinite(l.spot_outer_deg);
    for (int k = 0; k < 3; ++k)
      ok = ok && std::isfinite(l.position[k]) && std::isfinite(l.direction[k]) && !bad(l.color[k]);
    if (!ok)
      p.fail(key, "light " + std::to_string(i) +
                      ": a non-finite or negative position, direction, colour or intensity");
  }
}

}  // namespace

// ---- factory ------------------------------------------------------------------------------
Scene make_scene(Params& p, const std::string& models_dir) {
  const SceneKeys keys = scene_table().read(p);
  const std::string& type = keys.type;
  const double max_tris = keys.max_triangles;
  Scene s;
  if (type == "atrium")
    s = make_atrium(p);
  else if (type == "patterns")
    s = make_patterns(p);
  else if (type == "cornell")
    s = make_cornell(p, max_tris);
  else
    s = load_file_scene(p, models_dir);
  if (double(s.triangle_count()) > max_tris)
    p.fail("max_triangles", "the scene has " + std::to_string(s.triangle_count()) +
                                " triangles, over the limit of " + num(max_tris) +
                                " (raise scene.max_triangles)");
  check_geometry(s, p, type == "file" ? "path" : "type");
  check_materials_and_lights(s, p, type == "file" ? "path" : "type");
  for (int c = 0; c < 3; ++c)
    if (!(std::fabs(s.default_eye[c]) <= kMaxCoordinateM))
      p.fail("default_eye", "eye point coordinate " + num(s.default_eye[c]) +
                                " is beyond the coordinate bound +-1e5 m");
  // Common key `vpl`: how the frame's VPL set is generated (only for scenes with indirect light,
  // so a scene without it has no VPL pass anywhere).
  if (p.has("vpl")) {
    if (!s.wants_indirect)
      p.fail("vpl", "this scene has no indirect light (atrium: set \"indirect\": true)");
    Params vp = p.child("vpl");
    VplKeys v;
    for (const char* key : {"rsm_size", "min_dist", "shadow_rays"})
      vpl_table().find(key)->read(vp, v);
    s.vpl.rsm_size = v.rsm_size;
    s.vpl.min_dist = v.min_dist;
    s.vpl.shadow_rays = v.shadow_rays;
  }
  // Work bounded before it is spent: every reference pixel is shaded by every VPL, and a
  // frame has up to lights x rsm_size^2 of them (configs/README.md "Limits on input").
  if (s.wants_indirect) {
    Params vp = p.child("vpl");
    VplKeys v;  // max_vpls is read for every scene with indirect light, `vpl` given or not
    vpl_table().find("max_vpls")->read(vp, v);
    const double max_vpls = v.max_vpls;
    const double lights = double(std::max<size_t>(1, s.lights.size()));
    const double vpls = lights * double(s.vpl.rsm_size) * double(s.vpl.rsm_size);
    if (vpls > max_vpls)
      vp.fail(p.has("vpl") && vp.has("rsm_size") ? "rsm_size" : "max_vpls",
              "rsm_size " + std::to_string(s.vpl.rsm_size) + " gives up to " + num(lights) +
                  " light(s) x " + std::to_string(s.vpl.rsm_size) + "^2 = " + num(vpls) +
                  " VPLs per frame, over scene.vpl.max_vpls = " + num(max_vpls) +
                  " (every reference pixel is shaded by every VPL: lower scene.vpl.rsm_size or "
                  "raise scene.vpl.max_vpls)");
  }
  s.build_submodels(500);
  return s;
}

}  // namespace fovsim
