#include "sim/experiment/intervals.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "sim/core/error.h"
#include "sim/core/stats.h"
#include "sim/experiment/runner.h"
#include "sim/experiment/summary.h"
#include "sim/metrics/fvvdp.h"

namespace fovsim {
namespace {

ResultRow frame_row(const std::string& id, const std::string& gpu, int frame, double psnr,
                    double ms) {
  ResultRow r;
  r.set_text("config_id", id);
  r.set_text("gpu", gpu);
  r.set("sigma", 1.8);
  r.set("frame", frame);
  r.set("t", frame / 90.0);
  r.set("est_ms_total", ms);
  r.set("psnr", psnr);
  r.set("ref_ms", 3.0 + frame);
  return r;
}

TEST(Intervals, SummaryHasHalfWidthsOnlyForAggregates) {
  ResultTable f;
  for (int i = 0; i < 40; ++i) f.add(frame_row("a", "g", i, 30.0 + (i % 2), 5.0));
  for (int i = 0; i < 5; ++i) f.add(frame_row("short", "g", i, 30.0, 5.0));
  ResultTable s = summarize(f, 11.1);
  ASSERT_EQ(s.rows().size(), 2u);
  const ResultRow& a = s.rows()[0];
  EXPECT_DOUBLE_EQ(a.get("psnr", NAN), 30.5);
  // Batches of 4 frames alternate 30, 31: every batch mean is 30.5, so the interval is exact.
  EXPECT_DOUBLE_EQ(a.get("psnr_ci95", NAN), 0.0);
  EXPECT_DOUBLE_EQ(a.get("est_ms_total_ci95", NAN), 0.0);
  for (const char* col : {"frame_ci95", "t_ci95", "ref_ms_ci95", "sigma_ci95"})
    EXPECT_TRUE(std::isnan(a.get(col, NAN))) << col;  // never written
  auto cols = s.numeric_columns();
  EXPECT_EQ(std::count(cols.begin(), cols.end(), "ref_ms_ci95"), 0);
  EXPECT_EQ(std::count(cols.begin(), cols.end(), "sigma_ci95"), 0);
  EXPECT_EQ(*a.text_of("ci_method"), "batch_means");
  EXPECT_EQ(*a.text_of("ci_missing"), "");
  // Below kCiShortMinSamples frames the interval is undefined, the mean still reported, and
  // `ci_missing` says why, naming the columns.
  const ResultRow& sh = s.rows()[1];
  EXPECT_DOUBLE_EQ(sh.get("psnr", NAN), 30.0);
  EXPECT_TRUE(std::isnan(sh.get("psnr_ci95", 0.0)));
  EXPECT_EQ(*sh.text_of("ci_method"), "");
  EXPECT_EQ(*sh.text_of("ci_missing"),
            "est_ms_total psnr: 5 finite frames (an interval needs >= 8)");
  const std::vector<std::string> notes = interval_notes(s);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0],
            "no 95% interval for est_ms_total, psnr (short): 5 finite frames (an interval needs "
            ">= 8) (summary.csv ci_missing; docs/intervals.md)");
}

// 8..19 frames: the short-run interval (sim/core/stats.h), named in ci_method and in a note.
TEST(Intervals, ShortRunsGetTheShortRunInterval) {
  ResultTable f;
  std::vector<double> v;
  for (int i = 0; i < 12; ++i) {
    v.push_back(30 + std::sin(1.3 * i));
    f.add(frame_row("a", "g", i, v.back(), 5.0));
  }
  ResultTable s = summarize(f, 11.1);
  const ResultRow& a = s.rows()[0];
  EXPECT_DOUBLE_EQ(a.get("psnr_ci95", NAN), short_run_interval(v).half_width);
  EXPECT_GT(a.get("psnr_ci95", NAN), 0.0);
  EXPECT_EQ(*a.text_of("ci_method"), "short_run");
  const std::vector<std::string> notes = interval_notes(s);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("short-run t-intervals"), std::string::npos) << notes[0];
}

TEST(Intervals, SummaryHalfWidthMatchesBatchMeans) {
  ResultTable f;
  std::vector<double> v;
  for (int i = 0; i < 50; ++i) {
    v.push_back(std::sin(0.3 * i) + 0.01 * i);
    f.add(frame_row("a", "g", i, v.back(), 1.0));
  }
  ResultTable s = summarize(f, 11.1);
  EXPECT_DOUBLE_EQ(s.rows()[0].get("psnr_ci95", NAN), batch_means_interval(v).half_width);
}

