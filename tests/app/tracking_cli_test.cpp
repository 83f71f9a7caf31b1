// Tracking loss end to end (docs/tracking.md): per-state means with intervals in summary.csv
// and on the console; `full` charges a lost frame what a full render costs; `widen` makes
// every foveated method shade (and cost) more on lost frames; valid frames are unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "tests/app/app_util.h"

using namespace fovsim_test;

namespace {

// 30 frames at 90 Hz, head still, gaze sweeping slowly; samples 10-19 invalid (a blink).
std::string write_blink_trace(const std::string& dir) {
  std::string s = "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,valid\n";
  char buf[256];
  for (int i = 0; i < 30; ++i) {
    const double a = (-6.0 + 0.4 * i) * M_PI / 180.0;
    std::snprintf(buf, sizeof buf, "%.9f,0,0,0,1,0,0,0,%.12f,0,%.12f,%d\n", i / 90.0, std::sin(a),
                  -std::cos(a), (i >= 10 && i < 20) ? 0 : 1);
    s += buf;
  }
  write_text(dir + "/blink.csv", s);
  return dir + "/blink.csv";
}

std::string cfg(const std::string& trace, const std::string& policy) {
  return R"({"name": "trk", "display": "htc_vive_pro_eye", "render": {"scale": 0.06, "spp": 1},
    "scene": {"type": "atrium", "complexity": 1},
    "trace": {"file": ")" +
         trace + R"(", "on_invalid": ")" + policy + R"("}, "frames": {"count": 30},
    "methods": [{"method": "full"}, {"method": "kfr"}, {"method": "rmfr"}, {"method": "linear"}],
    "gpus": ["gtx1080"]})";
}

struct PolicyRun {
  Csv frames, summary;
  std::string console;
};

PolicyRun run_policy(const std::string& dir, const std::string& trace, const std::string& policy) {
  write_text(dir + "/" + policy + ".json", cfg(trace, policy));
  auto r = run_cmd(fovsim_bin() + " run " + dir + "/" + policy + ".json --no-plots --out " + dir +
                   "/" + policy);
  EXPECT_EQ(r.code, 0) << r.output;
  return {read_csv(dir + "/" + policy + "/frames.csv"),
          read_csv(dir + "/" + policy + "/summary.csv"), r.output};
}

// summary.csv value of `col` for the row whose label is `label`.
double at(const Csv& s, const std::string& label, const std::string& col) {
  const int kl = s.col("label"), kc = s.col(col);
  EXPECT_GE(kc, 0) << col;
  if (kl < 0 || kc < 0) return NAN;
  for (auto& r : s.rows)
    if (r[size_t(kl)] == label) return std::strtod(r[size_t(kc)].c_str(), nullptr);
  ADD_FAILURE() << "no row " << label;
  return NAN;
}

}  // namespace

TEST(TrackingCli, PerStateMeansPolicyCostAndWidenOnEveryMethod) {
  const std::string dir = temp_dir("tracking");
  const std::string trace = write_blink_trace(dir);
  const PolicyRun hold = run_policy(dir, trace, "hold");
  const PolicyRun full = run_policy(dir, trace, "full");
  const PolicyRun widen = run_policy(dir, trace, "widen");

  // Per-state means next to the overall ones; the per-frame text is not a summary column.
  EXPECT_LT(hold.summary.col("tracking"), 0);
  // The config's methods (cfg above: a subset, one of each kind a policy treats differently).
  for (const char* m : {"full", "kfr", "rmfr", "linear"}) {
    EXPECT_EQ(at(hold.summary, m, "frames_valid"), 20.0) << m;
    EXPECT_EQ(at(hold.summary, m, "frames_held"), 10.0) << m;
    EXPECT_EQ(at(hold.summary, m, "frames_lost"), 0.0) << m;
    // 20 valid frames: a batch-means interval; 10 held frames: below 20, undefined (nan).
    EXPECT_TRUE(std::isfinite(at(hold.summary, m, "est_ms_total_valid_ci95"))) << m;
    EXPECT_TRUE(std::isnan(at(hold.summary, m, "est_ms_total_held_ci95"))) << m;
    // The overall mean is the frame-weighted mean of the state means.
    const double all = at(hold.summary, m, "est_ms_total");
    const double w = (20 * at(hold.summary, m, "est_ms_total_valid") +
                      10 * at(hold.summary, m, "est_ms_total_held")) /
                     30;
    EXPECT_NEAR(all, w, 1e-9 * std::fabs(all)) << m;
  }
  EXPECT_NE(hold.console.find("per tracking state"), std::string::npos) << hold.console;
  EXPECT_NE(hold.console.find(" held "), std::string::npos) << hold.console;

  // `full`: every method's lost frames are charged as a full render.
  const double full_held = at(full.summary, "full", "est_ms_total_held");
  // The config's foveated methods (a subset, cfg above).
  for (const char* m : {"kfr", "rmfr", "linear"}) {
    EXPECT_EQ(at(full.summary, m, "shaded_fraction_held"), 1.0) << m;
    EXPECT_NEAR(at(full.summary, m, "est_ms_total_held"), full_held, 1e-9 * full_held) << m;
    EXPECT_LT(at(hold.summary, m, "est_ms_total_held"), full_held) << m;
  }
  // `widen`: every foveated method shades more and costs more on the lost frames; the valid
  // frames are the same as under `hold` (none of these methods is temporal; the config's
  // subset, cfg above).
  for (const char* m : {"kfr", "rmfr", "linear"}) {
    EXPECT_GT(at(widen.summary, m, "shaded_fraction_held"),
              at(hold.summary, m, "shaded_fraction_held"))
        << m;
    EXPECT_GT(at(widen.summary, m, "est_ms_total_held"), at(hold.summary, m, "est_ms_total_held"))
        << m;
    EXPECT_EQ(at(widen.summary, m, "est_ms_total_valid"), at(hold.summary, m, "est_ms_total_valid"))
        << m;
  }
}
