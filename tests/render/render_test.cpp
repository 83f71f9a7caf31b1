#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string>

#include "sim/core/error.h"
#include "sim/render/embree_device.h"
#include "sim/render/renderer.h"
#include "sim/scene/mesh_builder.h"

using namespace fovsim;

namespace {

const std::string kModels = std::string(FOVSIM_SOURCE_DIR) + "/models";

Display small_display(int w = 96, int h = 72, double fh = 90, double fv = 75) {
  Display d;
  d.width = w;
  d.height = h;
  d.fov_h_deg = fh;
  d.fov_v_deg = fv;
  return d;
}

int add_constant_material(Scene& s, glm::vec3 c, float spec = 0.f) {
  Material m;
  m.base_color = c;
  m.specular = spec;
  s.materials.push_back(m);
  return int(s.materials.size() - 1);
}

void add_mesh_object(Scene& s, Mesh&& m) {
  s.meshes.push_back(std::move(m));
  Object o;
  o.mesh = int(s.meshes.size() - 1);
  s.objects.push_back(o);
}

// A large plane z = -d facing +z (towards a camera at the origin looking down -z).
Scene plane_scene(float d, glm::vec3 albedo = glm::vec3(0.5f)) {
  Scene s;
  int mi = add_constant_material(s, albedo);
  Mesh m;
  MeshBuilder b(m);
  b.grid({-100, -100, -d}, {200, 0, 0}, {0, 200, 0}, 4, 4, mi);
  add_mesh_object(s, std::move(m));
  s.ambient = glm::vec3(0.f);
  s.build_submodels();
  return s;
}

Camera cam_at(const Display& d, glm::dvec3 pos = {0, 0, 0}, glm::dquat q = {1, 0, 0, 0}) {
  return Camera::from_pose(d, pos, q);
}

Scene atrium_small(bool dynamic = false) {
  Params p(Json{{"type", "atrium"}, {"complexity", 2}, {"dynamic", dynamic}});
  return make_scene(p, kModels);
}

}  // namespace

TEST(Render, PlaneDepthIsDistanceOverCos) {
  const float d = 3.f;
  Scene s = plane_scene(d);
  Renderer r(s, RenderSettings{});
  Display disp = small_display();
  // A tilted head so rays hit the plane at many angles.
  Camera cam = cam_at(disp, {0, 0, 0}, glm::angleAxis(0.2, glm::dvec3(0, 1, 0)));
  GBuffer g;
  r.trace_gbuffer(cam, kDepth, g);
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      glm::dvec3 dir = cam.dir_world(x + 0.5, y + 0.5);
      double expect = d / -dir.z;
      float got = g.depth[size_t(y) * size_t(cam.width) + size_t(x)];
      ASSERT_NEAR(got, expect, 1e-4 * expect) << x << "," << y;
    }
}

TEST(Render, SphereSilhouetteMatchesAnalyticDisc) {
  Scene s;
  int mi = add_constant_material(s, glm::vec3(0.5f));
  const float R = 1.f, D = 4.f;
  Mesh m;
  MeshBuilder b(m);
  b.sphere({0, 0, -D}, R, 512, 256, mi);
  add_mesh_object(s, std::move(m));
  s.build_submodels();
  Renderer r(s, RenderSettings{});
  Display disp = small_display(200, 200, 60, 60);
  Camera cam = cam_at(disp);
  GBuffer g;
  r.trace_gbuffer(cam, kDepth | kObjectId, g);
  // The silhouette of a sphere centred on the view axis is a circle of radius
  // tan(asin(R/D)) on the z = -1 image plane.
  const double rho = std::tan(std::asin(R / D));
  const double px_area = (2 * cam.tan_half_h / cam.width) * (2 * cam.tan_half_v / cam.height);
  size_t hits = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      size_t i = size_t(y) * size_t(cam.width) + size_t(x);
      bool hit = g.hit(i);
      hits += hit;
      EXPECT_EQ(g.object_id[i], hit ? 0 : -1);
      glm::dvec3 dir = cam.dir_head(x + 0.5, y + 0.5);
      double rr = std::hypot(dir.x / -dir.z, dir.y / -dir.z);
      double margin = 2.0 * (2 * cam.tan_half_h / cam.width);  // two pixels
      if (rr < rho - margin) {
        EXPECT_TRUE(hit) << x << "," << y;
      }
      if (rr > rho + margin) {
        EXPECT_FALSE(hit) << x << "," << y;
      }
    }
  const double analytic = kPi * rho * rho;
  EXPECT_NEAR(double(hits) * px_area / analytic, 1.0, 0.01);
}

