#include "sim/scene/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>

#include "sim/core/error.h"
#include "sim/scene/builtin.h"

using namespace fovsim;

namespace {

const std::string kModels = std::string(FOVSIM_SOURCE_DIR) + "/models";
const std::string kTestModels = "/usr/share/assimp/models";

// Builds a scene from {"scene": j} so error locations carry the "scene." prefix.
Scene build(const Json& j, std::string file = "test.json") {
  Params root(Json{{"scene", j}}, std::move(file));
  Params p = root.child("scene");
  Scene s = make_scene(p, kModels);
  root.finish();
  return s;
}

AABB world_bounds(const Scene& s) {
  AABB b;
  for (const Object& o : s.objects)
    for (const glm::vec3& v : s.meshes[size_t(o.mesh)].positions)
      b.extend(glm::vec3(o.transform * glm::vec4(v, 1.f)));
  return b;
}

std::string error_of(const Json& j) {
  try {
    build(j);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

void expect_submodels_partition(const Scene& s, uint32_t max_faces) {
  // Every triangle of every object in exactly one sub-model of <= max_faces.
  std::vector<std::vector<int>> seen(s.objects.size());
  for (size_t o = 0; o < s.objects.size(); ++o)
    seen[o].assign(s.meshes[size_t(s.objects[o].mesh)].triangles.size(), 0);
  for (const SubModel& sm : s.submodels) {
    ASSERT_GE(sm.object, 0);
    ASSERT_LT(size_t(sm.object), s.objects.size());
    EXPECT_LE(sm.tri_count, max_faces);
    EXPECT_GT(sm.tri_count, 0u);
    const Mesh& m = s.meshes[size_t(s.objects[size_t(sm.object)].mesh)];
    for (uint32_t t = sm.first_tri; t < sm.first_tri + sm.tri_count; ++t) {
      ASSERT_LT(t, seen[size_t(sm.object)].size());
      ++seen[size_t(sm.object)][t];
      for (int k = 0; k < 3; ++k) {  // bounds contain the triangle (object space)
        glm::vec3 v = m.positions[m.triangles[t][k]];
        EXPECT_TRUE(glm::all(glm::greaterThanEqual(v, sm.bounds.lo)) &&
                    glm::all(glm::lessThanEqual(v, sm.bounds.hi)));
      }
    }
  }
  for (auto& v : seen)
    for (int c : v) ASSERT_EQ(c, 1);
}

}  // namespace

TEST(SceneImport, BoxTexturedGltf) {
  std::string path = kTestModels + "/glTF2/BoxTextured-glTF/BoxTextured.gltf";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "assimp-testmodels not installed";
  Scene s = build({{"type", "file"}, {"path", path}});
  EXPECT_EQ(s.triangle_count(), 12u);
  AABB b = world_bounds(s);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(b.lo[k], -0.5f, 1e-5f);
    EXPECT_NEAR(b.hi[k], 0.5f, 1e-5f);
  }
  // The diffuse texture (CesiumLogoFlat.png) is loaded through OpenImageIO.
  ASSERT_EQ(s.images.size(), 1u);
  EXPECT_GT(s.images[0].width, 0);
  bool textured = false;
  for (const Material& m : s.materials) textured |= (m.tex == TexKind::Image && m.image == 0);
  EXPECT_TRUE(textured);
  EXPECT_FALSE(s.lights.empty());  // default lights: the file has none
  for (const Mesh& m : s.meshes) {
    EXPECT_EQ(m.normals.size(), m.positions.size());
    EXPECT_EQ(m.uvs.size(), m.positions.size());
  }
  EXPECT_TRUE(s.features().textures);
}

TEST(SceneImport, CylinderEngineGlb) {
  std::string path = kTestModels + "/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "assimp-testmodels not installed";
  Scene s = build({{"type", "file"}, {"path", path}});
  EXPECT_EQ(s.triangle_count(), 121496u);
  AABB b = world_bounds(s);
  glm::vec3 e = b.hi - b.lo;
  // An engine block some hundreds of units long along x (glTF-Sample-Models, mm-ish units).
  EXPECT_GT(e.x, e.y);
  EXPECT_GT(e.x, e.z);
  EXPECT_GT(e.x, 100.f);
  expect_submodels_partition(s, 500);
}

TEST(SceneImport, ObjWithTransformKeys) {
  std::string path = kTestModels + "/OBJ/box.obj";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "assimp-testmodels not installed";
  Scene s = build({{"type", "file"},
                   {"path", path},
                   {"scale", 2.0},
                   {"translate", {1, 2, 3}},
                   {"rotate_deg", {0, 90, 0}}});
  EXPECT_EQ(s.triangle_count(), 12u);
  AABB b = world_bounds(s);
  EXPECT_NEAR(b.lo.x, 0.f, 1e-4f);
  EXPECT_NEAR(b.hi.x, 2.f, 1e-4f);
  EXPECT_NEAR(b.lo.y, 1.f, 1e-4f);
  EXPECT_NEAR(b.hi.y, 3.f, 1e-4f);
  EXPECT_NEAR(b.lo.z, 2.f, 1e-4f);
  EXPECT_NEAR(b.hi.z, 4.f, 1e-4f);
}

TEST(SceneImport, RelativePathResolvesAgainstConfigDir) {
  std::string dir = kTestModels + "/OBJ";
  if (!std::filesystem::exists(dir + "/box.obj")) GTEST_SKIP() << "assimp-testmodels not installed";
  Scene s = build({{"type", "file"}, {"path", "box.obj"}}, dir + "/config.json");
  EXPECT_EQ(s.triangle_count(), 12u);
}

TEST(SceneParams, Errors) {
  std::string e = error_of({{"type", "castle"}});
  EXPECT_NE(e.find("scene.type"), std::string::npos) << e;
  EXPECT_NE(e.find("atrium"), std::string::npos) << e;  // lists the allowed values

  e = error_of({{"type", "file"}, {"path", "/nonexistent/dir/model.gltf"}});
  EXPECT_NE(e.find("scene.path"), std::string::npos) << e;
  EXPECT_NE(e.find("/nonexistent/dir/model.gltf"), std::string::npos) << e;

  e = error_of({{"type", "atrium"}, {"complexity", 99}});
  EXPECT_NE(e.find("scene.complexity"), std::string::npos) << e;

  e = error_of({{"type", "atrium"}, {"complexty", 2}});  // typo -> unknown key
  EXPECT_NE(e.find("complexty"), std::string::npos) << e;

  e = error_of({{"type", "patterns"}, {"pattern", "zebra"}});
  EXPECT_NE(e.find("scene.pattern"), std::string::npos) << e;

  e = error_of(Json::object());
  EXPECT_NE(e.find("scene.type"), std::string::npos) << e;
}

TEST(SceneBuiltin, AtriumComplexityKnob) {
  size_t prev = 0;
  for (int c = 1; c <= kAtriumMaxComplexity; ++c) {
    Params p(Json{{"complexity", c}});
    Scene s = make_atrium(p);  // mesh only: no sub-model split, no BVH
    size_t n = s.triangle_count();
    EXPECT_GT(n, prev) << "complexity " << c;
    prev = n;
    if (c == 1) {
      EXPECT_LT(n, 50000u);
    }
    if (c == kAtriumMaxComplexity) {
      EXPECT_GE(n, 1000000u);
    }
  }
}

TEST(SceneBuiltin, AtriumFeaturesAndSubmodels) {
  Scene s = build({{"type", "atrium"}, {"complexity", 2}, {"dynamic", true}, {"indirect", true}});
  SceneFeatures f = s.features();
  EXPECT_TRUE(f.shadows);
  EXPECT_TRUE(f.textures);
  EXPECT_TRUE(f.dynamic_objects);
  EXPECT_TRUE(f.indirect);
  EXPECT_FALSE(f.moving_lights);
  EXPECT_GE(f.lights, 3);
  EXPECT_EQ(f.triangles, s.triangle_count());
  EXPECT_EQ(f.submodels, s.submodels.size());
  expect_submodels_partition(s, 500);
  // Several texture kinds at several orientations.
  std::set<int> kinds;
  std::set<float> angles;
  for (const Material& m : s.materials) {
    kinds.insert(int(m.tex));
    angles.insert(m.angle);
  }
  EXPECT_GE(kinds.size(), 5u);
  EXPECT_GE(angles.size(), 4u);

  Scene st = build({{"type", "atrium"}, {"complexity", 1}});
  EXPECT_FALSE(st.features().dynamic_objects);
  EXPECT_FALSE(st.features().indirect);
}

TEST(SceneBuiltin, PatternsAndCornell) {
  Scene p = build({{"type", "patterns"}, {"angle", 30}, {"pattern", "checker"}});
  ASSERT_EQ(p.materials.size(), 1u);
  EXPECT_EQ(p.materials[0].tex, TexKind::Checker);
  EXPECT_NEAR(p.materials[0].angle, float(deg2rad(30.0)), 1e-6f);
  Scene c = build({{"type", "cornell"}});
  EXPECT_TRUE(c.wants_indirect);
  EXPECT_TRUE(c.features().indirect);
  EXPECT_EQ(c.lights.size(), 1u);
  expect_submodels_partition(c, 500);
}

TEST(SceneModel, SubmodelSplitKeepsTriangles) {
  Scene s;
  s.materials.push_back(Material{});
  Mesh m;
  for (int i = 0; i < 2000; ++i) {
    float x = float(i % 50), z = float(i / 50);
    uint32_t b = uint32_t(m.positions.size());
    m.positions.push_back({x, 0, z});
    m.positions.push_back({x + 1, 0, z});
    m.positions.push_back({x, 0, z + 1});
    m.triangles.emplace_back(b, b + 1, b + 2);
  }
  s.meshes.push_back(m);
  Object o;
  s.objects.push_back(o);
  std::multiset<std::tuple<uint32_t, uint32_t, uint32_t>> before, after;
  for (auto& t : s.meshes[0].triangles) before.insert({t.x, t.y, t.z});
  s.build_submodels(500);
  for (auto& t : s.meshes[0].triangles) after.insert({t.x, t.y, t.z});
  EXPECT_EQ(before, after);
  EXPECT_EQ(s.submodels.size(), 4u);
  expect_submodels_partition(s, 500);
  s.build_submodels(7);
  expect_submodels_partition(s, 7);
}

TEST(SceneModel, KeyframeInterpolation) {
  Object o;
  Keyframe a, b;
  a.t = 0;
  b.t = 2;
  b.translation = {2, 0, 0};
  b.rotation = glm::angleAxis(float(kPi / 2), glm::vec3(0, 1, 0));
  o.keys = {a, b};
  glm::mat4 m = o.transform_at(1.0);
  EXPECT_NEAR(m[3].x, 1.f, 1e-6f);
  glm::vec3 x = glm::mat3(m) * glm::vec3(1, 0, 0);  // rotated by 45 deg about y
  EXPECT_NEAR(x.x, std::cos(float(kPi / 4)), 1e-5f);
  EXPECT_NEAR(x.z, -std::sin(float(kPi / 4)), 1e-5f);
  EXPECT_NEAR(o.transform_at(-5)[3].x, 0.f, 1e-6f);  // clamped at the ends
  EXPECT_NEAR(o.transform_at(50)[3].x, 2.f, 1e-6f);
}

TEST(SceneTextures, ProceduralPatterns) {
  Scene s;
  Material m;
  m.base_color = glm::vec3(1.f);
  m.color2 = glm::vec3(0.f);
  m.scale = 1.f;
  m.tex = TexKind::Checker;
  EXPECT_EQ(eval_albedo(s, m, {0.25f, 0.25f}).x, 1.f);
  EXPECT_EQ(eval_albedo(s, m, {1.25f, 0.25f}).x, 0.f);
  EXPECT_EQ(eval_albedo(s, m, {1.25f, 1.25f}).x, 1.f);
  m.tex = TexKind::Stripes;  // varies along u only
  EXPECT_EQ(eval_albedo(s, m, {0.25f, 0.1f}).x, eval_albedo(s, m, {0.25f, 7.3f}).x);
  EXPECT_NE(eval_albedo(s, m, {0.25f, 0.1f}).x, eval_albedo(s, m, {0.75f, 0.1f}).x);
  m.angle = float(kPi / 2);  // rotated by 90 deg: varies along v only
  EXPECT_EQ(eval_albedo(s, m, {0.1f, 0.25f}).x, eval_albedo(s, m, {7.3f, 0.25f}).x);
  EXPECT_NE(eval_albedo(s, m, {0.1f, 0.25f}).x, eval_albedo(s, m, {0.1f, 0.75f}).x);
  for (TexKind k : {TexKind::Grating, TexKind::Bricks, TexKind::Noise, TexKind::Radial}) {
    m.tex = k;
    float lo = 1, hi = 0;
    for (int i = 0; i < 400; ++i) {
      glm::vec3 c = eval_albedo(s, m, {0.013f * float(i), 0.5f + 0.0071f * float(i)});
      EXPECT_TRUE(std::isfinite(c.x));
      lo = std::min(lo, c.x);
      hi = std::max(hi, c.x);
    }
    EXPECT_GT(hi - lo, 0.3f) << "texture kind " << int(k) << " has no contrast";
  }
  m.tex = TexKind::Constant;
  m.base_color = {0.2f, 0.3f, 0.4f};
  EXPECT_EQ(eval_albedo(s, m, {3, 4}), m.base_color);
}