TEST(Intervals, PairedDifferencesMatchFramesAndGpus) {
  ResultTable f;
  // b is a shifted by -0.5 dB on every frame, rows of b in reverse frame order; c differs by
  // noise only in sign-alternating pairs; d is on another GPU and is never paired.
  for (int i = 0; i < 40; ++i) f.add(frame_row("a", "g", i, 30.0 + 0.1 * i, 5.0));
  for (int i = 39; i >= 0; --i) f.add(frame_row("b", "g", i, 29.5 + 0.1 * i, 4.0));
  for (int i = 0; i < 40; ++i)
    f.add(frame_row("c", "g", i, 30.0 + 0.1 * i + (i % 2 ? 0.2 : -0.2), 5.0));
  for (int i = 0; i < 40; ++i) f.add(frame_row("d", "h", i, 10.0, 1.0));
  ResultTable p = paired_differences(f);
  int rows_ab = 0;
  for (auto& r : p.rows()) {
    const std::string& a = *r.text_of("config_a");
    const std::string& b = *r.text_of("config_b");
    EXPECT_NE(a, "d");
    EXPECT_NE(b, "d");
    const std::string& m = *r.text_of("metric");
    EXPECT_TRUE(m == "psnr" || m == "est_ms_total") << m;  // only headline metrics present
    EXPECT_DOUBLE_EQ(r.get("frames", 0), 40);
    if (a == "a" && b == "b") {
      ++rows_ab;
      double want = m == "psnr" ? 0.5 : 1.0;
      EXPECT_NEAR(r.get("diff", NAN), want, 1e-12);
      EXPECT_NEAR(r.get("diff_ci95", NAN), 0.0, 1e-12);
      EXPECT_DOUBLE_EQ(r.get("differs", NAN), 1);
    }
    if (a == "a" && b == "c" && m == "psnr") {
      EXPECT_NEAR(r.get("diff", NAN), 0.0, 1e-12);  // +-0.2 cancels within each batch of 4
      EXPECT_NEAR(r.get("diff_ci95", NAN), 0.0, 1e-12);
      EXPECT_NEAR(r.get("mean_a", NAN) - r.get("mean_b", NAN), r.get("diff", NAN), 1e-12);
    }
    if (a == "a" && b == "c" && m == "est_ms_total") {
      EXPECT_DOUBLE_EQ(r.get("differs", NAN), 0);
    }
  }
  EXPECT_EQ(rows_ab, 2);
  EXPECT_EQ(p.rows().size(), 3u * 2u);  // (a,b), (a,c), (b,c) x 2 metrics
}

// paired.csv has a row for every metric the docs recommend reading pairwise: the latency
// study's rmse_fovea_fl (docs/latency.md) and rmse_fovea, rmse_periphery and its _fl, beside
// the headline metrics.
TEST(Intervals, PairedHasTheRegionErrorsAndTheirFoveationLoss) {
  for (const char* m : {"rmse_fovea", "rmse_fovea_fl", "rmse_periphery", "rmse_periphery_fl"}) {
    const auto& pm = paired_metrics();
    EXPECT_NE(std::find(pm.begin(), pm.end(), m), pm.end()) << m;
  }
  ResultTable f;
  for (int i = 0; i < 40; ++i) {
    ResultRow a = frame_row("lat0", "g", i, 30, 5), b = frame_row("lat50", "g", i, 30, 5);
    a.set("rmse_fovea_fl", 0.010 + 0.001 * (i % 3));
    b.set("rmse_fovea_fl", 0.014 + 0.001 * (i % 3));  // +0.004 on every frame
    a.set("rmse_fovea", 0.2);
    b.set("rmse_fovea", 0.2);
    f.add(a);
    f.add(b);
  }
  ResultTable p = paired_differences(f);
  std::map<std::string, const ResultRow*> by;
  for (auto& r : p.rows()) by[*r.text_of("metric")] = &r;
  ASSERT_TRUE(by.count("rmse_fovea_fl"));
  ASSERT_TRUE(by.count("rmse_fovea"));
  EXPECT_FALSE(by.count("rmse_periphery"));  // not in the frames table
  EXPECT_NEAR(by["rmse_fovea_fl"]->get("diff", NAN), -0.004, 1e-12);
  EXPECT_NEAR(by["rmse_fovea_fl"]->get("diff_ci95", NAN), 0.0, 1e-12);
  EXPECT_EQ(by["rmse_fovea_fl"]->get("differs", NAN), 1.0);
  EXPECT_EQ(by["rmse_fovea"]->get("differs", NAN), 0.0);
  // The console's headline list is unchanged (the region errors are not headline metrics).
  const auto& h = headline_metrics();
  EXPECT_EQ(std::find(h.begin(), h.end(), "rmse_fovea_fl"), h.end());
}