TEST(Render, OnlyRequestedChannelsAllocated) {
  Scene s = plane_scene(2.f);
  Renderer r(s, RenderSettings{});
  Camera cam = cam_at(small_display(32, 24));
  GBuffer g;
  r.trace_gbuffer(cam, kDepth, g);
  EXPECT_EQ(g.depth.size(), g.size());
  EXPECT_TRUE(g.position.empty() && g.normal.empty() && g.albedo.empty() && g.material.empty() &&
              g.object_id.empty() && g.submodel.empty() && g.motion.empty() && g.uv.empty());
  r.trace_gbuffer(cam, kNormal | kUV, g);
  EXPECT_EQ(g.normal.size(), g.size());
  EXPECT_EQ(g.uv.size(), g.size());
  EXPECT_TRUE(g.position.empty() && g.albedo.empty() && g.motion.empty());
  r.trace_gbuffer(cam, kDepth, g);  // dropping a channel releases it
  EXPECT_TRUE(g.normal.empty() && g.uv.capacity() == 0);
  GBuffer full;
  full.resize(4, 4, kShadingChannels | kObjectId);
  GBuffer part;
  part.resize(2, 1, kDepth | kObjectId);
  full.depth[5] = 1.5f;
  full.object_id[5] = 7;
  part.copy_sample(full, 5, 1);
  EXPECT_EQ(part.depth[1], 1.5f);
  EXPECT_EQ(part.object_id[1], 7);
  part.clear_sample(1);
  EXPECT_FALSE(part.hit(1));
  EXPECT_EQ(part.object_id[1], -1);
}

TEST(Render, NormalsFaceViewerAndTracePointsMatch) {
  Scene s = atrium_small();
  Renderer r(s, RenderSettings{});
  Camera cam = cam_at(small_display(80, 60, 100, 90), glm::dvec3(s.default_eye));
  GBuffer g;
  r.trace_gbuffer(cam, kShadingChannels | kObjectId | kSubModel | kUV, g);
  size_t hits = 0;
  std::vector<glm::vec2> pts;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      size_t i = size_t(y) * size_t(cam.width) + size_t(x);
      pts.emplace_back(float(x) + 0.5f, float(y) + 0.5f);
      if (!g.hit(i)) continue;
      ++hits;
      glm::vec3 dir(cam.dir_world(x + 0.5, y + 0.5));
      EXPECT_LE(glm::dot(g.normal[i], dir), 1e-6f);
      EXPECT_NEAR(glm::length(g.normal[i]), 1.f, 1e-4f);
      ASSERT_GE(g.submodel[i], 0);
      EXPECT_EQ(s.submodels[size_t(g.submodel[i])].object, g.object_id[i]);
      glm::vec3 expect_pos = glm::vec3(cam.position) + g.depth[i] * dir;
      EXPECT_NEAR(glm::distance(g.position[i], expect_pos), 0.f, 1e-4f * (1.f + g.depth[i]));
    }
  EXPECT_GT(hits, g.size() / 2);
  GBuffer gp;
  r.trace_points(cam, pts, kShadingChannels | kObjectId, gp);
  ASSERT_EQ(gp.size(), g.size());
  for (size_t i = 0; i < g.size(); ++i) {
    ASSERT_EQ(gp.depth[i], g.depth[i]);
    if (g.hit(i)) {
      EXPECT_EQ(gp.object_id[i], g.object_id[i]);
      EXPECT_EQ(gp.albedo[i], g.albedo[i]);
    }
  }
}

