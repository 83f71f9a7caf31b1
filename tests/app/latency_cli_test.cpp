// Latency what-if end to end: zero latency reproduces the golden numbers, a steady
// gaze gives identical results at any latency, a large saccade raises foveal error with latency
// during and just after the saccade but not in steady fixation, bad values exit 2 with a path.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "tests/app/app_util.h"

using namespace fovsim_test;

namespace {

std::string cfg_for(const std::string& trace, int count, const std::string& methods,
                    const std::string& latency, double scale = 0.08) {
  return R"({"name": "lat", "display": "htc_vive_pro_eye", "render": {"scale": )" +
         std::to_string(scale) + R"(, "spp": 1},
    "scene": {"type": "atrium", "complexity": 1},
    "trace": {"file": ")" +
         trace + R"("}, "frames": {"count": )" + std::to_string(count) + R"(},
    "methods": )" +
         methods + R"(, "gpus": ["gtx1080"], "outputs": {"print_summary": false})" +
         (latency.empty() ? "" : R"(, "latency": )" + latency) + "}";
}

// Canonical trace at 90 Hz, head still; gaze yaw(t) in degrees.
template <class F>
std::string write_trace(const std::string& dir, int n, F yaw_deg) {
  std::string s = "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,valid\n";
  char buf[256];
  for (int i = 0; i < n; ++i) {
    double t = i / 90.0, a = yaw_deg(t) * M_PI / 180.0;
    std::snprintf(buf, sizeof buf, "%.9f,0,0,0,1,0,0,0,%.12f,0,%.12f,1\n", t, std::sin(a),
                  -std::cos(a));
    s += buf;
  }
  write_text(dir + "/trace.csv", s);
  return dir + "/trace.csv";
}

Csv run_ok(const std::string& dir, const std::string& cfg, const std::string& sub) {
  write_text(dir + "/" + sub + ".json", cfg);
  auto r = run_cmd(fovsim_bin() + " run " + dir + "/" + sub + ".json -q --out " + dir + "/" + sub);
  EXPECT_EQ(r.code, 0) << r.output;
  return read_csv(dir + "/" + sub + "/frames.csv");
}

std::vector<double> column(const Csv& c, const std::string& name) {
  std::vector<double> v;
  int k = c.col(name);
  EXPECT_GE(k, 0) << name;
  if (k < 0) return v;
  for (auto& r : c.rows) v.push_back(std::strtod(r[size_t(k)].c_str(), nullptr));
  return v;
}

}  // namespace

TEST(LatencyCli, ZeroLatencyReproducesTheGolden) {
  std::string dir = temp_dir("lat_zero");
  auto r = run_cmd(fovsim_bin() + " run tests/golden/methods_small.json -q --out " + dir +
                   " latency.tracker_ms=0 latency.render_ms=0 latency.display_ms=0");
  ASSERT_EQ(r.code, 0) << r.output;
  Csv got = read_csv(dir + "/frames.csv"),
      want = read_csv(std::string(FOVSIM_SOURCE_DIR) + "/tests/golden/methods_small.frames.csv");
  ASSERT_EQ(got.rows.size(), want.rows.size());
  for (const char* extra :
       {"phase", "latency_ms", "gaze_est_x", "gaze_error_deg", "gaze_speed_deg_s"})
    EXPECT_GE(got.col(extra), 0) << extra;
  for (size_t k = 0; k < want.header.size(); ++k) {
    const std::string& name = want.header[k];
    if (name == "sim_ms" || name == "ref_ms") continue;
    int g = got.col(name);
    ASSERT_GE(g, 0) << name;
    for (size_t i = 0; i < want.rows.size(); ++i) {
      const std::string &a = got.rows[i][size_t(g)], &b = want.rows[i][k];
      char* end = nullptr;
      double vb = std::strtod(b.c_str(), &end);
      if (!(end && *end == '\0' && !b.empty()) || !std::isfinite(vb)) {
        EXPECT_EQ(a, b) << name;
        continue;
      }
      EXPECT_LE(std::fabs(std::strtod(a.c_str(), nullptr) - vb), 1e-6 + 1e-4 * std::fabs(vb))
          << "row " << i << " " << name;
    }
  }
  for (double e : column(got, "gaze_error_deg")) EXPECT_EQ(e, 0.0);
}

