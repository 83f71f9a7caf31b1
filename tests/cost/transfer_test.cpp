// Absolute times across papers: passes a leave-one-paper-out refit never measured are costed
// from their nominal work (bytes or flops per unit, from the papers' algorithms) at the pooled
// efficiency of their resource; the held-out papers' frame totals, their speedups, and the
// coverage of the totals' intervals on the shipped calibration tables.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "sim/cost/calibration.h"
#include "sim/cost/passes.h"
#include "sim/cost/validate.h"

using namespace fovsim;

namespace {
const std::string kModels = std::string(FOVSIM_SOURCE_DIR) + "/models";

struct Shipped {
  CalData data;
  CostFit fit;
  ValidationReport rep;
};

const Shipped& shipped() {
  static const Shipped s = [] {
    Shipped x;
    x.data = load_calibration(kModels);
    FitOptions o;  // roofline, the committed profiles' model
    x.fit = fit_cost_model(x.data, o);
    x.rep = validate_cost(x.data, x.fit, o);
    return x;
  }();
  return s;
}
}  // namespace

// A pass no fitted row measured takes nominal work / pooled efficiency; an RSM is a shadow map
// with three render targets; a measured pass keeps its fitted theta.
TEST(CostTransfer, UnseenPassesTakeNominalWorkAtPooledEfficiency) {
  const Shipped& s = shipped();
  FitOptions o;
  // A subset of the calibration tables: TWFR left out, reprojection, SSAO, tonemap unseen.
  o.tables = {"kfr", "rmfr", "flc"};
  const CostFit f = fit_cost_model(s.data, o);
  EXPECT_TRUE(f.unseen("ssao"));
  EXPECT_TRUE(f.unseen("reproject"));
  EXPECT_FALSE(f.unseen("taa"));
  ASSERT_TRUE(f.efficiency.count(Resource::Memory));
  const double eff = f.efficiency.at(Resource::Memory);
  EXPECT_GT(eff, 0.05);
  EXPECT_LT(eff, 20.0);
  EXPECT_NEAR(prior_theta(f, "ssao", "pixels"), nominal_work("ssao", "pixels") / eff, 1e-9);
  EXPECT_GT(f.prior_overhead_ms, 0.0);
  const GpuProfile g = profile_from_fit(f, "rtx2070", s.data);
  const double rate = g.spec.rate_per_ms(Resource::Memory);
  EXPECT_NEAR(g.coef("reproject", "pixels") * rate, nominal_work("reproject", "pixels") / eff,
              1e-6);
  EXPECT_NEAR(g.passes.at("ssao").overhead_ms, f.prior_overhead_ms, 1e-12);
  // A subset, FLC left out: its RSM pass is costed like KFR's and RMFR's shadow maps.
  FitOptions o2;
  o2.tables = {"kfr", "rmfr", "twfr"};
  const CostFit f2 = fit_cost_model(s.data, o2);
  ASSERT_TRUE(f2.unseen("rsm"));
  std::string like;
  EXPECT_EQ(nominal_work("rsm", "texels", &like), 3.0);
  EXPECT_EQ(like, "shadow.shadow_texels");
  EXPECT_NEAR(prior_theta(f2, "rsm", "texels"),
              3.0 * std::max(1.0, f2.theta.at("shadow.shadow_texels")), 1e-9);
  // The full fit measured every pass: no prior is used, the committed coefficients hold.
  for (const std::string& p : known_passes()) EXPECT_FALSE(s.fit.unseen(p)) << p;
}

// Leave-one-paper-out mean |rel err| of the held-out frame totals: <= 25% for every paper, FLC
// (Yang et al. 2021) included since its post-antialiasing is costed in taps (eq. 15's clamp
// window) and its contribution pass in the FP32 work of eqs. 12-14 per BLSO lookup; and the
// other papers no worse than before FLC's passes were explained (KFR 7.1%, RMFR 4.1%, TWFR
// 12.3%), TWFR's since its reprojection is a point-sprite warp plus push-pull (Franke et al.
// 2021 §4-§5) costed as two dispatches.
TEST(CostTransfer, LeaveOnePaperOutTotalsWithin25Percent) {
  const Shipped& s = shipped();
  const std::map<std::string, double> before = {
      {"kfr", 0.071}, {"rmfr", 0.041}, {"twfr", 0.123}, {"flc", 0.25}};
  int checked = 0;
  for (const TransferError& e : lopo_errors(s.rep, s.data)) {
    ASSERT_GT(e.totals_n, 0) << e.table;
    EXPECT_LE(e.totals_mean, 0.25) << e.table;
    ASSERT_TRUE(before.count(e.table)) << e.table;
    EXPECT_LE(e.totals_mean, before.at(e.table) + 5e-4) << e.table;
    ++checked;
  }
  EXPECT_EQ(checked, 4);
}

// Franke et al. 2021 §4-§5: the reprojection is a warp of one pixel-sized point sprite per
// previous pixel (primitive-bound) followed by push-pull and the confidence (bytes); fitted,
// the push-pull bytes are within 2x of their stated work at the other papers' pooled memory
// efficiency (not a flagged residual), and the sprites cost within 2x of a depth-pass
// triangle at the peak primitive rate.
TEST(CostTransfer, ReprojectionIsAWarpThenAFill) {
  const Shipped& s = shipped();
  const auto& pr = s.rep.lopo_priors.at("twfr");
  const double eff = pr.at("efficiency.memory");
  const double fill =
      s.fit.theta.at("reproject.fill_pixels") / (nominal_work("reproject", "fill_pixels") / eff);
  EXPECT_GT(fill, 0.5);
  EXPECT_LT(fill, 2.0);
  std::string like;
  EXPECT_EQ(nominal_work("reproject", "sprites", &like), 1.0);
  EXPECT_EQ(like, "depth.tris");
  EXPECT_GE(s.fit.theta.at("reproject.sprites"), 1.0);
  EXPECT_LT(s.fit.theta.at("reproject.sprites"), 2.0);
  EXPECT_EQ(term_stage("reproject", "sprites"), term_stage("reproject", "pixels"));
  EXPECT_NE(term_stage("reproject", "sprites"), term_stage("reproject", "fill_pixels"));
  EXPECT_EQ(term_stage("reproject", "holes"), term_stage("reproject", "fill_pixels"));
}

