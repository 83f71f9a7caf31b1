// What a tracking-loss policy costs (docs/tracking.md "What each policy costs"): the widened
// parameters of each method, the lost frame of `full`, and the expected frame time.
#include "sim/cost/tracking_cost.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/cost/analytic.h"
#include "sim/foveation/factory.h"
#include "tests/common/method_lists.h"

using namespace fovsim;

namespace {
const std::string kModels = std::string(FOVSIM_SOURCE_DIR) + "/models";
}

TEST(TrackingCost, WidenedParametersPerMethod) {
  bool modelled = false;
  Json k = widened_method_params("kfr", Json::object(), 1.5, &modelled);
  EXPECT_TRUE(modelled);
  EXPECT_DOUBLE_EQ(k["sigma"].get<double>(), 1.8 / 1.5);
  EXPECT_DOUBLE_EQ(widened_method_params("kfr", Json{{"sigma", 1.2}}, 2, nullptr)["sigma"], 1.0);
  Json r = widened_method_params("rmfr", Json{{"fy_px", 100}}, 2, nullptr);
  EXPECT_DOUBLE_EQ(r["sigma"].get<double>(), 1.3);
  EXPECT_DOUBLE_EQ(r["fx"].get<double>(), 0.76);
  EXPECT_DOUBLE_EQ(r["fy_px"].get<double>(), 200);
  EXPECT_FALSE(r.contains("fy"));
  EXPECT_DOUBLE_EQ(widened_method_params("fvrs", Json::object(), 1.5, nullptr)["radius_scale"],
                   1.5);
  EXPECT_DOUBLE_EQ(widened_method_params("flc", Json{{"log_polar", true}}, 4, nullptr)["lp_sigma"],
                   1.0);
  // An analytic-only key (predict's filter_taps_per_pixel, shaded_fraction) is not the method's
  // parser's, yet the method's own keys still widen and the analytic key is kept for the
  // analytic parse (before, the parse failed on it and nothing widened, silently).
  const Json ka = widened_method_params(
      "kfr", Json{{"sigma", 1.2}, {"filter_taps_per_pixel", 3}, {"shaded_fraction", 0.3}}, 2,
      nullptr);
  EXPECT_DOUBLE_EQ(ka["sigma"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(ka["filter_taps_per_pixel"].get<double>(), 3);
  EXPECT_DOUBLE_EQ(ka["shaded_fraction"].get<double>(), 0.3);
  // rmfr_auto renders through rmfr, which widens its RS-buffer in a run: its own sigma key
  // widens the same way (its f_x, f_y are not keys).
  const Json ra = widened_method_params("rmfr_auto", Json{{"f_sum", 0.6}}, 2, nullptr);
  EXPECT_DOUBLE_EQ(ra["sigma"].get<double>(), 1.3);
  EXPECT_DOUBLE_EQ(ra["f_sum"].get<double>(), 0.6);
  EXPECT_FALSE(ra.contains("fx"));
  widened_method_params("twfr", Json::object(), 1.5, &modelled);
  EXPECT_FALSE(modelled);
  // k = 1: the parameters as given.
  const Json given{{"sigma", 2.0}};
  EXPECT_EQ(widened_method_params("kfr", given, 1, nullptr), given);
  EXPECT_EQ(lost_frame_method("kfr", OnInvalid::Full), "full");
  EXPECT_EQ(lost_frame_method("kfr", OnInvalid::Widen), "kfr");
  EXPECT_DOUBLE_EQ(expected_ms_with_loss(10, 16, 0.25), 11.5);
}

// A widened lost frame costs more than a tracked one and at most a full render, for every
// foveated method with an analytic cost.
TEST(TrackingCost, WidenedFramesCostMoreUpToAFullFrame) {
  const GpuProfile g = GpuProfile::load("gtx1080", kModels);
  const Workload w = Workload::load("kfr_bistro", kModels);
  const Display d = Display::load("htc_vive_pro_eye", kModels);
  const double full = analytic_frame(g, "full", Json::object(), w, d).total_ms;
  for (const std::string& name : methods_with_sampling_geometry()) {  // from the registry
    const char* m = name.c_str();
    const double valid = analytic_frame(g, m, Json::object(), w, d).total_ms;
    double prev = valid;
    for (double k : {1.25, 1.5, 2.0}) {
      const double lost =
          analytic_frame(g, m, widened_method_params(m, Json::object(), k, nullptr), w, d).total_ms;
      std::printf("[loss] %s k=%.2f %.3f ms (tracked %.3f, full %.3f)\n", m, k, lost, valid, full);
      EXPECT_GT(lost, prev) << m << " k=" << k;
      EXPECT_LE(lost, full * 1.05) << m << " k=" << k;
      prev = lost;
    }
  }
}

// predict resolves an iso-budget target before reading the columns (Ye et al. 2022 §5.1): the
// shaded fraction is the target and the frame is cheaper than the configured one.
TEST(AnalyticCounters, IsoBudgetTargetIsSolvedBeforeTheColumns) {
  const GpuProfile g = GpuProfile::load("gtx1080", kModels);
  const Workload w = Workload::load("kfr_bistro", kModels);
  Display d = Display::load("htc_vive_pro_eye", kModels);
  d.width = 360, d.height = 400;  // a quarter per axis: the solver runs over every pixel
  const double P = double(d.width) * d.height;
  for (const std::string& m : test::iso_budget_methods()) {
    const Json iso{{"target_shaded_fraction", 0.1}};
    const Counters c = analytic_counters(m, iso, w, d, "test");
    // The solver matches the samples a run shades (kfr: the LP-buffer slots that land on the
    // screen); predict charges kfr's and rmfr's whole W/sigma x H/sigma buffer, a little more.
    const double f = c.get(Counter::shaded_samples) / P;
    EXPECT_GE(f, 0.1 - 0.005) << m;
    EXPECT_LE(f, 0.1 + 0.02) << m;
    const double ms = analytic_frame(g, m, iso, w, d).total_ms;
    // kfr and rmfr shade more than 10% by default (sigma 1.8, 2.6): the target is cheaper.
    if (m == "kfr" || m == "rmfr") {
      EXPECT_LT(ms, analytic_frame(g, m, Json::object(), w, d).total_ms) << m;
    }
    // Under tracking loss a run widens the resolved geometry: the lost frame costs more.
    const Json lost = widened_method_params(m, iso, 1.5, nullptr, &d);
    EXPECT_FALSE(lost.contains("target_shaded_fraction")) << m;
    EXPECT_GT(analytic_frame(g, m, lost, w, d).total_ms, ms) << m;
  }
}