// The packet pass stages each packet's samples and copies runs of consecutive output slots:
// every channel must land in its own slot whatever the order of the points (shuffled: no runs;
// scanline: runs of 16; reversed: runs of 1), bit for bit as the G-buffer pass writes it.
TEST(Render, TracePointsInAnyOrderMatchTheGBufferBits) {
  Scene s = atrium_small();
  Renderer r(s, RenderSettings{});
  Camera cam = cam_at(small_display(37, 23, 100, 90), glm::dvec3(s.default_eye));
  const uint32_t ch = kShadingChannels | kObjectId | kSubModel | kUV | kFootprint;
  GBuffer g;
  r.trace_gbuffer(cam, ch, g);
  std::vector<size_t> order(g.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::vector<std::vector<size_t>> orders{order, order};
  std::reverse(orders[1].begin(), orders[1].end());
  orders.push_back(order);
  for (size_t i = 0; i < order.size(); ++i)  // a fixed shuffle (no std::shuffle: portable)
    std::swap(orders[2][i], orders[2][(i * 7919u + 13u) % order.size()]);
  for (const auto& ord : orders) {
    std::vector<glm::vec2> pts;
    for (size_t j : ord)
      pts.emplace_back(float(j % size_t(cam.width)) + 0.5f, float(j / size_t(cam.width)) + 0.5f);
    GBuffer gp;
    r.trace_points(cam, pts, ch, gp);
    size_t hits = 0;
    for (size_t k = 0; k < ord.size(); ++k) {
      const size_t i = ord[k];
      ASSERT_EQ(std::memcmp(&gp.depth[k], &g.depth[i], sizeof(float)), 0) << k;
      EXPECT_EQ(gp.material[k], g.material[i]);
      EXPECT_EQ(gp.object_id[k], g.object_id[i]);
      EXPECT_EQ(gp.submodel[k], g.submodel[i]);
      EXPECT_EQ(std::memcmp(&gp.position[k], &g.position[i], sizeof(glm::vec3)), 0);
      EXPECT_EQ(std::memcmp(&gp.normal[k], &g.normal[i], sizeof(glm::vec3)), 0);
      EXPECT_EQ(std::memcmp(&gp.uv[k], &g.uv[i], sizeof(glm::vec2)), 0);
      // Albedo and footprint depend on the cone width, equal here (spacing 1).
      EXPECT_EQ(std::memcmp(&gp.albedo[k], &g.albedo[i], sizeof(glm::vec3)), 0);
      EXPECT_EQ(std::memcmp(&gp.footprint[k], &g.footprint[i], sizeof(float)), 0);
      hits += g.hit(i);
    }
    EXPECT_GT(hits, ord.size() / 2);
  }
}

TEST(Render, ShadeMatchesShadeSample) {
  // shade() traces shadow rays in packets; shade_sample() one by one: same image.
  Scene s = atrium_small();
  Renderer r(s, RenderSettings{});
  Camera cam = cam_at(small_display(64, 48, 100, 90), glm::dvec3(s.default_eye),
                      glm::angleAxis(-0.3, glm::dvec3(0, 1, 0)));
  GBuffer g;
  Image img;
  r.trace_gbuffer(cam, kShadingChannels, g);
  r.shade(g, cam.position, img);
  size_t differ = 0;
  for (size_t i = 0; i < g.size(); ++i) {
    glm::vec3 c = r.shade_sample(g, i, glm::vec3(cam.position));
    differ += c.x != img.data[i * 3] || c.y != img.data[i * 3 + 1] || c.z != img.data[i * 3 + 2];
  }
  EXPECT_EQ(differ, 0u);
}

TEST(Render, PacketWideGBufferPathGivesThePerSampleBits) {
  // Hits on static objects with uvs and no normal map are refined and given their position,
  // uv, footprint and normal several lanes at a time; with kMotion requested every hit takes
  // the per-sample path (SampleWriter::hit). Both must write the same bits, on a static and a
  // dynamic scene (whose instanced objects always take the per-sample path).
  for (bool dynamic : {false, true}) {
    Scene s = atrium_small(dynamic);
    Renderer r(s, RenderSettings{});
    r.set_time(0.4);
    for (double yaw : {-0.3, 1.2, 2.6}) {
      Camera cam = cam_at(small_display(80, 64, 100, 90), glm::dvec3(s.default_eye),
                          glm::angleAxis(yaw, glm::dvec3(0, 1, 0)));
      const uint32_t ch = ~0u & ~uint32_t(kMotion);
      GBuffer a, b;
      r.trace_gbuffer(cam, ch, a);
      r.trace_gbuffer(cam, ch | kMotion, b, nullptr, &cam);
      auto same = [](const auto& x, const auto& y) {
        return x.size() == y.size() &&
               std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
      };
      EXPECT_TRUE(same(a.depth, b.depth)) << dynamic << " " << yaw;
      EXPECT_TRUE(same(a.position, b.position)) << dynamic << " " << yaw;
      EXPECT_TRUE(same(a.normal, b.normal)) << dynamic << " " << yaw;
      EXPECT_TRUE(same(a.albedo, b.albedo)) << dynamic << " " << yaw;
      EXPECT_TRUE(same(a.uv, b.uv)) << dynamic << " " << yaw;
      EXPECT_TRUE(same(a.footprint, b.footprint)) << dynamic << " " << yaw;
      EXPECT_TRUE(same(a.material, b.material)) << dynamic << " " << yaw;
      EXPECT_TRUE(same(a.object_id, b.object_id)) << dynamic << " " << yaw;
      EXPECT_TRUE(same(a.submodel, b.submodel)) << dynamic << " " << yaw;
      size_t hits = 0;
      for (size_t i = 0; i < a.size(); ++i) hits += a.hit(i);
      EXPECT_GT(hits, a.size() / 2);
    }
  }
}

TEST(Render, LambertPlaneUnderDirectionalLight) {
  const glm::vec3 albedo(0.5f, 0.25f, 0.125f);
  Scene s = plane_scene(2.f, albedo);
  Light l;
  l.type = Light::Type::Directional;
  const double inc = deg2rad(60.0);  // incidence angle from the plane normal (+z)
  l.direction = -glm::vec3(float(std::sin(inc)), 0.f, float(std::cos(inc)));
  l.intensity = 2.f;
  l.color = glm::vec3(1.f);
  s.lights.push_back(l);
  Renderer r(s, RenderSettings{});
  Camera cam = cam_at(small_display(40, 30));
  GBuffer g;
  Image img;
  Counters c;
  r.trace_gbuffer(cam, kShadingChannels, g, &c);
  r.shade(g, cam.position, img, nullptr, &c);
  glm::vec3 expect = albedo * float(std::cos(inc)) * 2.f;
  for (size_t i = 0; i < g.size(); ++i)
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(img.data[i * 3 + size_t(k)], expect[k], 1e-5f);
  EXPECT_EQ(c.get(Counter::primary_rays), double(g.size()));
  EXPECT_EQ(c.get(Counter::shaded_samples), double(g.size()));
  EXPECT_EQ(c.get(Counter::shadow_rays), double(g.size()));
  // shade_sample agrees with shade().
  glm::vec3 one = r.shade_sample(g, 17, glm::vec3(cam.position));
  EXPECT_EQ(one.x, img.data[17 * 3]);
}

TEST(Render, ShadowedPointIsDarker) {
  Scene s;
  int mi = add_constant_material(s, glm::vec3(0.6f));
  Mesh m;
  MeshBuilder b(m);
  b.grid({-10, 0, 10}, {20, 0, 0}, {0, 0, -20}, 2, 2, mi, true);  // floor y = 0, facing up
  b.box({-0.5f, 1.f, -3.5f}, {0.5f, 1.2f, -2.5f}, mi);            // a slab floating above it
  add_mesh_object(s, std::move(m));
  s.ambient = glm::vec3(0.05f);
  Light l;
  l.type = Light::Type::Directional;
  l.direction = {0, -1, 0};
  l.intensity = 1.f;
  s.lights.push_back(l);
  s.build_submodels();
  // Look straight down from above at the floor: points under the slab are in its shadow.
  Display d = small_display(64, 64, 90, 90);
  Camera cam = cam_at(d, {3, 5, -3}, glm::angleAxis(-kPi / 2, glm::dvec3(1, 0, 0)));
  glm::dvec2 px_shadow, px_lit;
  ASSERT_TRUE(cam.project_world({0.0, 0.0, -3.0}, px_shadow));  // under the slab
  ASSERT_TRUE(cam.project_world({5.0, 0.0, -3.0}, px_lit));
  std::vector<glm::vec2> pts = {glm::vec2(px_shadow), glm::vec2(px_lit)};
  for (bool shadows : {true, false}) {
    RenderSettings rs;
    rs.shadows = shadows;
    Renderer r(s, rs);
    GBuffer g;
    r.trace_points(cam, pts, kShadingChannels, g);
    ASSERT_TRUE(g.hit(0) && g.hit(1));
    ASSERT_NEAR(g.position[0].y, 0.f, 1e-4f);  // the floor point is visible from the camera
    glm::vec3 a = r.shade_sample(g, 0, glm::vec3(cam.position));
    glm::vec3 c = r.shade_sample(g, 1, glm::vec3(cam.position));
    if (shadows) {
      EXPECT_LT(a.x, 0.5f * c.x);
      EXPECT_NEAR(a.x, 0.05f * 0.6f, 1e-5f);  // ambient only
      EXPECT_TRUE(r.occluded({0, 0.01f, -3}, {0, 5, -3}));
      EXPECT_FALSE(r.occluded({5, 0.01f, -3}, {5, 5, -3}));
    } else {
      EXPECT_NEAR(a.x, c.x, 1e-5f);
    }
  }
}

TEST(Render, PointAndSpotLightFalloff) {
  Scene s = plane_scene(2.f, glm::vec3(1.f));
  Light p;
  p.type = Light::Type::Point;
  p.position = {0, 0, -1};  // 1 m in front of the plane
  p.intensity = 3.f;
  p.shadows = false;
  s.lights.push_back(p);
  Renderer r(s, RenderSettings{});
  Camera cam = cam_at(small_display(33, 33, 60, 60));
  std::vector<glm::vec2> pts = {{16.5f, 16.5f}};
  GBuffer g;
  r.trace_points(cam, pts, kShadingChannels, g);
  EXPECT_NEAR(r.shade_sample(g, 0, glm::vec3(0)).x, 3.f, 1e-4f);  // I / d^2, cos = 1
  Scene s2 = plane_scene(2.f, glm::vec3(1.f));
  Light sp = p;
  sp.type = Light::Type::Spot;
  sp.direction = {1, 0, 0};  // pointing away: the plane point straight ahead is outside
  s2.lights.push_back(sp);
  Renderer r2(s2, RenderSettings{});
  r2.trace_points(cam, pts, kShadingChannels, g);
  EXPECT_NEAR(r2.shade_sample(g, 0, glm::vec3(0)).x, 0.f, 1e-6f);
}

TEST(Render, IntersectAndMissBackground) {
  Scene s = plane_scene(5.f);
  s.background = {0.1f, 0.2f, 0.3f};
  Renderer r(s, RenderSettings{});
  int obj = -2, prim = -2;
  glm::vec3 n;
  float t = r.intersect({0, 0, 0}, {0, 0, -2}, &obj, &prim, &n);
  EXPECT_NEAR(t, 5.f, 1e-5f);
  EXPECT_EQ(obj, 0);
  EXPECT_GE(prim, 0);
  EXPECT_NEAR(n.z, 1.f, 1e-6f);
  EXPECT_TRUE(std::isinf(r.intersect({0, 0, 0}, {0, 0, 1}, &obj)));
  EXPECT_EQ(obj, -1);
  Camera cam = cam_at(small_display(8, 8), {0, 0, 0}, glm::angleAxis(kPi, glm::dvec3(0, 1, 0)));
  GBuffer g;
  Image img;
  r.trace_gbuffer(cam, kShadingChannels, g);
  r.shade(g, cam.position, img);
  EXPECT_FALSE(g.hit(0));
  EXPECT_EQ(img.data[0], 0.1f);
  EXPECT_EQ(img.data[2], 0.3f);
}

TEST(Render, ShadeMaskLeavesOthers) {
  Scene s = plane_scene(2.f);
  s.ambient = glm::vec3(1.f);
  Renderer r(s, RenderSettings{});
  Camera cam = cam_at(small_display(16, 8));
  GBuffer g;
  r.trace_gbuffer(cam, kShadingChannels, g);
  Image img(16, 8, 3, -7.f);
  std::vector<uint8_t> mask(g.size(), 0);
  mask[3] = 1;
  Counters c;
  r.shade(g, cam.position, img, mask.data(), &c);
  EXPECT_EQ(img.data[3 * 3], 0.5f);
  EXPECT_EQ(img.data[4 * 3], -7.f);
  EXPECT_EQ(c.get(Counter::shaded_samples), 1.0);
}

TEST(Render, DeterministicAcrossRunsAndThreadCounts) {
  Scene s = atrium_small(true);
  Display d = small_display(120, 100, 100, 100);
  Camera cam = cam_at(d, glm::dvec3(s.default_eye), glm::angleAxis(0.3, glm::dvec3(0, 1, 0)));
  Camera prev = cam_at(d, glm::dvec3(s.default_eye) + glm::dvec3(0.05, 0, 0),
                       glm::angleAxis(0.28, glm::dvec3(0, 1, 0)));
  const uint32_t ch = kShadingChannels | kObjectId | kSubModel | kMotion | kUV;
  auto render = [&](int threads, GBuffer& g, Image& img) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, size_t(threads));
    RenderSettings rs;
    rs.tile = 16;
    Renderer r(s, rs);
    r.set_time(0.9);
    r.set_time(1.0);
    r.trace_gbuffer(cam, ch, g, nullptr, &prev);
    r.shade(g, cam.position, img);
  };
  GBuffer g1, g2, g3;
  Image i1, i2, i3;
  render(2, g1, i1);
  render(2, g2, i2);
  render(1, g3, i3);
  auto same_bits = [](const auto& a, const auto& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
  };
  for (const GBuffer* o : {&g2, &g3}) {
    EXPECT_TRUE(same_bits(g1.depth, o->depth));
    EXPECT_TRUE(same_bits(g1.normal, o->normal));
    EXPECT_TRUE(same_bits(g1.albedo, o->albedo));
    EXPECT_TRUE(same_bits(g1.motion, o->motion));
    EXPECT_TRUE(same_bits(g1.submodel, o->submodel));
  }
  EXPECT_TRUE(same_bits(i1.data, i2.data));
  EXPECT_TRUE(same_bits(i1.data, i3.data));
}

