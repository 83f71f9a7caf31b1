// Forward reprojection with depth-tested splats (Franke et al. 2021 §4, §7).
#include "sim/foveation/twfr_reproject.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

using namespace fovsim;
using namespace fovsim::twfr;

namespace {
Display small_display() {
  Display d;
  d.width = 48;
  d.height = 40;
  d.fov_h_deg = 90;
  d.fov_v_deg = 80;
  return d;
}
// A wall at z = -3 seen from `cam`: every pixel's exact hit point, colour = pixel index.
void wall(const Camera& cam, Image& color, std::vector<Sample>& s) {
  color.resize(cam.width, cam.height, 3);
  s.assign(size_t(cam.width) * size_t(cam.height), Sample{});
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      glm::dvec3 d = cam.dir_world(x + 0.5, y + 0.5);
      double t = (-3.0 - cam.position.z) / d.z;
      size_t i = size_t(y) * size_t(cam.width) + size_t(x);
      s[i].pos = glm::vec3(cam.position + t * d);
      s[i].kind = kSurface;
      s[i].object = 0;
      s[i].age = 2;
      color.data[3 * i] = float(i);
    }
}
}  // namespace

TEST(TwfrReproject, StaticViewMapsEveryPixelOntoItselfExceptTheFovea) {
  Display d = small_display();
  Camera cam = Camera::from_pose(d, glm::dvec3(0, 1, 0), glm::dquat(1, 0, 0, 0));
  Image prev;
  std::vector<Sample> s;
  wall(cam, prev, s);
  std::vector<float> ecc = eccentricity_map(cam, glm::dvec3(0, 0, -1));
  ReprojectInput in;
  in.color = &prev;
  in.samples = &s;
  in.camera = &cam;
  in.eccentricity = &ecc;
  in.fovea_deg = 10.f;
  Image out;
  std::vector<Sample> os;
  std::vector<uint8_t> cov;
  SplatBuffer sb;
  ReprojectStats st = forward_reproject(in, out, os, cov, sb);
  size_t fovea = 0;
  for (size_t i = 0; i < ecc.size(); ++i) {
    if (ecc[i] < 10.f) {
      ++fovea;
      EXPECT_EQ(cov[i], 0);
      continue;
    }
    ASSERT_EQ(cov[i], 1) << i;
    EXPECT_EQ(out.data[3 * i], float(i));
    EXPECT_EQ(os[i].age, 3);
  }
  EXPECT_GT(fovea, 0u);
  EXPECT_EQ(st.fovea_discarded, fovea);
  EXPECT_EQ(st.landed + fovea, ecc.size());
}

TEST(TwfrReproject, DepthTestKeepsTheNearestSplatAndIsThreadIndependent) {
  Display d = small_display();
  Camera cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
  const size_t n = size_t(d.width) * size_t(d.height);
  Image prev(d.width, d.height, 3, 0.f);
  std::vector<Sample> s(n);
  // All samples on the ray through pixel (10, 7) at different depths, colour = depth.
  glm::dvec3 dir = cam.dir_world(10.5, 7.5);
  for (size_t i = 0; i < n; ++i) {
    double depth = 2.0 + double((i * 7919) % n) * 0.01;
    s[i].pos = glm::vec3(dir * depth);
    s[i].kind = kSurface;
    prev.data[3 * i] = float((i * 7919) % n);
  }
  std::vector<float> ecc(n, 50.f);
  ReprojectInput in;
  in.color = &prev;
  in.samples = &s;
  in.camera = &cam;
  in.eccentricity = &ecc;
  Image out1, out2;
  std::vector<Sample> o1, o2;
  std::vector<uint8_t> c1, c2;
  SplatBuffer sb;
  forward_reproject(in, out1, o1, c1, sb);
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    forward_reproject(in, out2, o2, c2, sb);
  }
  const size_t target = 7 * size_t(d.width) + 10;
  EXPECT_EQ(c1[target], 1);
  EXPECT_EQ(out1.data[3 * target], 0.f);  // the nearest (depth 2.0) wins
  EXPECT_EQ(out1.data, out2.data);
  EXPECT_EQ(c1, c2);
  size_t landed = 0;
  for (auto v : c1) landed += v;
  EXPECT_EQ(landed, 1u);
}

TEST(TwfrReproject, SkyAndDynamicObjectsMoveCorrectly) {
  Display d = small_display();
  Camera prev_cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
  // New view rotated by 5 degrees about +Y: a sky direction lands where the new camera sees it.
  Camera cam =
      Camera::from_pose(d, glm::dvec3(0), glm::angleAxis(glm::radians(5.0), glm::dvec3(0, 1, 0)));
  const size_t n = size_t(d.width) * size_t(d.height);
  Image prev(d.width, d.height, 3, 0.f);
  std::vector<Sample> s(n);
  const size_t src_sky = 20 * size_t(d.width) + 24;
  s[src_sky].kind = kSky;
  s[src_sky].pos = glm::vec3(prev_cam.dir_world(24.5, 20.5));
  prev.data[3 * src_sky] = 1.f;
  // A dynamic object's sample moved by its object's motion (translation 0.5 m along +X).
  const size_t src_dyn = 10 * size_t(d.width) + 10;
  s[src_dyn].kind = kSurface;
  s[src_dyn].object = 1;
  s[src_dyn].pos = glm::vec3(prev_cam.dir_world(10.5, 10.5) * 4.0);
  prev.data[3 * src_dyn] = 2.f;
  std::vector<glm::mat4> motion = {glm::mat4(1.f),
                                   glm::translate(glm::mat4(1.f), glm::vec3(0.5f, 0, 0))};
  std::vector<uint8_t> dyn = {0, 1};
  std::vector<float> ecc(n, 50.f);
  ReprojectInput in;
  in.color = &prev;
  in.samples = &s;
  in.camera = &cam;
  in.eccentricity = &ecc;
  in.object_motion = &motion;
  in.object_dynamic = &dyn;
  Image out;
  std::vector<Sample> os;
  std::vector<uint8_t> cov;
  SplatBuffer sb;
  forward_reproject(in, out, os, cov, sb);
  glm::dvec2 px;
  ASSERT_TRUE(cam.project_head(cam.to_head_dir(glm::dvec3(s[src_sky].pos)), px));
  size_t t_sky = size_t(int(px.y)) * size_t(d.width) + size_t(int(px.x));
  EXPECT_EQ(cov[t_sky], 1);
  EXPECT_EQ(out.data[3 * t_sky], 1.f);
  EXPECT_EQ(os[t_sky].kind, kSky);
  glm::dvec3 moved = glm::dvec3(s[src_dyn].pos) + glm::dvec3(0.5, 0, 0);
  ASSERT_TRUE(cam.project_world(moved, px));
  size_t t_dyn = size_t(int(px.y)) * size_t(d.width) + size_t(int(px.x));
  EXPECT_EQ(cov[t_dyn], 1);
  EXPECT_EQ(out.data[3 * t_dyn], 2.f);
  EXPECT_NEAR(os[t_dyn].pos.x, float(moved.x), 1e-5);
}
