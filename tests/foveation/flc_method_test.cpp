// FLC end to end on a small Cornell box (Yang et al. 2021 §5-§7): budget >= #VPLs equals the ground
// truth, foveal error falls with the budget (Fig. 7), tau > 1 (Table 1), extremes stay
// finite, determinism across thread counts, parameter validation.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

#include "sim/core/error.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/frame.h"

using namespace fovsim;

namespace {

struct Fixture {
  Scene scene;
  std::unique_ptr<Renderer> renderer;
  Display display;
  FrameData fd;

  explicit Fixture(double light_intensity = 1.6, int size = 48, int rsm = 16,
                   double min_dist = 0.01) {
    Params sp(Json{{"type", "cornell"},
                   {"light_intensity", light_intensity},
                   {"vpl", {{"rsm_size", rsm}, {"min_dist", min_dist}}}});
    scene = make_scene(sp, "");
    renderer = std::make_unique<Renderer>(scene, RenderSettings{});
    display.width = size;
    display.height = size;
    display.fov_h_deg = 60;
    display.fov_v_deg = 60;
    TraceSample s;
    s.head_pos = glm::dvec3(0, 1, 2.2);
    // Gaze on the red (left) wall.
    s.gaze_dir = glm::normalize(glm::dvec3(-0.35, 0.0, -1.0));
    renderer->set_time(0);
    prepare_frame(*renderer, display, s, 0, kShadingChannels, nullptr, fd);
  }
  FrameOutput run(const Json& params, int frame = 0) {
    Params p(params);
    auto m = make_method("flc", p);
    FrameContext ctx = fd.context(scene, *renderer, display, false);
    ctx.frame = frame;
    FrameOutput out;
    render_with_lighting(*m, ctx, out);
    return out;
  }
};

double max_abs_diff(const Image& a, const Image& b) {
  double m = 0;
  for (size_t i = 0; i < a.data.size(); ++i)
    m = std::max(m, double(std::fabs(a.data[i] - b.data[i])));
  return m;
}

bool all_finite(const Image& a) {
  for (float v : a.data)
    if (!std::isfinite(v)) return false;
  return true;
}

// One fixture per RSM size (the VPL set is the scene's, scene.vpl.rsm_size).
Fixture& cornell(int rsm = 16) {
  static std::map<int, std::unique_ptr<Fixture>> f;
  auto& p = f[rsm];
  if (!p) p = std::make_unique<Fixture>(1.6, 48, rsm);
  return *p;
}

}  // namespace

TEST(FlcMethod, GazeLandsOnTheRedWall) {
  Fixture& f = cornell();
  const glm::dvec2 g = f.fd.gaze_px;
  ASSERT_TRUE(g.x >= 0 && g.y >= 0 && g.x < f.display.width && g.y < f.display.height);
  const size_t i = size_t(g.y) * size_t(f.display.width) + size_t(g.x);
  ASSERT_TRUE(f.fd.gbuffer.hit(i));
  EXPECT_NEAR(f.fd.gbuffer.position[i].x, -1.f, 1e-3f);
}

TEST(FlcMethod, BudgetCoveringAllVplsEqualsGroundTruth) {
  Fixture& f = cornell(16);
  FrameOutput o = f.run(Json{{"vpl_budget", 100000}});
  EXPECT_GT(o.counters.get(Counter::vpls_total), 100.0);
  EXPECT_EQ(o.counters.get(Counter::vpls_kept), o.counters.get(Counter::vpls_total));
  // Every VPL with weight 1 is exactly the shared reference (all VPLs, TBDS): same loop, same
  // direct + indirect sum.
  EXPECT_EQ(max_abs_diff(o.image, f.fd.reference), 0.0);
  // Indirect light is really there: the reference is brighter than the direct light.
  double ind = 0;
  for (size_t i = 0; i < o.image.data.size(); ++i)
    ind += f.fd.reference.data[i] - f.fd.direct.data[i];
  EXPECT_GT(ind / double(o.image.data.size()), 1e-3);
  EXPECT_NEAR(o.counters.get(Counter::flc_tau), 1.0, 1e-9);
}

