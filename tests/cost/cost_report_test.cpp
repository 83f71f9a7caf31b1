// Per-pass prediction intervals and the library side of the cost commands
// (what-if maths, table lists, the profile writer, calibrate/validate orchestration).
#include "sim/cost/cost_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/cost/analytic.h"
#include "sim/cost/budget.h"
#include "sim/cost/passes.h"

using namespace fovsim;

namespace {
const std::string kModels = std::string(FOVSIM_SOURCE_DIR) + "/models";

FrameCost kfr_frame(const GpuProfile& g) {
  Workload w = Workload::load("kfr_bistro", kModels);
  Display d = Display::load("desktop_1920x1080", kModels);
  Counters c = analytic_counters("kfr", Json{{"sigma", 1.8}}, w, d, "test");
  CostInputs in;
  in.method = "kfr";
  in.counters = &c;
  in.display = d;
  in.workload = &w;
  return estimate_frame(g, in);
}
}  // namespace

TEST(PassIntervals, CombineAddsHalfWidthsInQuadrature) {
  double lo = 0, hi = 0;
  combine_pass_intervals({{3, 2, 7}, {4, 1, 4}}, &lo, &hi);
  EXPECT_DOUBLE_EQ(lo, 7 - std::sqrt(1.0 + 9.0));
  EXPECT_DOUBLE_EQ(hi, 7 + 4);
  combine_pass_intervals({{5, 4, 6}}, &lo, &hi);  // one pass: its own interval
  EXPECT_DOUBLE_EQ(lo, 4);
  EXPECT_DOUBLE_EQ(hi, 6);
  combine_pass_intervals({{1, 0, 1}, {1, 0, 1}}, &lo, &hi);  // never below 0
  EXPECT_GE(lo, 0);
}

TEST(PassIntervals, PassWithoutOwnRowsTakesThePooledFactors) {
  PredictionInterval iv;
  iv.level = 0.8, iv.lo_factor = 0.7, iv.hi_factor = 2.0;
  iv.passes["lighting"] = {0.9, 1.2, 12};
  EXPECT_DOUBLE_EQ(iv.for_pass("lighting").hi_factor, 1.2);
  EXPECT_DOUBLE_EQ(iv.for_pass("skybox").hi_factor, 2.0);
  EXPECT_DOUBLE_EQ(iv.for_pass("skybox").lo_factor, 0.7);
}

// Every pass of an estimate carries its interval; the total's is combined from them.
TEST(PassIntervals, EstimatesCarryPerPassIntervals) {
  GpuProfile g = GpuProfile::load("gtx1080", kModels);
  ASSERT_GT(g.interval.level, 0);
  FrameCost fc = kfr_frame(g);
  std::vector<PassSpan> spans;
  for (auto& pc : fc.passes) {
    const IntervalFactors f = g.interval.for_pass(pc.pass);
    EXPECT_DOUBLE_EQ(pc.lo_ms, pc.ms * f.lo_factor) << pc.pass;
    EXPECT_DOUBLE_EQ(pc.hi_ms, pc.ms * f.hi_factor) << pc.pass;
    EXPECT_LE(pc.lo_ms, pc.ms);
    EXPECT_GE(pc.hi_ms, pc.ms);
    spans.push_back({pc.ms, pc.lo_ms, pc.hi_ms});
  }
  // The total's interval: split-conformal on held-out frame totals (cost model v3); without
  // total factors it combines its passes'.
  ASSERT_GT(g.interval.total.n, 0);
  EXPECT_DOUBLE_EQ(fc.total_lo_ms, fc.total_ms * g.interval.total.lo_factor);
  EXPECT_DOUBLE_EQ(fc.total_hi_ms, fc.total_ms * g.interval.total.hi_factor);
  {
    GpuProfile g2 = g;
    g2.interval.total = IntervalFactors{};
    const FrameCost f2 = kfr_frame(g2);
    double lo = 0, hi = 0;
    combine_pass_intervals(spans, &lo, &hi);
    EXPECT_DOUBLE_EQ(f2.total_lo_ms, lo);
    EXPECT_DOUBLE_EQ(f2.total_hi_ms, hi);
  }
  EXPECT_LT(fc.total_lo_ms, fc.total_ms);
  EXPECT_GT(fc.total_hi_ms, fc.total_ms);
  // Without an interval every bound is the estimate itself.
  g.interval = PredictionInterval{};
  FrameCost none = kfr_frame(g);
  EXPECT_EQ(none.interval_level, 0);
  for (auto& pc : none.passes) EXPECT_EQ(pc.lo_ms, pc.ms);
}

TEST(PassIntervals, ProfilesRoundTripAndRejectUnknownPasses) {
  GpuProfile g = GpuProfile::load("rtx2070", kModels);
  GpuProfile back = GpuProfile::from_json(g.to_json(), "rt.json");
  EXPECT_EQ(back.interval.passes.size(), g.interval.passes.size());
  EXPECT_EQ(back.residuals.size(), g.residuals.size());
  EXPECT_EQ(back.calibration_tables, g.calibration_tables);
  EXPECT_EQ(back.to_json(), g.to_json());
  Json j = g.to_json();
  j["interval"]["passes"]["nosuchpass"] = {{"lo_factor", 0.5}, {"hi_factor", 2}, {"n", 9}};
  try {
    GpuProfile::from_json(j, "rt.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nosuchpass"), std::string::npos) << e.what();
  }
}