TEST(Render, MotionOfStaticAndDynamicGeometry) {
  Scene s = atrium_small(true);
  int sculpt = -1;
  for (size_t i = 0; i < s.objects.size(); ++i)
    if (s.objects[i].dynamic()) sculpt = int(i);
  ASSERT_GE(sculpt, 0);
  Display d = small_display(96, 96, 60, 60);
  glm::dvec3 eye(0.0, 1.8, -6.0);  // near the pedestal, looking at the sculpture
  Camera cam = cam_at(d, eye);
  Camera prev = cam_at(d, eye + glm::dvec3(0.02, 0, 0));
  Renderer r(s, RenderSettings{});
  r.set_time(2.0);
  r.set_time(2.1);
  GBuffer g;
  r.trace_gbuffer(cam, kPosition | kObjectId | kMotion, g, nullptr, &prev);
  int dyn = 0;
  for (int y = 0; y < d.height; ++y)
    for (int x = 0; x < d.width; ++x) {
      size_t i = size_t(y) * size_t(d.width) + size_t(x);
      if (!g.hit(i)) continue;
      if (g.object_id[i] == sculpt) {
        ++dyn;
        continue;
      }
      // Static: motion = current pixel - previous camera's projection of the same point.
      glm::dvec2 pp;
      ASSERT_TRUE(prev.project_world(glm::dvec3(g.position[i]), pp));
      EXPECT_NEAR(g.motion[i].x, x + 0.5 - pp.x, 2e-3);
      EXPECT_NEAR(g.motion[i].y, y + 0.5 - pp.y, 2e-3);
    }
  EXPECT_GT(dyn, 50);
  // Time moves the dynamic object: its pixels change between t = 2.1 and t = 4.
  GBuffer g2;
  r.set_time(4.0);
  r.trace_gbuffer(cam, kPosition | kObjectId, g2);
  size_t changed = 0;
  for (size_t i = 0; i < g.size(); ++i)
    changed += (g.object_id[i] == sculpt) != (g2.object_id[i] == sculpt) ||
               (g.object_id[i] == sculpt && g.depth[i] != g2.depth[i]);
  EXPECT_GT(changed, 10u);
  // Sub-model bounds follow the object.
  for (size_t i = 0; i < s.submodels.size(); ++i) {
    AABB b = r.submodel_bounds_world(i);
    EXPECT_FALSE(b.empty());
  }
}

