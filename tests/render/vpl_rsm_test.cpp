// Reflective shadow maps and VPL shading (Yang et al. 2021 §3): octahedral mapping, texel measures,
// projection round trips, flux conservation on a floor, the 1/d^2 clamp, zero VPLs.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/core/rng.h"
#include "sim/render/renderer.h"
#include "sim/render/rsm.h"
#include "sim/render/vpl.h"

using namespace fovsim;

namespace {
Scene one_light_scene(Light::Type type) {
  Scene s;
  Material m;
  m.base_color = glm::vec3(0.5f);
  s.materials.push_back(m);
  Light l;
  l.type = type;
  l.position = glm::vec3(0, 1, 0);
  l.direction = glm::vec3(0.3f, -1, 0.1f);
  l.spot_inner_deg = 30;
  l.spot_outer_deg = 40;
  s.lights.push_back(l);
  return s;
}
AABB unit_bounds() {
  AABB b;
  b.extend(glm::vec3(-1.f));
  b.extend(glm::vec3(1.f));
  return b;
}
}  // namespace

TEST(Rsm, OctahedralRoundTrip) {
  Rng r(3);
  for (int i = 0; i < 2000; ++i) {
    glm::vec3 d(float(r.normal()), float(r.normal()), float(r.normal()));
    d = glm::normalize(d);
    glm::vec2 e = oct_encode(d);
    EXPECT_LE(std::fabs(e.x), 1.f + 1e-6f);
    EXPECT_LE(std::fabs(e.y), 1.f + 1e-6f);
    EXPECT_LT(glm::length(oct_decode(e) - d), 1e-5f);
  }
}

TEST(Rsm, TexelMeasuresIntegrateExactly) {
  RSM rsm;
  setup_rsm(one_light_scene(Light::Type::Point), 0, 0.0, 32, unit_bounds(), rsm);
  double sum = 0;
  for (float m : rsm.measure) sum += m;
  EXPECT_NEAR(sum, 4.0 * kPi, 4e-3);  // whole sphere
  setup_rsm(one_light_scene(Light::Type::Spot), 0, 0.0, 32, unit_bounds(), rsm);
  sum = 0;
  for (float m : rsm.measure) sum += m;
  const double T2 = double(rsm.tan_outer) * rsm.tan_outer;
  EXPECT_NEAR(sum, 4.0 * std::asin(T2 / (1.0 + T2)), 2e-3);  // square pyramid
  setup_rsm(one_light_scene(Light::Type::Directional), 0, 0.0, 32, unit_bounds(), rsm);
  sum = 0;
  for (float m : rsm.measure) sum += m;
  EXPECT_NEAR(sum, 4.0 * rsm.half_extent * rsm.half_extent, 1e-3);
}

TEST(Rsm, ProjectInvertsTexelRays) {
  for (auto type : {Light::Type::Point, Light::Type::Spot, Light::Type::Directional}) {
    RSM rsm;
    setup_rsm(one_light_scene(type), 0, 0.0, 16, unit_bounds(), rsm);
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x) {
        glm::vec3 o, d;
        rsm.texel_ray(x + 0.5f, y + 0.5f, o, d);
        glm::vec2 t;
        float depth;
        ASSERT_TRUE(rsm.project(o + 0.7f * d, t, depth));
        EXPECT_EQ(int(t.x), x);
        EXPECT_EQ(int(t.y), y);
        EXPECT_NEAR(
            depth,
            type == Light::Type::Directional ? glm::dot(o + 0.7f * d - rsm.origin, rsm.axis) : 0.7f,
            1e-4f);
      }
  }
  RSM spot;
  setup_rsm(one_light_scene(Light::Type::Spot), 0, 0.0, 16, unit_bounds(), spot);
  glm::vec2 t;
  float depth;
  EXPECT_FALSE(spot.project(spot.ls.position - spot.axis, t, depth));  // behind the spot
}

TEST(Rsm, FloorUnderPointLightReflectsAlbedoTimesHemisphere) {
  Scene s = one_light_scene(Light::Type::Point);
  Mesh m;
  const float e = 200.f;
  m.positions = {{-e, 0, -e}, {e, 0, -e}, {e, 0, e}, {-e, 0, e}};
  m.triangles = {{0, 2, 1}, {0, 3, 2}};
  s.meshes.push_back(m);
  Object o;
  s.objects.push_back(o);
  Renderer r(s, RenderSettings{});
  RSM rsm;
  Counters c;
  render_rsm(r, 0, 64, scene_bounds(r), rsm, &c);
  EXPECT_EQ(c.get(Counter::rsm_texels), 64.0 * 64.0);
  std::vector<VPL> v;
  vpls_from_rsm(rsm, v);
  EXPECT_NEAR(double(v.size()), 64.0 * 64.0 / 2.0, 64.0 * 2);  // the lower hemisphere
  glm::dvec3 flux(0.0);
  for (const VPL& p : v) {
    flux += glm::dvec3(p.flux);
    EXPECT_NEAR(p.position.y, 0.f, 1e-3f);
    EXPECT_NEAR(p.normal.y, 1.f, 1e-5f);  // faces the light
  }
  // Phi = albedo * I * 2 pi (minus the sliver beyond the floor's edge).
  EXPECT_NEAR(flux.x, 0.5 * 2.0 * kPi, 0.5 * 2.0 * kPi * 0.02);
}

TEST(Vpl, SinglePairMatchesFormulaAndClampKeepsFinite) {
  VPL v;
  v.position = glm::vec3(0.f);
  v.normal = glm::vec3(0, 1, 0);
  v.flux = glm::vec3(3.f, 2.f, 1.f);
  VplSoA s = make_soa({v});
  VplShading sh;
  sh.min_dist = 0.1f;
  const glm::vec3 a(0.5f);
  // Receiver 2 above, facing down: cos = 1, 1.
  glm::vec3 L = shade_vpls_point(s, glm::vec3(0, 2, 0), glm::vec3(0, -1, 0), a, sh);
  EXPECT_NEAR(L.x, 0.5 * 3.0 / (kPi * 4.0), 1e-6);
  EXPECT_NEAR(L.z, 0.5 * 1.0 / (kPi * 4.0), 1e-6);
  // Receiver on top of the VPL: bounded by the clamp, finite.
  glm::vec3 near = shade_vpls_point(s, glm::vec3(0, 1e-7f, 0), glm::vec3(0, -1, 0), a, sh);
  EXPECT_TRUE(std::isfinite(near.x));
  EXPECT_LE(near.x, 0.5 * 3.0 / (kPi * 0.01) + 1e-3);
  glm::vec3 on = shade_vpls_point(s, glm::vec3(0.f), glm::vec3(0, -1, 0), a, sh);
  EXPECT_TRUE(std::isfinite(on.x));
  // Behind the VPL: nothing.
  EXPECT_EQ(shade_vpls_point(s, glm::vec3(0, -1, 0), glm::vec3(0, 1, 0), a, sh).x, 0.f);
  // Weights scale linearly; zero VPLs give zero.
  VplSoA w = make_soa({v}, {0}, {2.5f});
  glm::vec3 L2 = shade_vpls_point(w, glm::vec3(0, 2, 0), glm::vec3(0, -1, 0), a, sh);
  EXPECT_NEAR(L2.x, 2.5f * L.x, 1e-6);
  EXPECT_EQ(shade_vpls_point(VplSoA(), glm::vec3(0, 2, 0), glm::vec3(0, -1, 0), a, sh),
            glm::vec3(0.f));
}
