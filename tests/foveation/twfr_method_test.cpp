// The `twfr` method end to end on a small atrium (Franke et al. 2021 §4-§8): small resolution, few
// frames.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <set>

#include "sim/core/error.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/frame.h"
#include "sim/foveation/twfr.h"
#include "sim/scene/scene.h"

using namespace fovsim;
using namespace fovsim::twfr;

namespace {

Display test_display() {
  Display d;
  d.width = 72;
  d.height = 64;
  d.fov_h_deg = 90;
  d.fov_v_deg = 85;
  return d;
}

Scene atrium(bool dynamic = false, bool moving_light = false) {
  Params p(Json{
      {"type", "atrium"}, {"complexity", 1}, {"dynamic", dynamic}, {"moving_light", moving_light}});
  return make_scene(p, "");
}

// Drives a method over a sequence of poses like the experiment runner does.
struct Driver {
  const Scene& scene;
  Display display = test_display();
  Renderer renderer;
  TwfrMethod method;
  FrameData fd;
  std::optional<Camera> prev;
  int frame = 0;
  Driver(const Scene& s, TwfrParams p = {}) : scene(s), renderer(s, RenderSettings{}), method(p) {}
  FrameOutput step(double yaw_deg, glm::dvec3 gaze = {0, 0, -1}, glm::dvec3 offset = glm::dvec3(0),
                   double pitch_deg = 0, bool debug = false) {
    TraceSample s;
    s.t = frame / 90.0;
    s.head_pos = glm::dvec3(scene.default_eye) + offset;
    s.head_rot = glm::angleAxis(glm::radians(yaw_deg), glm::dvec3(0, 1, 0)) *
                 glm::angleAxis(glm::radians(pitch_deg), glm::dvec3(1, 0, 0));
    s.gaze_dir = glm::normalize(gaze);
    renderer.set_time(s.t);
    prepare_frame(renderer, display, s, frame, method.required_channels(), prev ? &*prev : nullptr,
                  fd);
    FrameContext ctx = fd.context(scene, renderer, display, debug);
    FrameOutput out;
    method.render(ctx, out);
    prev = fd.camera;
    ++frame;
    return out;
  }
  size_t pixels() const { return size_t(display.width) * size_t(display.height); }
};

size_t count_nonzero(const std::vector<uint8_t>& v) {
  size_t c = 0;
  for (auto x : v) c += x != 0;
  return c;
}

void expect_sane(const FrameOutput& o, size_t n, const TwfrMethod& m) {
  ASSERT_EQ(o.image.pixels(), n);
  for (float v : o.image.data) ASSERT_TRUE(std::isfinite(v));
  for (float c : m.confidence()) ASSERT_TRUE(c >= 0.f && c <= 1.f);
  for (Counter k : {Counter::pixels_redrawn, Counter::shaded_samples, Counter::reprojected_pixels,
                    Counter::holes_filled}) {
    double v = o.counters.get(k, -1);
    EXPECT_GE(v, 0) << counter_name(k);
    EXPECT_LE(v, double(n)) << counter_name(k);
  }
  EXPECT_EQ(o.counters.get(Counter::cull_conflicts, -1), 0.0);
  EXPECT_EQ(m.cull_conflicts(), 0u);
  EXPECT_GE(o.counters.get(Counter::prims_submitted, -1), 0.0);
  EXPECT_GE(o.counters.get(Counter::prims_culled, -1), 0.0);
}

}  // namespace

TEST(TwfrMethod, FirstFrameRedrawsEverythingAndMatchesReference) {
  Scene s = atrium();
  Driver d(s);
  FrameOutput o = d.step(0);
  EXPECT_EQ(o.counters.get(Counter::twfr_restart), 1.0);
  EXPECT_EQ(o.counters.get(Counter::pixels_redrawn), double(d.pixels()));
  EXPECT_EQ(o.counters.get(Counter::shaded_samples), double(d.pixels()));
  EXPECT_EQ(o.image.data, d.fd.reference.data);
  expect_sane(o, d.pixels(), d.method);
}