TEST(Render, ToneMapMonotoneInUnitRange) {
  const int n = 2000;
  Image lin(n, 1, 1);
  for (int i = 0; i < n; ++i) lin.data[size_t(i)] = std::pow(10.f, -4.f + 8.f * float(i) / n);
  for (auto curve : {ToneMap::Curve::Aces, ToneMap::Curve::Reinhard, ToneMap::Curve::Clamp}) {
    ToneMap tm;
    tm.curve = curve;
    tm.exposure = 1.5;
    Image out;
    tm.apply(lin, out);
    ASSERT_EQ(out.data.size(), lin.data.size());
    for (int i = 0; i < n; ++i) {
      ASSERT_GE(out.data[size_t(i)], 0.f);
      ASSERT_LE(out.data[size_t(i)], 1.f);
      if (i) {
        ASSERT_GE(out.data[size_t(i)], out.data[size_t(i - 1)]);
      }
    }
    EXPECT_GT(out.data[size_t(n - 1)], 0.95f);
  }
  Image odd(4, 1, 1);
  odd.data = {-1.f, std::nanf(""), std::numeric_limits<float>::infinity(), 0.f};
  Image out;
  ToneMap{}.apply(odd, out);
  EXPECT_EQ(out.data[0], 0.f);
  EXPECT_EQ(out.data[1], 0.f);
  EXPECT_EQ(out.data[2], 1.f);
  EXPECT_EQ(out.data[3], 0.f);
}