// Fig. 7's trend as a statistical claim, not a coin flip of two single-seed RMSEs: FLC's VPL
// selection is stochastic, so at each budget step (4 -> 32 -> 256 VPLs) the per-seed paired
// log ratio of foveal RMSE (same seed, both budgets; log because the noise is multiplicative)
// is averaged over 24 seeds and must exceed 3 standard errors (paired t > 3). Measured: t =
// 5.95 and 11.05, i.e. a margin of 2x and 3.7x over the threshold; results are also identical
// on every Embree ISA path, so the margin is the same on any x86-64 CPU.
TEST(FlcMethod, FovealErrorFallsWithBudget) {
  Fixture& f = cornell(24);
  const int budgets[3] = {4, 32, 256};
  const int n = 24;
  std::vector<double> r[3];
  for (int b = 0; b < 3; ++b)
    for (int seed = 1; seed <= n; ++seed)
      r[b].push_back(f.run(Json{{"vpl_budget", budgets[b]}, {"samples", 128}, {"seed", seed}})
                         .counters.get(Counter::flc_rmse_fovea));
  for (int b = 0; b < 2; ++b) {
    double m = 0, m2 = 0;
    auto d = [&](int k) { return std::log(r[b][size_t(k)] / r[b + 1][size_t(k)]); };
    for (int k = 0; k < n; ++k) m += d(k) / n;
    for (int k = 0; k < n; ++k) m2 += std::pow(d(k) - m, 2) / (n - 1);
    const double t = m / std::sqrt(m2 / n);
    std::printf("budget %d -> %d: mean log RMSE ratio %.3g, paired t = %.2f\n", budgets[b],
                budgets[b + 1], m, t);
    EXPECT_GT(t, 3.0) << "budget " << budgets[b] << " -> " << budgets[b + 1];
  }
}

TEST(FlcMethod, TauAboveOneWithGazeOnAWall) {
  Fixture& f = cornell(24);
  double tau = 0;
  for (int seed = 1; seed <= 3; ++seed) {
    FrameOutput o =
        f.run(Json{{"vpl_budget", 64}, {"samples", 128}, {"seed", seed}, {"w_periphery", 0.25}});
    tau += o.counters.get(Counter::flc_tau) / 3;
  }
  EXPECT_GT(tau, 1.0);
}

TEST(FlcMethod, ExtremesStayFinite) {
  Fixture& f = cornell(8);
  // Budget 0: only direct light.
  FrameOutput z = f.run(Json{{"vpl_budget", 0}});
  EXPECT_EQ(z.counters.get(Counter::vpls_kept), 0.0);
  EXPECT_EQ(max_abs_diff(z.image, f.fd.direct), 0.0);
  EXPECT_TRUE(all_finite(f.fd.reference));
  // Zero importance map (delta = 0 after a first frame -> p_b = 0), tiny clamp, every mode.
  Fixture tiny(1.6, 32, 8, 1e-9);
  for (const char* vis : {"none", "blso", "exact"}) {
    Params p(Json{{"vpl_budget", 10}, {"delta", 0.0}, {"visibility", vis}});
    auto m = make_method("flc", p);
    FrameContext ctx = tiny.fd.context(tiny.scene, *tiny.renderer, tiny.display, true);
    for (int k = 0; k < 2; ++k) {
      FrameOutput o;
      ctx.frame = k;
      render_with_lighting(*m, ctx, o);
      EXPECT_TRUE(all_finite(o.image)) << vis;
      EXPECT_LE(o.counters.get(Counter::vpls_kept), 10.0);
      EXPECT_TRUE(std::isfinite(o.counters.get(Counter::flc_tau)));
      EXPECT_FALSE(o.debug.empty());
    }
  }
  // Log-polar with interleaving: fewer shaded samples, finite.
  FrameOutput lp = f.run(Json{{"log_polar", true}, {"lp_sigma", 2.0}, {"interleave", 2}});
  EXPECT_TRUE(all_finite(lp.image));
  EXPECT_LT(lp.counters.get(Counter::shaded_samples), 0.5 * f.display.width * f.display.height);
}