TEST(TwfrMethod, EpsilonOneRedrawsEveryPixelEveryFrame) {
  Scene s = atrium();
  TwfrParams p;
  p.conf.epsilon = 1.f;
  p.taa = false;  // the redrawn image itself (TAA would blend the moving frames)
  Driver d(s, p);
  for (int f = 0; f < 4; ++f) {
    FrameOutput o = d.step(3.0 * f, {0.2, 0.1, -1}, glm::dvec3(0.05 * f, 0, 0));
    EXPECT_EQ(o.counters.get(Counter::pixels_redrawn), double(d.pixels()));
    EXPECT_EQ(o.counters.get(Counter::shaded_samples), double(d.pixels()));
    EXPECT_EQ(o.image.data, d.fd.reference.data) << "frame " << f;
    expect_sane(o, d.pixels(), d.method);
  }
}

TEST(TwfrMethod, EpsilonZeroRedrawsOnlyFoveaAndUncovered) {
  Scene s = atrium();
  TwfrParams p;
  p.conf.epsilon = 0.f;
  Driver d(s, p);
  d.step(0);
  for (int f = 1; f < 4; ++f) {
    FrameOutput o = d.step(2.0 * f, {0.1, 0, -1});
    const auto& ecc = d.fd.eccentricity;
    const auto& rm = d.method.redraw_map();
    size_t fovea = 0;
    for (size_t i = 0; i < rm.size(); ++i) {
      if (ecc[i] < p.conf.phi_f) {
        ++fovea;
        EXPECT_NE(rm[i] & kRedrawFovea, 0);
      }
      if (rm[i]) {
        EXPECT_TRUE((rm[i] & (kRedrawFovea | kRedrawUncovered)) || ecc[i] <= p.conf.phi_f) << i;
      }
    }
    EXPECT_GT(fovea, 0u);
    EXPECT_EQ(o.counters.get(Counter::pixels_redrawn), double(count_nonzero(rm)));
    EXPECT_EQ(o.counters.get(Counter::pixels_redrawn),
              o.counters.get(Counter::fovea_pixels) + o.counters.get(Counter::uncovered_pixels) +
                  o.counters.get(Counter::redraw_confidence_pixels));
    expect_sane(o, d.pixels(), d.method);
  }
}

TEST(TwfrMethod, RedrawnFractionNonDecreasingInEpsilon) {
  Scene s = atrium();
  std::vector<uint8_t> prev_map;
  double prev_count = -1;
  for (float eps : {0.f, 0.05f, 0.1f, 0.2f, 0.25f, 0.5f, 1.f}) {
    TwfrParams p;
    p.conf.epsilon = eps;
    Driver d(s, p);
    d.step(0);
    FrameOutput o =
        d.step(4.0, {0.3, -0.1, -1}, glm::dvec3(0.1, 0, -0.1));  // same state for every eps
    const auto& rm = d.method.redraw_map();
    double cnt = o.counters.get(Counter::pixels_redrawn);
    EXPECT_GE(cnt, prev_count) << "eps " << eps;
    for (size_t i = 0; i < prev_map.size(); ++i) {
      if (prev_map[i]) {
        ASSERT_NE(rm[i], 0) << "eps " << eps << " pixel " << i;
      }
    }
    prev_map = rm;
    prev_count = cnt;
    expect_sane(o, d.pixels(), d.method);
  }
  EXPECT_EQ(prev_count, double(test_display().width * test_display().height));
}

TEST(TwfrMethod, StaticSceneStaticHeadRedrawsOnlyTheFovealRegion) {
  Scene s = atrium();
  TwfrParams p;   // defaults: eps 0.2, phi_F 10, phi_0 30
  p.taa = false;  // the composed image itself
  Driver d(s, p);
  d.step(5);
  for (int f = 1; f < 5; ++f) {
    FrameOutput o = d.step(5);
    const auto& ecc = d.fd.eccentricity;
    const auto& rm = d.method.redraw_map();
    size_t expect = 0;
    for (size_t i = 0; i < rm.size(); ++i) {
      bool foveal = eccentricity_confidence(ecc[i], p.conf.phi_f, p.conf.phi_0) <= p.conf.epsilon;
      expect += foveal;
      ASSERT_EQ(rm[i] != 0, foveal) << "frame " << f << " pixel " << i << " ecc " << ecc[i];
    }
    EXPECT_GT(expect, 0u);
    EXPECT_LT(expect, rm.size());
    EXPECT_EQ(o.counters.get(Counter::holes_filled), 0.0);
    EXPECT_EQ(o.counters.get(Counter::uncovered_pixels), 0.0);
    EXPECT_EQ(o.counters.get(Counter::pixels_redrawn), double(expect));
    // Static everything: reprojected colour is exact, the image equals the reference.
    EXPECT_EQ(o.image.data, d.fd.reference.data);
    expect_sane(o, d.pixels(), d.method);
  }
}