TEST(Render, SettingsFromParams) {
  Params p(Json{{"render", {{"shadows", false}, {"tile", 16}}}}, "cfg.json");
  Params rp = p.child("render");
  RenderSettings s = RenderSettings::from_params(rp);
  EXPECT_FALSE(s.shadows);
  EXPECT_EQ(s.tile, 16);
  Params bad(Json{{"render", {{"tile", 0}}}}, "cfg.json");
  Params bp = bad.child("render");
  try {
    RenderSettings::from_params(bp);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("render.tile"), std::string::npos);
  }
}

namespace {
// The quickstart's atrium (complexity 1) with its rotating sculpture: the scene on which
// Embree's coherent 16-wide packets never returned after a top-level recommit.
Scene atrium_dynamic_c1() {
  Params p(Json{{"type", "atrium"}, {"complexity", 1}, {"dynamic", true}});
  return make_scene(p, kModels);
}

// Runs f with FOVSIM_EMBREE_ISA set to isa ("" = unset), restoring the variable afterwards.
template <class F>
void with_embree_isa(const std::string& isa, F f) {
  const char* old = std::getenv("FOVSIM_EMBREE_ISA");
  const std::string saved = old ? old : "";
  if (isa.empty())
    ::unsetenv("FOVSIM_EMBREE_ISA");
  else
    ::setenv("FOVSIM_EMBREE_ISA", isa.c_str(), 1);
  f();
  if (old)
    ::setenv("FOVSIM_EMBREE_ISA", saved.c_str(), 1);
  else
    ::unsetenv("FOVSIM_EMBREE_ISA");
}
}  // namespace

