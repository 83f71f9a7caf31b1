// JOD decisions below native resolution (sim/experiment/jod_fidelity.h): the measured bias is
// carried into a constraint's feasibility, an unmeasured scale says it needs native resolution.
#include "sim/experiment/jod_fidelity.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "sim/experiment/intervals.h"
#include "sim/experiment/sweep_spec.h"

using namespace fovsim;

TEST(JodFidelity, RecordPerScale) {
  const Json n = jod_fidelity_record(1.0, 18.7);
  EXPECT_TRUE(n["native"].get<bool>());
  EXPECT_FALSE(n["needs_native"].get<bool>());
  EXPECT_EQ(jod_bias_of(n, "fvvdp_jod_fl"), 0.0);
  EXPECT_FALSE(n.contains("note"));
  ASSERT_FALSE(jod_bias_rungs().empty());
  for (const JodBiasRung& r : jod_bias_rungs()) {
    const Json j = jod_fidelity_record(r.scale, 18.7);
    EXPECT_FALSE(j["needs_native"].get<bool>()) << r.scale;
    EXPECT_EQ(jod_bias_of(j, "fvvdp_jod_fl"), r.fvvdp_jod_fl);
    EXPECT_EQ(jod_bias_of(j, "fvvdp_jod_lo"), r.fvvdp_jod);
    EXPECT_GT(r.fvvdp_jod_fl, 0.0);
    EXPECT_NEAR(j["ppd_simulated"].get<double>(), 18.7 * r.scale, 1e-12);
  }
  const Json u = jod_fidelity_record(0.3, 18.7);  // not a measured rung
  EXPECT_TRUE(u["needs_native"].get<bool>());
  EXPECT_TRUE(std::isnan(jod_bias_of(u, "fvvdp_jod")));
  EXPECT_NE(u["note"].get<std::string>().find("needs native resolution"), std::string::npos);
  EXPECT_TRUE(std::isnan(jod_bias_of(n, "psnr")));  // not a JOD column
  EXPECT_EQ(jod_metric_of("fvvdp_jod_fl_ci95"), "fvvdp_jod_fl");
  EXPECT_EQ(jod_metric_of("fvvdp_jod_hi"), "fvvdp_jod");
  EXPECT_EQ(jod_metric_of("fvvdp_jodx"), "");
}

TEST(JodFidelity, MeasuredBiasDecidesFeasibility) {
  const JodBiasRung r = jod_bias_rungs().back();
  SearchSpec sp;
  SearchConstraint c;
  c.column = "fvvdp_jod_fl";
  c.min = 8.0;
  sp.constraints.push_back(c);
  const Json at = jod_fidelity_record(r.scale, 18.7), nat = jod_fidelity_record(1.0, 18.7);
  const JodJudgement j = judge_jod(c, at);
  EXPECT_EQ(j.margin, r.fvvdp_jod_fl);
  EXPECT_FALSE(j.needs_native);
  // A value above the threshold by less than the bias could flip at native resolution: not
  // feasible at the reduced scale, feasible at native.
  const double v = 8.0 + 0.5 * r.fvvdp_jod_fl;
  EXPECT_GT(sp.violation({v}, {j.margin}), 0.0);
  EXPECT_EQ(sp.violation({v}, {judge_jod(c, nat).margin}), 0.0);
  EXPECT_EQ(sp.violation({8.0 + 1.5 * r.fvvdp_jod_fl}, {j.margin}), 0.0);
  // An upper limit takes the margin on the other side.
  SearchSpec up;
  SearchConstraint cu = c;
  cu.min = -INFINITY;
  cu.max = 9.0;
  up.constraints.push_back(cu);
  EXPECT_GT(up.violation({9.0 - 0.5 * r.fvvdp_jod_fl}, {j.margin}), 0.0);
  EXPECT_NE(jod_verdict_sentence(c, j, at).find("judged with the measured bias"),
            std::string::npos);
  EXPECT_EQ(jod_verdict_sentence(c, judge_jod(c, nat), nat), "");
  // Unmeasured scale: judged as it is, and the verdict says so.
  const Json u = jod_fidelity_record(0.08, 18.7);
  const JodJudgement ju = judge_jod(c, u);
  EXPECT_TRUE(ju.needs_native);
  EXPECT_EQ(ju.margin, 0.0);
  EXPECT_NE(jod_verdict_sentence(c, ju, u).find("the answer needs native resolution"),
            std::string::npos);
  // Another column is never touched.
  SearchConstraint other;
  other.column = "psnr";
  other.min = 30;
  EXPECT_EQ(judge_jod(other, at).margin, 0.0);
  EXPECT_FALSE(judge_jod(other, u).needs_native);
}

TEST(JodFidelity, PairedRowsCarryTheJodBias) {
  const JodBiasRung r = jod_bias_rungs().front();
  const Json fid{{"render_scale", r.scale},
                 {"known_bias", nullptr},
                 {"jod", jod_fidelity_record(r.scale, 18.7)}};
  EXPECT_EQ(fidelity_bias(fid, "fvvdp_jod", 7, 8), r.fvvdp_jod);
  EXPECT_EQ(fidelity_bias(fid, "fvvdp_jod_fl", 7, 8), r.fvvdp_jod_fl);
  const Json native{{"jod", jod_fidelity_record(1.0, 18.7)}};
  EXPECT_EQ(fidelity_bias(native, "fvvdp_jod_fl", 7, 8), 0.0);
}