TEST(TwfrMethod, CullsSubModelsBehindConfidentPixelsOnly) {
  Scene s = atrium();
  Driver d(s);
  d.step(0, {0.5, 0.2, -1});
  FrameOutput o = d.step(0, {0.5, 0.2, -1});
  const GBuffer& g = d.fd.gbuffer;
  const auto& culled = d.method.submodel_culled();
  const auto& rm = d.method.redraw_map();
  ASSERT_EQ(culled.size(), s.submodels.size());
  std::set<int32_t> marked, visible;
  for (size_t i = 0; i < g.size(); ++i) {
    if (g.submodel[i] < 0) continue;
    visible.insert(g.submodel[i]);
    if (rm[i]) marked.insert(g.submodel[i]);
  }
  for (int32_t sm : marked)
    EXPECT_EQ(culled[size_t(sm)], 0) << "sub-model over a marked pixel was culled";
  size_t culled_visible = 0;
  for (int32_t sm : visible) culled_visible += culled[size_t(sm)];
  EXPECT_GT(culled_visible, 0u) << "no visible sub-model wholly behind confident pixels was culled";
  EXPECT_GT(o.counters.get(Counter::prims_foveation_culled), 0.0);
  EXPECT_EQ(o.counters.get(Counter::prims_submitted) + o.counters.get(Counter::prims_culled),
            double(s.triangle_count()));
  // Every marked pixel was shaded (nothing marked lies on a culled sub-model).
  for (size_t i = 0; i < rm.size(); ++i) ASSERT_EQ(rm[i] != 0, d.method.shade_mask()[i] != 0);
  expect_sane(o, d.pixels(), d.method);
}

TEST(TwfrMethod, DynamicPixelsRedrawnWithinFramesImpliedByD) {
  Scene s = atrium(/*dynamic=*/true);
  TwfrParams p;
  Driver d(s, p);
  const int tmax = int(std::ceil(std::log(p.conf.epsilon) / std::log(p.conf.D)));  // 6
  double dyn_seen = 0;
  d.step(0, {0.6, 0.3, -1});  // gaze away from the sculpture
  for (int f = 1; f < 12; ++f) {
    FrameOutput o = d.step(0, {0.6, 0.3, -1});
    dyn_seen += o.counters.get(Counter::dynamic_pixels);
    for (const Sample& smp : d.method.samples()) {
      if (smp.kind != kSurface || smp.object < 0 || !s.objects[size_t(smp.object)].dynamic())
        continue;
      ASSERT_LT(int(smp.age), tmax) << "a dynamic pixel survived " << smp.age << " frames";
    }
    expect_sane(o, d.pixels(), d.method);
  }
  EXPECT_GT(dyn_seen, 0.0);
}

TEST(TwfrMethod, ExtremesStayFinite) {
  Scene s = atrium();
  struct Case {
    float phi_f, phi_0;
    glm::dvec3 gaze;
    double yaw_step;
  };
  std::vector<Case> cases = {
      {10, 10, {0, 0, -1}, 2},     // phi_F == phi_0
      {0, 30, {0, 0, -1}, 2},      // phi_F = 0
      {10, 30, {5, 0, -1}, 2},     // gaze outside the screen
      {10, 30, {0, 0, 1}, 2},      // gaze behind the eye
      {10, 30, {0.1, 0, -1}, 35},  // very fast head sweep
      {180, 180, {0, 0, -1}, 2},   // everything foveal
  };
  for (const Case& c : cases) {
    TwfrParams p;
    p.conf.phi_f = c.phi_f;
    p.conf.phi_0 = c.phi_0;
    p.taa = true;
    Driver d(s, p);
    for (int f = 0; f < 4; ++f) {
      FrameOutput o = d.step(c.yaw_step * f, c.gaze, glm::dvec3(0, 0, -0.2 * f), 3.0 * f);
      expect_sane(o, d.pixels(), d.method);
    }
  }
}