// Regression (issue: make test hung on AVX2-only CPUs): construct, recommit the instanced top
// level (set_time), then trace and shade with shadow packets, several frames. With the coherent
// packet flag this never returned (ctest's per-test timeout turns that into a failure).
TEST(Render, DynamicSceneShadowPacketsAfterRecommit) {
  Scene s = atrium_dynamic_c1();
  Display d = small_display(96, 104, 100, 110);
  Renderer r(s, RenderSettings{});
  GBuffer g;
  Image img;
  for (double t : {0.0, 0.0, 0.011, 0.5}) {
    r.set_time(t);
    Camera cam = cam_at(d, glm::dvec3(s.default_eye), glm::angleAxis(-0.05, glm::dvec3(0, 1, 0)));
    r.trace_gbuffer(cam, kShadingChannels, g);
    r.shade(g, cam.position, img);
  }
  double sum = 0;
  for (float v : img.data) sum += v;
  EXPECT_GT(sum, 0.0);
}

// Every Embree ISA path this CPU has gives the same bits: G-buffer (hits refined in double
// precision), shading (occlusion decided on the refined t) and the dynamic scene after
// recommits. Only a ray through an exact silhouette edge could still differ (none here).
TEST(Render, IdenticalBitsOnEveryEmbreeIsa) {
  Scene s = atrium_dynamic_c1();
  Display d = small_display(120, 100, 100, 100);
  const uint32_t ch = kShadingChannels | kObjectId | kSubModel | kUV;
  struct Out {
    GBuffer g;
    Image img;
    float t_hit = 0;
  };
  auto render = [&](Out& o) {
    Renderer r(s, RenderSettings{});
    r.set_time(0.25);
    r.set_time(0.5);
    Camera cam = cam_at(d, glm::dvec3(s.default_eye), glm::angleAxis(0.3, glm::dvec3(0, 1, 0)));
    r.trace_gbuffer(cam, ch, o.g);
    r.shade(o.g, cam.position, o.img);
    o.t_hit = r.intersect(glm::vec3(s.default_eye), glm::vec3(0.1f, -0.2f, -1.f));
  };
  auto same_bits = [](const auto& a, const auto& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
  };
  std::vector<std::string> isas = embree_supported_isas();
  ASSERT_FALSE(isas.empty());
  Out base;
  with_embree_isa(isas.front(), [&] { render(base); });
  for (size_t k = 1; k < isas.size(); ++k) {
    Out o;
    with_embree_isa(isas[k], [&] { render(o); });
    SCOPED_TRACE("embree isa " + isas[k] + " vs " + isas.front());
    EXPECT_TRUE(same_bits(base.g.depth, o.g.depth));
    EXPECT_TRUE(same_bits(base.g.position, o.g.position));
    EXPECT_TRUE(same_bits(base.g.normal, o.g.normal));
    EXPECT_TRUE(same_bits(base.g.albedo, o.g.albedo));
    EXPECT_TRUE(same_bits(base.g.uv, o.g.uv));
    EXPECT_TRUE(same_bits(base.g.object_id, o.g.object_id));
    EXPECT_TRUE(same_bits(base.img.data, o.img.data));
    EXPECT_EQ(base.t_hit, o.t_hit);
  }
}