// Yang et al. 2021 §6: post-antialiasing reads a 3x3 Gaussian (9), the TAA clamp window eta^2
// (eq. 15, mean 451 over a square display with the gaze at the centre) and history + motion
// (2) per pixel; the mean depends on the aspect ratio only, not on the resolution.
TEST(CostTransfer, FlcPostAaTapsFollowEq15) {
  const double sq = post_aa_taps_per_pixel(1024, 1024);
  EXPECT_GT(sq, 455.0);
  EXPECT_LT(sq, 470.0);
  EXPECT_NEAR(post_aa_taps_per_pixel(2048, 2048), sq, 0.01 * sq);
  EXPECT_NEAR(post_aa_taps_per_pixel(1920, 1080), sq, 0.02 * sq);
  EXPECT_EQ(post_aa_taps_per_pixel(0, 1080), 0.0);
  EXPECT_DOUBLE_EQ(contribution_flops(10, 80), 10 * kEq14FlopsPerPair + 80 * kBlsoFlopsPerLookup);
}

// What the stated work explains: post-antialiasing's fitted bytes per tap are within 2x of the
// nominal 8 B at the other papers' pooled memory efficiency; the contribution pass stays a flagged
// residual (3-8x the FP32 work eqs. 12-14 state, at peak rate), not fitted away.
TEST(CostTransfer, FlcResidualsAreReportedNotFitted) {
  const Shipped& s = shipped();
  const auto& pr = s.rep.lopo_priors.at("flc");
  const double eff_mem = pr.count("efficiency.memory") ? pr.at("efficiency.memory") : 1.0;
  const double post = s.fit.theta.at("post_aa.taps") / (nominal_work("post_aa", "taps") / eff_mem);
  EXPECT_GT(post, 0.5);
  EXPECT_LT(post, 2.0);
  EXPECT_FALSE(pr.count("efficiency.shading"));  // no other paper states a shading pass's flops
  const double contrib =
      s.fit.theta.at("contribution.flops") / nominal_work("contribution", "flops");
  EXPECT_GT(contrib, 3.0);
  EXPECT_LT(contrib, 8.0);
}

// The papers' own speedups (baseline over their method) from the held-out totals stay within
// 10% of the published ones for KFR and RMFR, 20% for TWFR: its reprojection and SSAO, which no
// other paper measures, cost 3.6x and 3.8x their stated bytes at the other papers' pooled memory
// efficiency (flagged residuals), so its foveated frame comes out fast (+5% to +18%).
TEST(CostTransfer, LeaveOnePaperOutSpeedupsWithin10Percent) {
  const Shipped& s = shipped();
  int n = 0;
  for (const TransferSpeedup& sp : lopo_speedups(s.rep, s.data)) {
    if (sp.fov == "fvrs") continue;  // TWFR's competitor, not a method of a calibration table
    EXPECT_LE(std::fabs(sp.model / sp.published - 1), sp.table == "twfr" ? 0.20 : 0.10)
        << sp.table << " " << sp.workload << " " << sp.row << " " << sp.fov;
    ++n;
  }
  EXPECT_GE(n, 6);
}

// The frame totals' 80% intervals, calibrated on the other papers' held-out totals only, cover
// 70-90% of every held-out total (leave-one-scene-out and leave-one-paper-out).
TEST(CostTransfer, TotalIntervalsCoverWithinTarget) {
  const Shipped& s = shipped();
  const ModelSummary m = summarize_model(s.rep, CostModelKind::Roofline, 0.8);
  ASSERT_GE(m.total_coverage_n, 30);
  EXPECT_GE(m.total_coverage, 0.70);
  EXPECT_LE(m.total_coverage, 0.90);
  for (const CoverageStat& c : m.total_cov) {
    EXPECT_LE(c.wilson_lo, c.coverage);
    EXPECT_GE(c.wilson_hi, c.coverage);
    EXPECT_GT(c.median_half_width, 0.0);
  }
}

// The held-out scene's triangle cost is refit through the roofline: its baseline G-buffer row
// is reproduced even where the other papers' fit left triangles below the fragment or byte
// bound (KFR's and RMFR's Bistro G-buffer rows were 67% and 25% low with the linear refit).
TEST(CostTransfer, RooflineRefitReachesTheBaselineGbufferRow) {
  const Shipped& s = shipped();
  int n = 0;
  for (const ValidationRow& r : s.rep.rows) {
    if (r.kind != "refit" || r.parts.size() != 1 || r.parts[0].pass != "gbuffer") continue;
    if (r.experiment != "cross:fit all but kfr -> predict kfr" &&
        r.experiment != "cross:fit all but rmfr -> predict rmfr")
      continue;
    EXPECT_NEAR(r.model_ms, r.published_ms, 0.01 * r.published_ms) << r.experiment;
    ++n;
  }
  EXPECT_EQ(n, 2);
}