TEST(TwfrMethod, FlagsMovingLightsAndTransparency) {
  Scene s = atrium(false, /*moving_light=*/true);
  s.materials[0].transparent = true;
  Driver d(s);
  d.step(0);
  FrameOutput o = d.step(1);
  std::set<std::string> flags(o.flags.begin(), o.flags.end());
  EXPECT_TRUE(flags.count("twfr_moving_lights"));
  EXPECT_TRUE(flags.count("twfr_transparency"));
  // Transparent surfaces are redrawn every frame (§8.5).
  const GBuffer& g = d.fd.gbuffer;
  size_t transparent = 0;
  for (size_t i = 0; i < g.size(); ++i)
    if (g.hit(i) && g.material[i] == 0) {
      ++transparent;
      EXPECT_NE(d.method.redraw_map()[i], 0);
    }
  EXPECT_GT(transparent, 0u);
  expect_sane(o, d.pixels(), d.method);
}

TEST(TwfrMethod, ResetRedrawsEverythingAndRunsAreThreadIndependent) {
  Scene s = atrium(true);
  std::vector<Image> a, b;
  for (int pass = 0; pass < 2; ++pass) {
    std::unique_ptr<tbb::global_control> gc;
    if (pass == 1)
      gc = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, 1);
    Driver d(s);
    for (int f = 0; f < 4; ++f) {
      FrameOutput o = d.step(2.5 * f, {0.2, -0.1, -1}, glm::dvec3(0.03 * f, 0, 0));
      (pass ? b : a).push_back(o.image);
    }
    d.method.reset();
    FrameOutput o = d.step(12);
    EXPECT_EQ(o.counters.get(Counter::pixels_redrawn), double(d.pixels()));
  }
  for (size_t f = 0; f < a.size(); ++f) EXPECT_EQ(a[f].data, b[f].data) << "frame " << f;
}

TEST(TwfrMethod, FactoryValidatesParameters) {
  Params ok(Json{{"epsilon", 0.1}, {"phi_f", 6}, {"phi_0", 20}});
  auto m = make_method("twfr", ok);
  ASSERT_TRUE(m);
  EXPECT_TRUE(m->temporal());
  auto cols = m->param_columns();
  ASSERT_EQ(cols.size(), 5u);
  EXPECT_EQ(cols[0].first, "epsilon");
  EXPECT_NEAR(cols[0].second, 0.1, 1e-6);
  EXPECT_EQ(cols[3].first, "A");
  EXPECT_EQ(cols[4].first, "D");
  try {
    Params bad(Json{{"phi_f", 20}, {"phi_0", 10}});
    make_method("twfr", bad);
    FAIL() << "phi_0 < phi_f accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("phi_0"), std::string::npos) << e.what();
  }
  try {
    Params bad(Json{{"epsilon", 1.5}});
    make_method("twfr", bad);
    FAIL() << "epsilon 1.5 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("epsilon"), std::string::npos) << e.what();
  }
  try {
    Params bad(Json{{"epsilonn", 0.2}});
    make_method("twfr", bad);
    FAIL() << "unknown key accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("epsilonn"), std::string::npos) << e.what();
  }
}

TEST(TwfrMethod, DebugImages) {
  Scene s = atrium();
  Driver d(s);
  d.step(0);
  FrameOutput o = d.step(3, {0, 0, -1}, glm::dvec3(0), 0, /*debug=*/true);
  std::set<std::string> names;
  for (auto& [n, im] : o.debug) {
    names.insert(n);
    EXPECT_EQ(im.pixels(), d.pixels());
  }
  for (const char* n : {"redraw", "confidence", "holes", "reprojected"})
    EXPECT_TRUE(names.count(n)) << n;
}
