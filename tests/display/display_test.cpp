#include "sim/display/display.h"

#include <gtest/gtest.h>

#include "sim/core/error.h"

using namespace fovsim;

static Display vive() {
  return Display::load("htc_vive_pro_eye", std::string(FOVSIM_SOURCE_DIR) + "/models");
}

TEST(Display, LoadsAllModels) {
  for (const char* n : {"htc_vive_pro_eye", "fove_1280x1440", "fove_2560x1440", "desktop_1920x1080",
                        "uhd_3840x2160"}) {
    Display d = Display::load(n, std::string(FOVSIM_SOURCE_DIR) + "/models");
    EXPECT_EQ(d.name, n);
    EXPECT_GT(d.ppd_center(), 5.0);
  }
  EXPECT_THROW(Display::load("nope", std::string(FOVSIM_SOURCE_DIR) + "/models"), Error);
}

TEST(Display, EdgeRaysMatchFov) {
  Display d = vive();
  Camera c = Camera::from_pose(d, {}, glm::dquat(1, 0, 0, 0));
  glm::dvec3 left = c.dir_head(0, d.height / 2.0), right = c.dir_head(d.width, d.height / 2.0);
  EXPECT_NEAR(rad2deg(angle_between(left, right)), d.fov_h_deg, 1e-9);
  glm::dvec3 top = c.dir_head(d.width / 2.0, 0), bottom = c.dir_head(d.width / 2.0, d.height);
  EXPECT_NEAR(rad2deg(angle_between(top, bottom)), d.fov_v_deg, 1e-9);
  EXPECT_GT(top.y, 0);  // row 0 is on top
}

TEST(Display, EccentricityIsExactAngleNotPixelDistance) {
  Display d = vive();
  Camera c = Camera::from_pose(d, {}, glm::dquat(1, 0, 0, 0));
  glm::dvec3 gaze(0, 0, -1);
  EXPECT_NEAR(c.eccentricity_deg(d.width / 2.0, d.height / 2.0, gaze), 0.0, 1e-9);
  // The screen edge is at half the FOV.
  EXPECT_NEAR(c.eccentricity_deg(d.width, d.height / 2.0, gaze), d.fov_h_deg / 2, 1e-9);
  // A point at 1/4 of the half width is at atan(0.25 tan(49 deg)), not 49/4 deg.
  double e = c.eccentricity_deg(d.width * 0.625, d.height / 2.0, gaze);
  EXPECT_NEAR(e, rad2deg(std::atan(0.25 * std::tan(deg2rad(49.0)))), 1e-9);
  // A flat panel under perspective projection packs more pixels per degree towards its edge:
  // d(angle)/dx = cos^2(theta) * (2 tan(h/2) / W) at angle theta from the axis.
  double ppd_c = c.ppd_at(d.width / 2.0, d.height / 2.0);
  EXPECT_GT(c.ppd_at(10, d.height / 2.0), ppd_c);
  double dtheta_dx = 2.0 * std::tan(deg2rad(49.0)) / d.width;  // radians per pixel at the centre
  double dtheta_dy = 2.0 * std::tan(deg2rad(53.5)) / d.height;
  EXPECT_NEAR(0.5 * (1.0 / rad2deg(dtheta_dx) + 1.0 / rad2deg(dtheta_dy)), ppd_c, 1e-3);
}

TEST(Display, EccentricityMapIntoAReusedBufferEqualsAFreshMap) {
  Display d = vive();
  d.width = 37;  // odd, small
  d.height = 29;
  Camera c = Camera::from_pose(d, {}, glm::dquat(1, 0, 0, 0));
  const glm::dvec3 g1(0.2, -0.1, -1), g2(-0.3, 0.25, -1);
  std::vector<float> buf(5, -1.f);  // wrong size and stale values: resized, every slot written
  eccentricity_map(c, g1, buf);
  EXPECT_EQ(buf, eccentricity_map(c, g1));
  const float* storage = buf.data();
  eccentricity_map(c, g2, buf);  // same size: no reallocation
  EXPECT_EQ(buf.data(), storage);
  EXPECT_EQ(buf, eccentricity_map(c, g2));
  ASSERT_EQ(buf.size(), size_t(37 * 29));
  EXPECT_FLOAT_EQ(buf[size_t(5 * 37 + 11)],
                  float(c.eccentricity_deg(11.5, 5.5, glm::normalize(g2))));
}

TEST(Display, ProjectRoundTrip) {
  Display d = vive();
  glm::dquat rot = glm::angleAxis(0.3, glm::normalize(glm::dvec3(0.2, 1, 0.1)));
  Camera c = Camera::from_pose(d, {1, 2, 3}, rot);
  for (double px : {0.5, 100.25, 719.5, 1439.5})
    for (double py : {0.5, 800.0, 1599.5}) {
      glm::dvec3 p = c.position + 3.0 * c.dir_world(px, py);
      glm::dvec2 q;
      double depth;
      ASSERT_TRUE(c.project_world(p, q, &depth));
      EXPECT_NEAR(q.x, px, 1e-7);
      EXPECT_NEAR(q.y, py, 1e-7);
      EXPECT_GT(depth, 0);
    }
  double u, v;
  ASSERT_TRUE(gaze_screen_from_dir(d, gaze_dir_from_screen(d, 0.3, 0.8), u, v));
  EXPECT_NEAR(u, 0.3, 1e-12);
  EXPECT_NEAR(v, 0.8, 1e-12);
  EXPECT_FALSE(gaze_screen_from_dir(d, glm::dvec3(0, 0, 1), u, v));
}
