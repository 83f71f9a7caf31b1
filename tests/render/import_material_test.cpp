// Imported glTF materials (sim/scene/import.cpp) rendered: alpha cut-out, normal map, PBR and
// emission mapping, on the small files of tests/data/gltf (make_gltf.py states what each holds
// and what to expect).
#include <gtest/gtest.h>

#include "sim/render/renderer.h"

using namespace fovsim;

namespace {

const std::string kData = std::string(FOVSIM_SOURCE_DIR) + "/tests/data/gltf/";

Scene load(const std::string& file) {
  Params p(Json{{"type", "file"}, {"path", kData + file}, {"default_lights", false}});
  return make_scene(p, std::string(FOVSIM_SOURCE_DIR) + "/models");
}

// assimp appends a default material: look materials up by name.
int material_named(const Scene& s, const std::string& name) {
  for (size_t i = 0; i < s.materials.size(); ++i)
    if (s.materials[i].name == name) return int(i);
  ADD_FAILURE() << "no material " << name;
  return 0;
}

Display disp(int w, int h) {
  Display d;
  d.width = w;
  d.height = h;
  d.fov_h_deg = 60;
  d.fov_v_deg = 60;
  return d;
}

}  // namespace

TEST(ImportMaterial, CutoutShowsWhatIsBehindWhereAlphaBelowCutoff) {
  Scene s = load("cutout.gltf");
  const Material& front = s.materials[size_t(material_named(s, "front_cutout"))];
  EXPECT_TRUE(front.cutout());
  EXPECT_FLOAT_EQ(front.alpha_cutoff, 0.5f);
  EXPECT_FALSE(front.transparent);
  ASSERT_GE(front.image, 0);
  EXPECT_FALSE(s.images[size_t(front.image)].alpha.empty());
  s.ambient = glm::vec3(1.f);  // unlit: a pixel shows its albedo
  Renderer r(s, RenderSettings{});
  Display d = disp(64, 64);
  // 2 m in front of the front quad (which spans x in [-1, 1] at z = 0).
  Camera cam = Camera::from_pose(d, {0, 0, 2}, {1, 0, 0, 0});
  GBuffer g;
  r.trace_gbuffer(cam, kShadingChannels | kObjectId, g);
  Image img;
  r.shade(g, cam.position, img);
  // Left of centre (x < 0 on the quad): alpha 0 -> the red back quad; right: green front quad.
  const int y = 32;
  for (int x : {22, 26}) {
    const float* p = img.at(x, y);
    EXPECT_GT(p[0], 0.5f) << x;
    EXPECT_LT(p[1], 0.1f) << x;
    EXPECT_EQ(g.depth[size_t(y * 64 + x)] > 2.5f, true) << x;  // hit at z = -1
  }
  for (int x : {38, 42}) {
    const float* p = img.at(x, y);
    EXPECT_LT(p[0], 0.1f) << x;
    EXPECT_GT(p[1], 0.5f) << x;
    EXPECT_LT(g.depth[size_t(y * 64 + x)], 2.5f) << x;  // hit at z = 0
  }
  // Shadow rays and intersect() see through the cut-out part as well.
  EXPECT_FALSE(r.occluded({-0.5f, 0.f, 0.5f}, {-0.5f, 0.f, -0.5f}));
  EXPECT_TRUE(r.occluded({0.5f, 0.f, 0.5f}, {0.5f, 0.f, -0.5f}));
  EXPECT_NEAR(r.intersect({-0.5f, 0.f, 1.f}, {0, 0, -1}), 2.f, 1e-4);
  EXPECT_NEAR(r.intersect({0.5f, 0.f, 1.f}, {0, 0, -1}), 1.f, 1e-4);
}

TEST(ImportMaterial, NormalMapPbrAndEmission) {
  Scene s = load("normalmap.gltf");
  const int mi = material_named(s, "bumpy");
  const Material& m = s.materials[size_t(mi)];
  ASSERT_GE(m.normal_image, 0);
  // Metallic 0, roughness 0.5: ks 0.04, exponent 2 / 0.0625^2 ... (a = 0.25): 2/a^2 - 2 = 30.
  EXPECT_NEAR(m.specular, 0.04f, 1e-6);
  EXPECT_NEAR(m.shininess, 30.f, 1e-3);
  EXPECT_NEAR(m.emission.x, 0.2f, 1e-6);
  EXPECT_NEAR(m.emission.y, 0.1f, 1e-6);
  // Normal texels stay linear: the flat texel decodes to (0, 0, 1).
  const TextureImage& nt = s.images[size_t(m.normal_image)];
  EXPECT_NEAR(nt.texels[1].z * 2.f - 1.f, 1.f, 0.01f);
  s.materials[size_t(mi)].specular = 0.f;
  s.materials[size_t(mi)].emission = glm::vec3(0.f);
  s.ambient = glm::vec3(0.f);
  Light l;
  l.type = Light::Type::Directional;
  l.direction = glm::normalize(glm::vec3(-1.f, 0.f, -1.f));  // from +x, +z
  l.shadows = false;
  s.lights.push_back(l);
  Renderer r(s, RenderSettings{});
  Display d = disp(64, 64);
  Camera cam = Camera::from_pose(d, {0, 0, 2}, {1, 0, 0, 0});
  GBuffer g;
  r.trace_gbuffer(cam, kShadingChannels, g);
  Image img;
  r.shade(g, cam.position, img);
  // Texel centres: u = 0.25 (tilted to +x, towards the light) and u = 0.75 (flat).
  // The quad spans x in [-1, 1] at distance 2, 60 deg FOV: u = 0.25 at x = -0.5.
  const double px_per_m = 32 / (2 * std::tan(deg2rad(30.0)));
  const int xl = int(32 - 0.5 * px_per_m), xr = int(32 + 0.5 * px_per_m);
  const glm::vec3 nl = g.normal[size_t(32 * 64 + xl)], nr = g.normal[size_t(32 * 64 + xr)];
  EXPECT_GT(nl.x, 0.4f);
  EXPECT_NEAR(nr.x, 0.f, 0.05f);
  EXPECT_GT(img.at(xl, 32)[0], 1.2f * img.at(xr, 32)[0]);
}