TEST(LatencyCli, SteadyGazeIsIdenticalAtAnyLatency) {
  std::string dir = temp_dir("lat_steady");
  std::string tr = write_trace(dir, 12, [](double) { return 4.0; });
  const std::string methods = R"([{"method": "kfr"}, {"method": "fvrs"}])";
  Csv a = run_ok(dir, cfg_for(tr, 8, methods, R"({})"), "l0");
  Csv b = run_ok(
      dir, cfg_for(tr, 8, methods, R"({"tracker_ms": 80, "jitter": "normal", "jitter_ms": 10})"),
      "l80");
  for (const char* m :
       {"psnr", "fpsnr", "rmse_fovea", "rmse_periphery", "shaded_samples", "est_ms_total"}) {
    int ka = a.col(m), kb = b.col(m);
    ASSERT_GE(ka, 0) << m;
    for (size_t i = 0; i < a.rows.size(); ++i)
      EXPECT_EQ(a.rows[i][size_t(ka)], b.rows[i][size_t(kb)]) << m << " row " << i;
  }
  auto lat = column(b, "latency_ms");
  EXPECT_GT(lat[1], 0.0);
}

TEST(LatencyCli, SaccadeRaisesFovealErrorOnlyDuringAndAfterIt) {
  std::string dir = temp_dir("lat_saccade");
  // Fixation at -8 deg, a 16 deg saccade at 0.2 s (main sequence: ~56 ms), fixation at +8 deg.
  auto yaw = [](double t) {
    if (t < 0.2) return -8.0;
    if (t >= 0.256) return 8.0;
    return -8.0 + 16.0 * (1 - std::cos(M_PI * (t - 0.2) / 0.056)) / 2;
  };
  std::string tr = write_trace(dir, 60, yaw);
  const std::string methods = R"([{"method": "fvrs"}])";
  // fVRS rates are display pixels (Franke et al. 2021 §8.4): at 0.4 its 4x4 rate is 2x2
  // simulated pixels (at the 0.08 of the other tests every rate is one pixel: no foveation).
  const double kScale = 0.4;
  Csv l0 = run_ok(dir, cfg_for(tr, 44, methods, R"({})", kScale), "l0");
  Csv l80 = run_ok(dir, cfg_for(tr, 44, methods, R"({"tracker_ms": 80})", kScale), "l80");
  auto t = column(l0, "t"), e0 = column(l0, "rmse_fovea"), e80 = column(l80, "rmse_fovea");
  int kp = l80.col("phase");
  ASSERT_GE(kp, 0);
  double sac0 = 0, sac80 = 0;
  int n_sac = 0, n_steady = 0;
  for (size_t i = 0; i < t.size(); ++i) {
    const std::string& ph = l80.rows[i][size_t(kp)];
    EXPECT_EQ(ph, l0.rows[i][size_t(l0.col("phase"))]);  // phases come from the true gaze
    if (ph == "saccade" || ph == "suppression") {
      sac0 += e0[i];
      sac80 += e80[i];
      ++n_sac;
    }
    // Steady fixation: the gaze 80 ms ago is the current one (before the saccade, or 80 ms
    // plus a frame after landing).
    if (t[i] < 0.2 || t[i] > 0.256 + 0.08 + 0.012) {
      EXPECT_EQ(e0[i], e80[i]) << "t=" << t[i];
      ++n_steady;
    }
  }
  ASSERT_GE(n_sac, 5);
  ASSERT_GE(n_steady, 15);
  EXPECT_GT(sac80, 1.2 * sac0) << "mean rmse_fovea in saccade+suppression: " << sac0 / n_sac
                               << " vs " << sac80 / n_sac;
}

