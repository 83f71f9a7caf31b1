// Screen rectangles of sub-model AABBs and foveation culling (Franke et al. 2021 §6.1).
#include "sim/foveation/twfr_cull.h"

#include <gtest/gtest.h>

#include "sim/core/rng.h"

using namespace fovsim;
using namespace fovsim::twfr;

namespace {
Camera test_camera(int w = 96, int h = 80) {
  Display d;
  d.width = w;
  d.height = h;
  d.fov_h_deg = 90;
  d.fov_v_deg = 80;
  glm::dquat rot =
      glm::angleAxis(0.3, glm::dvec3(0, 1, 0)) * glm::angleAxis(-0.1, glm::dvec3(1, 0, 0));
  return Camera::from_pose(d, glm::dvec3(0.5, 1.6, 2.0), rot);
}
AABB box(glm::vec3 lo, glm::vec3 hi) {
  AABB b;
  b.extend(lo);
  b.extend(hi);
  return b;
}
}  // namespace

TEST(TwfrCull, RectangleContainsEveryVisiblePointOfTheBox) {
  Camera cam = test_camera();
  Rng r(9);
  int rects = 0;
  for (int t = 0; t < 200; ++t) {
    glm::vec3 c(float(r.uniform(-6, 6)), float(r.uniform(-2, 5)), float(r.uniform(-8, 4)));
    glm::vec3 e(float(r.uniform(0.01, 1.5)), float(r.uniform(0.01, 1.5)),
                float(r.uniform(0.01, 1.5)));
    AABB b = box(c - e, c + e);
    int x0, y0, x1, y1;
    RectKind k = screen_rect(cam, b, x0, y0, x1, y1);
    rects += k == RectKind::Rect;
    for (int s = 0; s < 300; ++s) {
      glm::dvec3 p(r.uniform(b.lo.x, b.hi.x), r.uniform(b.lo.y, b.hi.y), r.uniform(b.lo.z, b.hi.z));
      glm::dvec2 px;
      double depth;
      if (!cam.project_world(p, px, &depth) || !cam.inside(px)) continue;
      ASSERT_NE(k, RectKind::Offscreen) << "visible point in an offscreen box";
      if (k == RectKind::FullScreen) continue;
      int ix = int(px.x), iy = int(px.y);
      EXPECT_TRUE(ix >= x0 && ix <= x1 && iy >= y0 && iy <= y1);
    }
  }
  EXPECT_GT(rects, 20);
}

TEST(TwfrCull, BehindAndStraddlingBoxes) {
  Display d;
  d.width = 64;
  d.height = 64;
  Camera cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
  int x0, y0, x1, y1;
  EXPECT_EQ(screen_rect(cam, box({-1, -1, 1}, {1, 1, 3}), x0, y0, x1, y1), RectKind::Offscreen);
  EXPECT_EQ(screen_rect(cam, box({-1, -1, -1}, {1, 1, 1}), x0, y0, x1, y1), RectKind::FullScreen);
  EXPECT_EQ(screen_rect(cam, AABB{}, x0, y0, x1, y1), RectKind::Offscreen);
  // A small box straight ahead covers the centre.
  EXPECT_EQ(screen_rect(cam, box({-0.1f, -0.1f, -5.f}, {0.1f, 0.1f, -4.f}), x0, y0, x1, y1),
            RectKind::Rect);
  EXPECT_LE(x0, 32);
  EXPECT_GE(x1, 31);
}

TEST(TwfrCull, CulledOnlyWhenNoMarkedPixelUnderTheRectangle) {
  Display d;
  d.width = 64;
  d.height = 64;
  d.fov_h_deg = d.fov_v_deg = 90;
  Camera cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
  // Mark the left-top 8x8 corner only.
  std::vector<uint8_t> map(64 * 64, 0);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) map[size_t(y) * 64 + size_t(x)] = 1;
  OrMip mip;
  mip.build(map, 64, 64);
  std::vector<AABB> boxes = {
      box({-0.2f, -0.2f, -5.f}, {0.2f, 0.2f, -4.f}),  // centre: culled
      box({-5.f, 4.f, -5.2f}, {-4.5f, 4.6f, -5.f}),   // top-left corner: drawn
      box({-1.f, -1.f, 2.f}, {1.f, 1.f, 3.f}),        // behind: offscreen
  };
  std::vector<double> tris = {100, 200, 300};
  std::vector<uint8_t> culled;
  CullStats st = cull_submodels(
      cam, mip, boxes.size(), [&](size_t s) { return boxes[s]; }, [&](size_t s) { return tris[s]; },
      culled);
  EXPECT_EQ(culled[0], 1);
  EXPECT_EQ(culled[1], 0);
  EXPECT_EQ(culled[2], 1);
  EXPECT_EQ(st.prims_total, 600);
  EXPECT_EQ(st.prims_culled, 100);
  EXPECT_EQ(st.prims_offscreen, 300);
  EXPECT_EQ(st.prims_submitted, 200);
}
