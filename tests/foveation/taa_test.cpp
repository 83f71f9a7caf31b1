// The shared temporal anti-aliasing pass (sim/foveation/taa.h; docs/methods.md "Temporal
// anti-aliasing"): Halton jitter, Yang et al. 2021 eq. 15's clamp window, reprojection through
// the G-buffer's motion, the neighbourhood clamp and the blend; the methods' TAA keys.
#include "sim/foveation/taa.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "sim/core/error.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/method.h"

using namespace fovsim;

namespace {

TaaSettings on(TaaClamp clamp = TaaClamp::Box3, bool jitter = false) {
  TaaSettings s;
  s.enabled = true;
  s.alpha = 0.1;
  s.clamp = clamp;
  s.jitter = jitter;
  return s;
}

// A W x H frame whose every pixel is a hit moving by (mx, my) pixels since the previous frame.
struct Frame {
  Display d;
  Camera cam;
  GBuffer g;
  FrameContext ctx;
  Frame(int W, int H, float mx, float my) {
    d.width = W;
    d.height = H;
    d.fov_h_deg = 90;
    d.fov_v_deg = 90;
    cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
    g.resize(W, H, kDepth | kMotion);
    for (size_t i = 0; i < g.size(); ++i) {
      g.depth[i] = 1.f;
      g.motion[i] = glm::vec2(mx, my);
    }
    ctx.gbuffer = &g;
    ctx.camera = &cam;
    ctx.prev_camera = &cam;
    ctx.display = &d;
    ctx.gaze_px = glm::dvec2(W / 2.0, H / 2.0);
  }
};

}  // namespace

TEST(Taa, HaltonJitterIsSixteenPointsInTheUnitSquareCentredOnZero) {
  TaaSettings s = on(TaaClamp::Box3, true);
  glm::dvec2 sum(0);
  for (int f = 0; f < 16; ++f) {
    const glm::dvec2 j = taa_jitter(s, f);
    EXPECT_GE(j.x, -0.5);
    EXPECT_LT(j.x, 0.5);
    EXPECT_GE(j.y, -0.5);
    EXPECT_LT(j.y, 0.5);
    EXPECT_EQ(j, taa_jitter(s, f + 16));  // cycled
    sum += j;
  }
  // Halton(2, 3) points 1..16: base 2 gives 1/2, 1/4, 3/4, 1/8, ...
  EXPECT_DOUBLE_EQ(taa_jitter(s, 0).x, 0.0);
  EXPECT_DOUBLE_EQ(taa_jitter(s, 1).x, -0.25);
  EXPECT_DOUBLE_EQ(taa_jitter(s, 0).y, 1.0 / 3.0 - 0.5);
  EXPECT_NEAR(sum.x / 16, 0.0, 0.04);
  EXPECT_NEAR(sum.y / 16, 0.0, 0.04);
  s.jitter = false;
  EXPECT_EQ(taa_jitter(s, 3), glm::dvec2(0));
  s = on(TaaClamp::Box3, true);
  s.enabled = false;
  EXPECT_EQ(taa_jitter(s, 3), glm::dvec2(0));
}

TEST(Taa, EtaWindowFollowsEquation15InDisplayPixels) {
  EXPECT_EQ(taa_eta_half(0.0, 1.0), 0);   // eta < 3 near the gaze: the pixel itself
  EXPECT_EQ(taa_eta_half(0.12, 1.0), 1);  // eta 3
  EXPECT_EQ(taa_eta_half(0.16, 1.0), 2);  // eta 5
  EXPECT_EQ(taa_eta_half(1.0, 1.0), 19);  // eta 39 at the far corner
  EXPECT_EQ(taa_eta_half(5.0, 1.0), 19);  // r > e^L is capped
  // At render.scale 0.5 the window is half as wide in simulated pixels.
  EXPECT_EQ(taa_eta_half(1.0, 0.5), 9);
  EXPECT_EQ(taa_eta_half(0.12, 0.5), 0);
}

TEST(Taa, ReprojectedHistoryOfAMovingImageIsTheImageItself) {
  // A pattern moving right by 2 pixels a frame, with the G-buffer's motion saying so: the
  // reprojected history is the current image wherever it was on screen, so TAA changes nothing.
  const int W = 24, H = 16;
  Frame fr(W, H, 2.f, 0.f);
  auto pattern = [&](int shift) {
    Image img(W, H, 3);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        for (int c = 0; c < 3; ++c)
          img.at(x, y)[c] = float(((x - shift) * 7 + y * 3 + c) % 11) / 10.f;
    return img;
  };
  TaaPass pass;
  for (int f = 0; f < 6; ++f) {
    Image img = pattern(2 * f);
    const Image cur = img;
    Counters c;
    pass.apply(on(), fr.ctx, img, c);
    for (size_t i = 0; i < img.data.size(); ++i) ASSERT_NEAR(img.data[i], cur.data[i], 1e-6) << f;
    // Every pixel but the two columns entering from the left blends a history.
    EXPECT_EQ(c.get(Counter::taa_pixels), f == 0 ? 0.0 : double((W - 2) * H));
  }
}

