#include "sim/experiment/startup.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/core/error.h"
#include "sim/experiment/runner.h"
#include "sim/experiment/search_runner.h"
#include "sim/experiment/summary.h"

namespace fovsim {
namespace {

ResultRow row(const std::string& label, int frame, double ms, double q) {
  ResultRow r;
  r.set_text("config_id", label);
  r.set_text("label", label);
  r.set("frame", frame);
  r.set("est_ms_total", ms);
  r.set("fvvdp_q", q);
  r.set("fvvdp_jod", 10 - 0.01 * q);
  return r;
}

StartupPlan plan_of(int settle) {
  StartupPlan p;
  p.method_frames = {{"twfr", 1}, {"rmfr", 0}};
  StartupPlan::Metric m;
  m.name = "fvvdp_jod";
  m.frames = settle;
  m.seconds = settle / 90.0;
  m.columns = {"fvvdp_q", "fvvdp_q_fl", "fvvdp_jod", "fvvdp_jod_fl"};
  p.metrics.push_back(m);
  return p;
}

// TWFR's cold first frame (187 ms) is left out of its means, the metric's settle frames out of
// the metric's columns; frames.csv (the input) is unchanged, and the manifest and note say so.
TEST(Startup, WarmupAndSettleFramesLeaveTheMeans) {
  ResultTable f;
  for (int i = 0; i < 30; ++i) {
    f.add(row("twfr", i, i == 0 ? 187.0 : 21.6 + 0.1 * (i % 3), i < 15 ? 100.0 : 1.0));
    f.add(row("rmfr", i, 9.0, i < 15 ? 100.0 : 2.0));
  }
  const StartupPlan plan = plan_of(15);
  StartupReport rep;
  const ResultTable means = exclude_startup(f, plan, rep);
  EXPECT_EQ(means.rows().size(), 59u);  // twfr's first row dropped
  ResultTable s = summarize(means, 11.1);
  mark_startup(s, rep, plan);
  const ResultRow& tw = s.rows()[0];
  EXPECT_EQ(*tw.text_of("label"), "twfr");
  EXPECT_EQ(tw.get("frames", NAN), 29.0);
  EXPECT_EQ(tw.get("startup_frames", NAN), 1.0);
  EXPECT_LT(tw.get("est_ms_total", NAN), 22.0);
  EXPECT_LT(tw.get("est_ms_total_ci95", NAN), 0.2);
  EXPECT_DOUBLE_EQ(tw.get("fvvdp_q", NAN), 1.0);  // the 15 settle frames (Q = 100) left out
  EXPECT_DOUBLE_EQ(s.rows()[1].get("fvvdp_q", NAN), 2.0);
  EXPECT_EQ(s.rows()[1].get("startup_frames", NAN), 0.0);
  EXPECT_EQ(rep.manifest["methods"]["twfr"], 1);
  EXPECT_EQ(rep.manifest["metrics"]["fvvdp_jod"]["frames_excluded"], 15);
  ASSERT_EQ(rep.notes.size(), 1u);
  EXPECT_NE(rep.notes[0].find("twfr 1 frame (warm-up)"), std::string::npos) << rep.notes[0];
  EXPECT_NE(rep.notes[0].find("fvvdp_jod columns 15 frames"), std::string::npos);

  // frames.include_startup: nothing left out.
  StartupPlan inc = plan;
  inc.include = true;
  StartupReport r2;
  EXPECT_EQ(exclude_startup(f, inc, r2).rows().size(), 60u);
  EXPECT_EQ(r2.manifest["excluded"], false);
  // frames.warmup frames rendered before count towards both.
  StartupPlan warm = plan;
  warm.warmup_rendered = 20;
  StartupReport r3;
  EXPECT_EQ(exclude_startup(f, warm, r3).rows().size(), 60u);
  EXPECT_TRUE(r3.notes.empty());
}

// A run shorter than the settle time + 8 frames keeps the settling frames in the metric's mean,
// has no interval for it, and says so (ci_missing, a note); a search constraint on its bound is
// refused with that reason.
TEST(Startup, TooShortToSettleHasNoIntervalAndASearchRefusesItsBound) {
  ResultTable f;
  for (int i = 0; i < 12; ++i) f.add(row("rmfr", i, 9.0 + 0.1 * (i % 2), 50.0 + i));
  const StartupPlan plan = plan_of(15);
  StartupReport rep;
  const ResultTable means = exclude_startup(f, plan, rep);
  ResultTable s = summarize(means, 11.1);
  // The sequence metric's _lo/_hi as summarize writes them for a pooled metric.
  mark_startup(s, rep, plan);
  const ResultRow& r = s.rows()[0];
  EXPECT_TRUE(std::isfinite(r.get("fvvdp_q", NAN)));
  EXPECT_TRUE(std::isnan(r.get("fvvdp_q_ci95", 0.0)));
  EXPECT_TRUE(std::isfinite(r.get("est_ms_total_ci95", NAN)));  // the short-run interval
  const std::string missing = *r.text_of("ci_missing");
  EXPECT_NE(missing.find("fvvdp_q fvvdp_jod: the run's 12 frames leave fewer than 8 after "
                         "fvvdp_jod's settle time of 15 frames"),
            std::string::npos)
      << missing;
  EXPECT_TRUE(rep.notes.empty());  // interval_notes names it
  const std::vector<std::string> notes = interval_notes(s);
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_EQ(notes[0].rfind("no 95% interval for fvvdp_jod (rmfr): the run's 12 frames", 0), 0u)
      << notes[0];

  ResultRow scored = r;
  scored.set("fvvdp_jod_lo", NAN);
  SearchSpec sp;
  sp.objective.column = "est_ms_total";
  SearchConstraint c;
  c.column = "fvvdp_jod_lo";
  c.min = 9.5;
  sp.constraints.push_back(c);
  try {
    refuse_undefined_bounds(scored, sp, "s.json");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("s.json: sweep.search.subject_to.fvvdp_jod_lo"), std::string::npos) << m;
    EXPECT_NE(m.find("the 95% interval of fvvdp_jod is undefined (the run's 12 frames"),
              std::string::npos)
        << m;
  }
  sp.constraints[0].column = "est_ms_total_ci95";  // defined: accepted
  EXPECT_NO_THROW(refuse_undefined_bounds(scored, sp, "s.json"));
}

}  // namespace
}  // namespace fovsim