TEST(BudgetWhatIf, FactorsAreWhatEachResourceNeeds) {
  FrameCost fc;
  fc.total_ms = 20;
  fc.resource_ms = {{"shading", 12}, {"geometry", 6}, {"fixed", 2}};
  const BudgetFactors f = budget_factors(fc, 14);
  EXPECT_DOUBLE_EQ(f.x.at("shading"), 12.0 / (14 - 8));  // shading alone must make 6 ms room
  EXPECT_TRUE(std::isinf(f.x.at("geometry")));           // 14 < 20 - 6: cannot fit alone
  EXPECT_TRUE(std::isinf(f.x.at("memory")));             // no time there, frame over budget
  EXPECT_DOUBLE_EQ(f.x_all, 18.0 / 12.0);
  EXPECT_DOUBLE_EQ(budget_factors(fc, 40).x.at("memory"), 0.0);
  // Doubling shading throughput halves the lighting pass of a shading-bound frame.
  GpuProfile g = GpuProfile::load("gtx1080", kModels);
  WhatIf wi;
  wi.shading = 2;
  const FrameCost a = kfr_frame(g), b = kfr_frame(apply_what_if(g, wi));
  EXPECT_NEAR(b.pass_ms("lighting") - g.passes.at("lighting").overhead_ms,
              (a.pass_ms("lighting") - g.passes.at("lighting").overhead_ms) / 2, 1e-9);
}

TEST(CostReport, TableListsAreCommaSeparated) {
  // Table ids parsed from text (a subset of the calibration tables).
  EXPECT_EQ(parse_id_list("kfr, rmfr,,twfr", "--tables"),
            (std::set<std::string>{"kfr", "rmfr", "twfr"}));
  EXPECT_TRUE(parse_id_list("", "--tables").empty());
  CalibrateOptions o;
  o.models = kModels;
  o.tables = {"nosuch"};
  o.write = false;
  try {
    run_calibration(o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nosuch"), std::string::npos) << e.what();
  }
}

// A dry run fits and reports without touching the models directory.
TEST(CostReport, DryRunCalibrationReportsEveryEntry) {
  CalibrateOptions o;
  o.models = kModels;
  o.write = false;
  const CalibrationRun run = run_calibration(o);
  size_t entries = 0;
  for (auto& t : run.data.tables) entries += t.entries.size();
  EXPECT_EQ(run.rows.size(), entries);
  EXPECT_GT(run.fitted_n, 50);
  EXPECT_LT(run.fitted_mean_abs_err, 0.2);
  EXPECT_TRUE(run.written.empty());
  // The committed profile is what calibrate would write from this fit (coefficients).
  GpuProfile g = calibrated_profile(run.fit, run.data, "gtx1080", PredictionInterval{}, {});
  GpuProfile c = GpuProfile::load("gtx1080", kModels);
  EXPECT_TRUE(g.calibrated);
  for (auto& [pass, pc] : c.passes)
    for (auto& [term, v] : pc.terms)
      EXPECT_NEAR(g.coef(pass, term), v, 1e-9 * std::max(1.0, std::fabs(v))) << pass << "." << term;
}

// validate-cost's outputs (report, CSV with each row's passes and interval) and the plot script
// on them (skipped without /usr/bin/python3 + matplotlib).
TEST(CostReport, ValidationOutputsAndPlot) {
  const ValidationOutputs v = run_validation(kModels);
  ASSERT_EQ(v.ranked.size(), 2u);
  EXPECT_LE(v.ranked[0].leaveout_mean, v.ranked[1].leaveout_mean);  // ranked by held-out error
  for (const char* s : {"leave-one-resolution-out: not possible", "per-pass coverage",
                        "total coverage", "kfr_table4_2_3840x2160 kfr_raymarch",
                        "twfr_fig10_8k_3840x1440 twfr_sponza", "== cross-predictions"})
    EXPECT_NE(v.report_txt.find(s), std::string::npos) << s;
  EXPECT_EQ(v.validate_csv.rfind("experiment,id,table,gpu,workload,config,row,passes,kind,", 0),
            0u);
  int totals = 0, intervals = 0;
  for (auto& r : v.report.rows) {
    totals += r.kind == "total";
    if (r.kind == "predicted") {
      double lo = 0, hi = 0;
      row_interval(v.ranked[0].interval, r.parts, &lo, &hi);
      intervals += lo <= r.model_ms && r.model_ms <= hi && !r.parts.empty();
    }
  }
  EXPECT_GT(totals, 10);
  EXPECT_EQ(intervals, v.ranked[0].leaveout_n);
  const std::string dir = ::testing::TempDir() + "fovsim_validate_cost";
  write_validation(v, dir);
  for (const char* f : {"report.txt", "validate_cost.csv", "cross_predictions.csv"})
    EXPECT_TRUE(file_exists(dir + "/" + f)) << f;
  if (std::system("/usr/bin/python3 -c 'import matplotlib' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "no /usr/bin/python3 with matplotlib: plot not checked";
  const std::string cmd = "/usr/bin/python3 '" + std::string(FOVSIM_SOURCE_DIR) +
                          "/viz/plot_cost.py' '" + dir + "/validate_cost.csv' '" + dir +
                          "/validate_cost.png' >/dev/null 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  EXPECT_TRUE(file_exists(dir + "/validate_cost.png"));
}