TEST(LatencyCli, BadLatencyIsOneLineExit2) {
  std::string dir = temp_dir("lat_bad");
  auto r = run_cmd(fovsim_bin() + " run tests/golden/full_small.json -q --out " + dir +
                   " latency.tracker_ms=-3");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("latency.tracker_ms"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("[0, 1000]"), std::string::npos) << r.output;
  r = run_cmd(fovsim_bin() + " run tests/golden/full_small.json -q --out " + dir +
              " 'latency.predictor=\"oracle\"'");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("latency.predictor"), std::string::npos) << r.output;
}

TEST(LatencyCli, RenderPartFromTheEstimateIsWholeRefreshPeriods) {
  std::string dir = temp_dir("lat_est");
  auto r = run_cmd(fovsim_bin() + " run tests/golden/methods_small.json -q --out " + dir +
                   " latency.tracker_ms=5 latency.render_ms=3 latency.render_from_estimate=true");
  ASSERT_EQ(r.code, 0) << r.output;
  Csv c = read_csv(dir + "/frames.csv");
  auto lat = column(c, "latency_ms"), frame = column(c, "frame"), est = column(c, "est_ms_total");
  const double period = 1000.0 / 90.0;
  std::map<std::string, double> prev;  // label -> previous frame's est_ms_total
  int kl = c.col("label");
  for (size_t i = 0; i < lat.size(); ++i) {
    const std::string& label = c.rows[i][size_t(kl)];
    if (frame[i] == 0) {
      EXPECT_DOUBLE_EQ(lat[i], 8.0);  // no estimate yet: render_ms
    } else {
      ASSERT_TRUE(prev.count(label));
      double periods = std::max(1.0, std::ceil(prev[label] / period - 1e-9));
      EXPECT_NEAR(lat[i], 5.0 + periods * period, 1e-6) << label << " frame " << frame[i];
    }
    prev[label] = est[i];
  }
}

TEST(LatencyCli, JitterAndPredictorGiveTheSameNumbersAtAnyThreadCount) {
  std::string dir = temp_dir("lat_threads");
  const std::string ov =
      " latency.tracker_ms=30 'latency.jitter=\"normal\"' latency.jitter_ms=8 "
      "'latency.predictor=\"main_sequence\"'";
  auto a = run_cmd(fovsim_bin() + " run tests/golden/methods_small.json -q -j 1 --out " + dir +
                   "/a" + ov);
  auto b = run_cmd(fovsim_bin() + " run tests/golden/methods_small.json -q -j 2 --out " + dir +
                   "/b" + ov);
  ASSERT_EQ(a.code, 0) << a.output;
  ASSERT_EQ(b.code, 0) << b.output;
  Csv x = read_csv(dir + "/a/frames.csv"), y = read_csv(dir + "/b/frames.csv");
  ASSERT_EQ(x.header, y.header);
  ASSERT_EQ(x.rows.size(), y.rows.size());
  for (size_t i = 0; i < x.rows.size(); ++i)
    for (size_t k = 0; k < x.header.size(); ++k) {
      if (x.header[k] != "sim_ms" && x.header[k] != "ref_ms") {
        EXPECT_EQ(x.rows[i][k], y.rows[i][k]) << x.header[k];
      }
    }
}

TEST(LatencyCli, CommittedLatencyConfigsAreValid) {
  auto e = run_cmd(fovsim_bin() + " sweep expand configs/sweeps/latency.json");
  ASSERT_EQ(e.code, 0) << e.output;
  EXPECT_NE(e.output.find("4 cells"), std::string::npos) << e.output;
  EXPECT_NE(e.output.find("latency.tracker_ms=80"), std::string::npos) << e.output;
  std::string dir = temp_dir("lat_cfg");
  auto r = run_cmd(fovsim_bin() + " run configs/latency.json -q --out " + dir +
                   " frames.count=2 render.scale=0.05 'methods=[{\"method\": \"fvrs\"}]'");
  ASSERT_EQ(r.code, 0) << r.output;
  Csv c = read_csv(dir + "/frames.csv");
  auto lat = column(c, "latency_ms");
  ASSERT_EQ(lat.size(), 2u);
  EXPECT_NEAR(lat[0], 50.0, 1e-9);
}