TEST(Render, EmbreeIsaFromEnvironment) {
  with_embree_isa("avx9", [] {
    try {
      embree_forced_isa();
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      EXPECT_EQ(e.where(), "FOVSIM_EMBREE_ISA");
      EXPECT_NE(std::string(e.what()).find("allowed: native, sse2, sse4.2, avx, avx2, avx512"),
                std::string::npos);
    }
  });
  with_embree_isa("native", [] { EXPECT_EQ(embree_forced_isa(), ""); });
  with_embree_isa("sse2", [] {
    EXPECT_EQ(embree_active_isa(), "sse2");
    EXPECT_EQ(embree_device_config(), "isa=sse2");
  });
  EXPECT_EQ(embree_supported_isas().front(), "sse2");
}

// trace_gbuffer traces a tile in bands of whole 4x4 blocks (at most 1024 rays: the whole tile
// at 32, 20-row bands at 48, 4-row bands at 256) and shades each band's hits together; tiles
// and bands cut at the image's edges into partial blocks. Every tile size must give the same
// bits (each pixel is computed on its own), also with the per-sample path's channels (kMotion).
TEST(Render, GBufferBitsDoNotDependOnTileOrBand) {
  for (bool dynamic : {false, true}) {
    Scene s = atrium_small(dynamic);
    Camera cam = cam_at(small_display(150, 70, 100, 80), glm::dvec3(s.default_eye),
                        glm::angleAxis(0.4, glm::dvec3(0, 1, 0)));
    for (uint32_t ch : {~0u & ~uint32_t(kMotion), ~0u, uint32_t(kDepth | kMaterial)}) {
      GBuffer ref;
      {
        RenderSettings rs;
        rs.tile = 32;
        Renderer(s, rs).trace_gbuffer(cam, ch, ref, nullptr, &cam);
      }
      for (int tile : {4, 7, 48, 256}) {
        RenderSettings rs;
        rs.tile = tile;
        GBuffer g;
        Renderer(s, rs).trace_gbuffer(cam, ch, g, nullptr, &cam);
        auto same = [](const auto& x, const auto& y) {
          return x.size() == y.size() &&
                 std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
        };
        SCOPED_TRACE("dynamic " + std::to_string(dynamic) + " tile " + std::to_string(tile) +
                     " channels " + std::to_string(ch));
        EXPECT_TRUE(same(g.depth, ref.depth));
        EXPECT_TRUE(same(g.position, ref.position));
        EXPECT_TRUE(same(g.normal, ref.normal));
        EXPECT_TRUE(same(g.albedo, ref.albedo));
        EXPECT_TRUE(same(g.uv, ref.uv));
        EXPECT_TRUE(same(g.footprint, ref.footprint));
        EXPECT_TRUE(same(g.material, ref.material));
        EXPECT_TRUE(same(g.object_id, ref.object_id));
        EXPECT_TRUE(same(g.submodel, ref.submodel));
        EXPECT_TRUE(same(g.motion, ref.motion));
        size_t hits = 0;
        for (size_t i = 0; i < g.size(); ++i) hits += g.hit(i);
        EXPECT_GT(hits, g.size() / 2);
      }
    }
  }
}