TEST(Taa, FlickerWithinTheNeighbourhoodIsSmoothedAndASteadyImageKept) {
  // A checkerboard whose phase flips every frame (sub-pixel aliasing as a static camera sees
  // it): every 3x3 neighbourhood spans [0, 1], so the history survives the clamp and the output
  // changes by alpha-sized steps instead of 1.
  const int W = 16, H = 16;
  Frame fr(W, H, 0.f, 0.f);
  TaaPass pass;
  Image prev;
  double last_step = 0;
  for (int f = 0; f < 40; ++f) {
    Image img(W, H, 3);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        for (int c = 0; c < 3; ++c) img.at(x, y)[c] = float((x + y + f) % 2);
    Counters cn;
    pass.apply(on(), fr.ctx, img, cn);
    if (f > 0) {
      double step = 0;
      for (size_t i = 0; i < img.data.size(); ++i)
        step = std::max(step, double(std::fabs(img.data[i] - prev.data[i])));
      last_step = step;
    }
    prev = img;
  }
  EXPECT_LT(last_step, 0.12);  // alpha 0.1: the steady state flickers by ~0.1, not 1
  EXPECT_GT(last_step, 0.05);
  // A constant image stays itself (the clamp and the blend of equal values).
  TaaPass still;
  for (int f = 0; f < 3; ++f) {
    Image img(W, H, 3, 0.25f);
    Counters cn;
    still.apply(on(TaaClamp::Eta), fr.ctx, img, cn);
    for (float v : img.data) ASSERT_FLOAT_EQ(v, 0.25f);
  }
}

TEST(Taa, AChangeOutsideTheNeighbourhoodIsNotGhosted) {
  // The whole image jumps from 0 to 1 (a disocclusion without motion): the clamp to the new
  // neighbourhood rejects the old history at once.
  const int W = 8, H = 8;
  Frame fr(W, H, 0.f, 0.f);
  TaaPass pass;
  Image a(W, H, 3, 0.f), b(W, H, 3, 1.f);
  Counters c;
  pass.apply(on(), fr.ctx, a, c);
  pass.apply(on(), fr.ctx, b, c);
  for (float v : b.data) EXPECT_FLOAT_EQ(v, 1.f);
  pass.reset();  // no history after a reset: the image passes through
  Image z(W, H, 3, 0.5f);
  pass.apply(on(), fr.ctx, z, c);
  EXPECT_EQ(c.get(Counter::taa_pixels), 0.0);
}

TEST(Taa, MethodsDeclareTheirSeedsTaa) {
  // On by default where the seed's pipeline ends with TAA (Meng 2018 §2.3.2, Ye et al. 2022
  // Table 3, Yang et al. 2021 §6, Franke et al. 2021 §6.2); off for full and the baselines.
  struct Want {
    const char* method;
    bool enabled;
    TaaClamp clamp;
    bool jitter;
  };
  for (const Want& w :
       {Want{"kfr", true, TaaClamp::Box3, true}, Want{"rmfr", true, TaaClamp::Box3, true},
        Want{"rmfr_auto", true, TaaClamp::Box3, true}, Want{"flc", true, TaaClamp::Eta, false},
        Want{"twfr", true, TaaClamp::Box3, false}, Want{"full", false, TaaClamp::Box3, false},
        Want{"hyperbolic", false, TaaClamp::Box3, false}}) {
    Params p(Json::object(), "test");
    auto m = make_method(w.method, p);
    const TaaSettings s = m->taa();
    EXPECT_EQ(s.enabled, w.enabled) << w.method;
    if (!w.enabled) continue;
    EXPECT_EQ(s.clamp, w.clamp) << w.method;
    EXPECT_EQ(s.jitter, w.jitter) << w.method;
    EXPECT_DOUBLE_EQ(s.alpha, 0.1) << w.method;
  }
  // `full` takes a method's keys (the foveation-loss reference), not a jitter.
  Params p(Json{{"taa", true}, {"taa_alpha", 0.2}, {"taa_clamp", "eta"}}, "test");
  auto full = make_method("full", p);
  EXPECT_TRUE(full->taa().enabled);
  EXPECT_EQ(full->taa().clamp, TaaClamp::Eta);
  EXPECT_DOUBLE_EQ(full->taa().alpha, 0.2);
  Params bad(Json{{"taa_jitter", true}}, "test");
  EXPECT_THROW(
      {
        auto m = make_method("full", bad);
        bad.finish();
      },
      Error);
  Params alpha0(Json{{"taa_alpha", 0}}, "test");
  EXPECT_THROW(make_method("kfr", alpha0), Error);
}