TEST(Intervals, PairedSkipsNonFiniteFramesAndIsUndefinedWhenShort) {
  ResultTable f;
  for (int i = 0; i < 25; ++i) f.add(frame_row("full", "g", i, INFINITY, 6.0));
  for (int i = 0; i < 25; ++i) f.add(frame_row("kfr", "g", i, 30.0, 3.0));
  ResultTable p = paired_differences(f);
  for (auto& r : p.rows()) {
    if (*r.text_of("metric") == "psnr") {
      EXPECT_DOUBLE_EQ(r.get("frames", -1), 0);
      EXPECT_TRUE(std::isnan(r.get("diff", 0)));
      EXPECT_TRUE(std::isnan(r.get("differs", 0)));
    } else {
      EXPECT_DOUBLE_EQ(r.get("diff", NAN), 3.0);
      EXPECT_DOUBLE_EQ(r.get("diff_ci95", NAN), 0.0);
    }
  }
}

}  // namespace
}  // namespace fovsim

namespace fovsim {
namespace {

// FovVideoVDP pools Q over the frames and maps the mean to JOD (sim/metrics/registry.h
// Pooling::sequence): the summary's fvvdp_jod is the JOD of the mean Q, not the mean of per-frame
// JODs; its interval is the batch-means interval of Q mapped through the JOD regression.
TEST(Intervals, SequencePooledMetricSummaryAndPairedDifference) {
  ResultTable f;
  for (int i = 0; i < 40; ++i) {
    ResultRow a = frame_row("a", "g", i, 30, 5), b = frame_row("b", "g", i, 28, 4);
    const double qa = 10 + (i % 7), qb = 30 + 2 * (i % 5);
    a.set("fvvdp_q", qa);
    a.set("fvvdp_jod", fvvdp_jod_from_q(qa));
    b.set("fvvdp_q", qb);
    b.set("fvvdp_jod", fvvdp_jod_from_q(qb));
    f.add(a);
    f.add(b);
  }
  ResultTable s = summarize(f, 11.1);
  std::vector<double> qa;
  for (auto& r : f.rows())
    if (*r.text_of("config_id") == "a") qa.push_back(r.get("fvvdp_q", NAN));
  MeanInterval ci = batch_means_interval(qa);
  const ResultRow& sa = s.rows()[0];
  EXPECT_DOUBLE_EQ(sa.get("fvvdp_jod", NAN), fvvdp_jod_from_q(ci.mean));
  EXPECT_DOUBLE_EQ(sa.get("fvvdp_jod_lo", NAN), fvvdp_jod_from_q(ci.hi()));
  EXPECT_DOUBLE_EQ(sa.get("fvvdp_jod_hi", NAN), fvvdp_jod_from_q(ci.lo()));
  EXPECT_DOUBLE_EQ(sa.get("fvvdp_jod_ci95", NAN),
                   0.5 * (fvvdp_jod_from_q(ci.lo()) - fvvdp_jod_from_q(ci.hi())));
  EXPECT_GT(sa.get("fvvdp_jod", NAN), s.rows()[1].get("fvvdp_jod", NAN));
  ResultTable p = paired_differences(f);
  bool seen = false;
  for (auto& r : p.rows()) {
    if (*r.text_of("metric") != "fvvdp_jod") continue;
    seen = true;
    EXPECT_DOUBLE_EQ(r.get("mean_a", NAN), sa.get("fvvdp_jod", NAN));
    EXPECT_DOUBLE_EQ(r.get("diff", NAN),
                     sa.get("fvvdp_jod", NAN) - s.rows()[1].get("fvvdp_jod", NAN));
    EXPECT_TRUE(std::isfinite(r.get("diff_ci95", NAN)));
    EXPECT_EQ(r.get("differs", NAN), 1.0);  // Q 10-16 vs 30-38 on every frame
  }
  EXPECT_TRUE(seen);
}

// at_floor: a method whose per-frame rmse_fovea equals the floor's (full at the same sampling
// against the reference) is flagged; one clearly apart is not; a sequence metric is compared
// on its pooled column and named by its metric.
TEST(Intervals, ReferenceFloorIsFlagged) {
  ResultTable f;
  std::map<std::string, std::map<int, double>> floor;
  for (int i = 0; i < 40; ++i) {
    const double base = 0.08 + 0.001 * (i % 5);
    ResultRow a = frame_row("a", "g", i, 30, 5), b = frame_row("b", "g", i, 28, 4);
    a.set("rmse_fovea", base);         // the floor exactly (full-rate fovea)
    b.set("rmse_fovea", base + 0.02);  // worse on every frame
    a.set("fvvdp_q", 20 + (i % 3));
    b.set("fvvdp_q", 20 + (i % 3) + ((i % 2) ? 0.5 : -0.5));  // noise around the floor
    f.add(a);
    f.add(b);
    floor["rmse_fovea"][i] = base;
    floor["fvvdp_q"][i] = 20 + (i % 3);
    floor["psnr"][i] = 20;  // both rows far above: not at the floor
  }
  ResultTable s = summarize(f, 11.1);
  mark_reference_floor(s, f, [&floor](const std::string&) { return &floor; });
  ASSERT_EQ(s.rows().size(), 2u);
  EXPECT_EQ(*s.rows()[0].text_of("at_floor"), "fvvdp_jod rmse_fovea");
  EXPECT_EQ(*s.rows()[1].text_of("at_floor"), "fvvdp_jod");
}

TEST(Targets, ParseSpecs) {
  IntervalTarget a = parse_target("est_ms_total:1%");
  EXPECT_EQ(a.column, "est_ms_total");
  EXPECT_DOUBLE_EQ(a.value, 1.0);
  EXPECT_TRUE(a.relative);
  IntervalTarget b = parse_target("fpsnr:0.2dB");
  EXPECT_EQ(b.column, "fpsnr");
  EXPECT_DOUBLE_EQ(b.value, 0.2);
  EXPECT_FALSE(b.relative);
  EXPECT_FALSE(parse_target("ssim:0.01").relative);
  for (const char* bad :
       {"fpsnr", ":1", "fpsnr:", "fpsnr:x", "fpsnr:0", "fpsnr:-1", "fpsnr:nan", "fpsnr:1 dB",
        "fpsnr:2px", "frame:1", "sim_ms:1", "sigma:1", "psnr:100%"}) {
    try {
      parse_target(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.where(), std::string("--target ") + bad);
    }
  }
}

TEST(Targets, SamplingOrderIsASeededPermutation) {
  std::vector<int> a = sampling_order(100, 1), b = sampling_order(100, 1),
                   c = sampling_order(100, 2);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  std::vector<int> s = a;
  std::sort(s.begin(), s.end());
  for (int i = 0; i < 100; ++i) EXPECT_EQ(s[size_t(i)], i);
  EXPECT_TRUE(sampling_order(0, 1).empty());
}

TEST(Targets, MetPerConfigWithAchievedRecord) {
  ResultTable f;
  for (int i = 0; i < 40; ++i) f.add(frame_row("a", "g", i, 30.0 + (i % 4 == 0 ? 4.0 : 0.0), 5.0));
  for (int i = 0; i < 40; ++i) f.add(frame_row("full", "g", i, INFINITY, 10.0));
  // psnr of a: batches of 4 frames each hold exactly one +4 dB frame -> every batch mean is 31.
  Json ach;
  EXPECT_TRUE(targets_met({parse_target("psnr:0.1dB"), parse_target("est_ms_total:1%")}, f, &ach));
  EXPECT_DOUBLE_EQ(ach["a"]["psnr"]["mean"].get<double>(), 31.0);
  EXPECT_DOUBLE_EQ(ach["a"]["psnr"]["ci95"].get<double>(), 0.0);
  EXPECT_TRUE(ach["full"]["psnr"]["ci95"].is_null());  // inf on every frame: exact, passes
  EXPECT_TRUE(ach["full"]["psnr"]["met"].get<bool>());
  EXPECT_DOUBLE_EQ(ach["a"]["est_ms_total"]["target"].get<double>(), 0.05);
  // Shifting the spike breaks the batch alignment: the interval widens past 0.1 dB.
  ResultTable g;
  for (int i = 0; i < 40; ++i) g.add(frame_row("a", "g", i, 30.0 + (i % 7 == 0 ? 4.0 : 0.0), 5.0));
  EXPECT_FALSE(targets_met({parse_target("psnr:0.1dB")}, g, nullptr));
  // Fewer than kCiMinSamples frames: undefined interval, never met.
  ResultTable h;
  for (int i = 0; i < 10; ++i) h.add(frame_row("a", "g", i, 30.0, 5.0));
  EXPECT_FALSE(targets_met({parse_target("psnr:5dB")}, h, nullptr));
  EXPECT_THROW(targets_met({parse_target("fpsnr:1dB")}, h, nullptr), Error);  // no such column
}

}  // namespace
// A paired difference smaller than the known bias of the run's fidelity is named
// (paired.csv fidelity_bias, below_fidelity_bias; docs/fidelity.md known_bias).
TEST(Intervals, PairedDifferencesBelowTheFidelityBiasAreMarked) {
  ResultTable frames;
  for (int f = 0; f < 40; ++f) {
    frames.add(frame_row("a", "g", f, 30.0 + 0.1 * (f % 3), 10.0));
    frames.add(frame_row("b", "g", f, 29.0 + 0.1 * (f % 3), 10.5));  // a - b = +1 dB, -0.5 ms
  }
  const ResultTable paired = paired_differences(frames);
  const Json fid{{"render_scale", 0.25},
                 {"known_bias", {{"psnr_db", 2.39}, {"est_ms_total_percent", 2.27}}}};
  size_t n = 0;
  const ResultTable marked = with_fidelity_bias(paired, fid, &n);
  ASSERT_EQ(marked.rows().size(), paired.rows().size());
  for (auto& r : marked.rows()) {
    const std::string m = *r.text_of("metric");
    EXPECT_DOUBLE_EQ(r.get("differs", NAN), 1.0) << m;
    if (m == "psnr") {
      EXPECT_DOUBLE_EQ(r.get("fidelity_bias", NAN), 2.39);
      EXPECT_DOUBLE_EQ(r.get("below_fidelity_bias", NAN), 1.0);  // |1 dB| < 2.39 dB
    } else if (m == "est_ms_total") {
      EXPECT_NEAR(r.get("fidelity_bias", NAN), 0.0227 * 10.5, 1e-12);  // % of the larger mean
      EXPECT_DOUBLE_EQ(r.get("below_fidelity_bias", NAN), 0.0);        // |0.5 ms| > 0.238 ms
    }
  }
  EXPECT_EQ(n, 1u);
  // No known bias (scale >= 0.5 or an unmeasured rung): the columns are nan.
  size_t n0 = 7;
  const ResultTable none = with_fidelity_bias(paired, Json{{"known_bias", nullptr}}, &n0);
  EXPECT_EQ(n0, 0u);
  for (auto& r : none.rows()) {
    EXPECT_TRUE(std::isnan(r.get("fidelity_bias", 0)));
    EXPECT_TRUE(std::isnan(r.get("below_fidelity_bias", 0)));
  }
}

// fits_budget is the budget decision of sim/cost/budget.h on the p95 frame: p_fit against the
// level, with the row's own GPU profile's interval; not the point estimate's p95 <= budget.
TEST(Intervals, FitsBudgetIsTheProbabilityAtTheLevel) {
  ResultTable f;
  for (int i = 0; i < 30; ++i) f.add(frame_row("a@wide", "wide", i, 30.0, 10.0));
  for (int i = 0; i < 30; ++i) f.add(frame_row("a@none", "none", i, 30.0, 10.0));
  FitRule rule;
  rule.level = 0.8;
  PredictionInterval wide;  // the model is as likely 20% low as 20% high
  wide.level = 0.8;
  for (int i = 0; i < 19; ++i) wide.total_scores.push_back(-0.2 + 0.4 * i / 18.0);
  rule.intervals["wide"] = wide;
  ResultTable s = summarize(f, 11.1, &rule);
  ASSERT_EQ(s.rows().size(), 2u);
  const ResultRow& w = s.rows()[0];
  // 10 ms: log(11.1 / 10) = 0.104 is above 14 of the 19 scores (-0.2 .. 0.089): p 14.5 / 20.
  EXPECT_NEAR(w.get("p_fit", NAN), 14.5 / 20, 1e-12);
  EXPECT_EQ(w.get("fits_budget", NAN), 0);  // 0.725 < 0.8, though 10 ms < 11.1 ms
  EXPECT_NEAR(w.get("headroom_ms", NAN), 1.1, 1e-9);
  EXPECT_EQ(w.get("fit_level", NAN), 0.8);
  const double t = w.get("fit_threshold_ms", NAN);
  EXPECT_LT(t, 10.0);
  EXPECT_EQ(decide_budget(wide, t, 11.1, 0.8).fits, true);
  const ResultRow& n = s.rows()[1];  // no interval: the point estimate decides
  EXPECT_EQ(n.get("p_fit", NAN), 1.0);
  EXPECT_EQ(n.get("fits_budget", NAN), 1);
  EXPECT_EQ(n.get("fit_threshold_ms", NAN), 11.1);
  rule.level = 0.7;  // a laxer level: the same probability now fits
  ResultTable s6 = summarize(f, 11.1, &rule);
  EXPECT_EQ(s6.rows()[0].get("fits_budget", NAN), 1);
  EXPECT_EQ(s6.rows()[0].get("p_fit", NAN), w.get("p_fit", NAN));
}

}  // namespace fovsim