TEST(FlcMethod, NoVplsWhenTheLightIsOff) {
  Fixture dark(0.0, 16, 8);
  FrameOutput o = dark.run(Json::object());
  EXPECT_EQ(o.counters.get(Counter::vpls_total), 0.0);
  EXPECT_EQ(o.counters.get(Counter::vpls_kept), 0.0);
  EXPECT_TRUE(all_finite(o.image));
  EXPECT_EQ(max_abs_diff(o.image, dark.fd.reference), 0.0);
}

TEST(FlcMethod, DeterministicAcrossThreadCounts) {
  Fixture& f = cornell();
  const Json p{{"vpl_budget", 50}, {"samples", 64}, {"seed", 9}};
  FrameOutput a, b;
  tbb::task_arena(1).execute([&] { a = f.run(p); });
  tbb::task_arena(2).execute([&] { b = f.run(p); });
  EXPECT_EQ(max_abs_diff(a.image, b.image), 0.0);
  EXPECT_EQ(a.counters.get(Counter::vpls_kept), b.counters.get(Counter::vpls_kept));
  FrameOutput c = f.run(Json{{"vpl_budget", 50}, {"samples", 64}, {"seed", 10}});
  EXPECT_GT(max_abs_diff(a.image, c.image), 0.0);
}

TEST(FlcMethod, ParameterErrorsNameTheKey) {
  Params p1(Json{{"vpl_budget", -1}}, "cfg.json", "methods[0]");
  try {
    make_method("flc", p1);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("vpl_budget"), std::string::npos) << e.what();
  }
  Params p2(Json{{"visibility", "raytraced"}}, "cfg.json", "methods[0]");
  EXPECT_THROW(make_method("flc", p2), Error);
  Params p3(Json{{"vpl_budgte", 10}}, "cfg.json", "methods[0]");
  EXPECT_THROW(make_method("flc", p3), Error);
  // VPL generation moved to the scene: the old key says where it went.
  Params p4(Json{{"rsm_size", 16}}, "cfg.json", "methods[0]");
  try {
    make_method("flc", p4);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("scene.vpl.rsm_size"), std::string::npos) << e.what();
  }
}

// Tracking loss with trace.on_invalid = widen (docs/tracking.md): FLC's foveal region of
// eq. 5 grows by k = FrameContext::widen (more acuity importance, so the shading points and
// the VPL budget cover a larger region), and its log-polar shading buffer grows by k per axis
// (more shaded samples). k = 1 is bit-identical to a frame without the policy.
TEST(FlcMethod, WidenGrowsTheFovealRegionAndTheShadedFraction) {
  Fixture& f = cornell();
  auto run = [&](const Json& params, double k) {
    Params p(params);
    auto m = make_method("flc", p);
    FrameContext ctx = f.fd.context(f.scene, *f.renderer, f.display, true);
    ctx.widen = k;
    FrameOutput out;
    render_with_lighting(*m, ctx, out);
    return out;
  };
  auto acuity_sum = [](const FrameOutput& o) {
    for (auto& [name, img] : o.debug)
      if (name == "acuity") {
        double s = 0;
        for (float v : img.data) s += v;
        return s;
      }
    return -1.0;
  };
  const Json lp{{"log_polar", true}, {"lp_sigma", 2.0}, {"vpl_budget", 50}};
  const FrameOutput base = f.run(lp);
  const FrameOutput one = run(lp, 1.0);
  EXPECT_EQ(one.image.data, base.image.data);
  double prev_shaded = one.counters.get(Counter::shaded_samples), prev_acuity = acuity_sum(one);
  ASSERT_GT(prev_acuity, 0.0);
  for (double k : {1.2, 1.5, 1.9}) {
    const FrameOutput o = run(lp, k);
    const double n = o.counters.get(Counter::shaded_samples), a = acuity_sum(o);
    std::printf("[widen] flc k=%.1f shaded %.0f acuity sum %.1f\n", k, n, a);
    EXPECT_GT(n, prev_shaded) << k;
    EXPECT_GT(a, prev_acuity) << k;
    prev_shaded = n;
    prev_acuity = a;
  }
}
