// Latency what-if: config validation with located errors, gaze at t - latency, the
// saccade detector against the synthetic generator's ground truth, the main-sequence predictor.
#include "sim/experiment/latency.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/trace/synth.h"

using namespace fovsim;

namespace {

LatencyConfig parse(const Json& lat) {
  Params root(Json{{"latency", lat}}, "run.json");
  LatencyConfig c = LatencyConfig::from_params(root);
  root.finish();
  return c;
}

std::string err_of(const Json& lat) {
  try {
    parse(lat);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

glm::dvec3 dir_deg(double yaw_deg) {
  double a = yaw_deg * 3.14159265358979323846 / 180.0;
  return {std::sin(a), 0.0, -std::cos(a)};
}

// 1 kHz trace: fixation at -10 deg, one 20 deg saccade (main sequence: 65 ms) at 0.3 s, fixation.
Trace step_trace() {
  Trace tr;
  for (int i = 0; i <= 800; ++i) {
    double t = i * 1e-3, yaw = -10;
    if (t >= 0.3)
      yaw = t >= 0.365 ? 10 : -10 + 20 * (1 - std::cos(3.14159265358979 * (t - 0.3) / 0.065)) / 2;
    TraceSample s;
    s.t = t;
    s.gaze_dir = dir_deg(yaw);
    tr.samples.push_back(s);
  }
  return tr;
}

}  // namespace

TEST(Latency, AbsentBlockIsDisabledAndDefaultsAreStated) {
  Params root(Json::object(), "run.json");
  EXPECT_FALSE(LatencyConfig::from_params(root).enabled);
  LatencyConfig c = parse(Json::object());
  EXPECT_TRUE(c.enabled);
  EXPECT_EQ(c.total_ms(0, c.render_ms), 0.0);
  EXPECT_EQ(c.saccade_deg_s, 75.0);
  EXPECT_EQ(c.suppression_ms, 50.0);
  LatencyConfig d = parse(Json{{"tracker_ms", 10}, {"render_ms", 11.1}, {"display_ms", 5}});
  EXPECT_NEAR(d.total_ms(3, d.render_ms), 26.1, 1e-12);
}

TEST(Latency, BadValuesNameTheJsonPathAndRange) {
  std::string e = err_of(Json{{"tracker_ms", -5}});
  EXPECT_NE(e.find("run.json: latency.tracker_ms"), std::string::npos) << e;
  EXPECT_NE(e.find("[0, 1000]"), std::string::npos) << e;
  e = err_of(Json{{"jitter", "gamma"}});
  EXPECT_NE(e.find("latency.jitter"), std::string::npos) << e;
  EXPECT_NE(e.find("normal"), std::string::npos) << e;
  e = err_of(Json{{"predictor", "kalman"}});
  EXPECT_NE(e.find("latency.predictor"), std::string::npos) << e;
  e = err_of(Json{{"saccade", {{"velocity_threshold_deg_s", 0}}}});
  EXPECT_NE(e.find("latency.saccade.velocity_threshold_deg_s"), std::string::npos) << e;
  e = err_of(Json{{"tracker", 5}});
  EXPECT_NE(e.find("latency.tracker"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown"), std::string::npos) << e;
  e = err_of(Json{{"display_ms", "5"}});
  EXPECT_NE(e.find("latency.display_ms"), std::string::npos) << e;
}

TEST(Latency, JitterIsSeededPerFrameAndNeverNegative) {
  LatencyConfig c =
      parse(Json{{"tracker_ms", 5}, {"jitter", "normal"}, {"jitter_ms", 10}, {"seed", 3}});
  double sum = 0, sum2 = 0;
  const int n = 4000;
  for (int f = 0; f < n; ++f) {
    double l = c.total_ms(f, 0);
    EXPECT_GE(l, 0.0);
    EXPECT_EQ(l, c.total_ms(f, 0));  // same frame, same value (any order, any thread)
    sum += l;
    sum2 += l * l;
  }
  // Truncation at 0 lifts the mean of N(5, 10) to 5 + 10 * phi(0.5)/Phi(0.5)-ish... just bound it.
  double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_GT(mean, 5.0);
  EXPECT_LT(mean, 12.0);
  EXPECT_GT(sd, 5.0);
  EXPECT_LT(sd, 10.5);
  LatencyConfig u = parse(Json{{"jitter", "uniform"}, {"jitter_ms", 8}});
  for (int f = 0; f < 200; ++f) {
    EXPECT_GE(u.total_ms(f, 0), 0.0);
    EXPECT_LT(u.total_ms(f, 0), 8.0);
  }
}

TEST(Latency, GazeAtTMinusLatencyAndConstantGazeIgnoresLatency) {
  Trace tr = step_trace();
  LatencyConfig c = parse(Json::object());
  // During fixation after the saccade, 50 ms of latency shows the landing point...
  TraceSample s = estimated_gaze(tr, 0.6, 0.05, 1 / 90.0, c);
  EXPECT_NEAR(angle_deg(s.gaze_dir, dir_deg(10)), 0.0, 1e-9);
  // ... and just after landing still the start point.
  s = estimated_gaze(tr, 0.37, 0.08, 1 / 90.0, c);
  EXPECT_NEAR(angle_deg(s.gaze_dir, dir_deg(-10)), 0.0, 1e-9);
  // Before the trace starts the first sample is held.
  s = estimated_gaze(tr, 0.01, 0.08, 1 / 90.0, c);
  EXPECT_NEAR(angle_deg(s.gaze_dir, dir_deg(-10)), 0.0, 1e-9);
  Trace flat;
  for (int i = 0; i < 100; ++i)
    flat.samples.push_back({i * 0.01, {}, {1, 0, 0, 0}, dir_deg(3), true});
  for (double l : {0.0, 0.02, 0.05, 0.08, 0.5})
    EXPECT_EQ(estimated_gaze(flat, 0.7, l, 1 / 90.0, c).gaze_dir, flat.samples[0].gaze_dir);
}

TEST(Latency, PhasesOfAStepSaccade) {
  Trace tr = step_trace();
  LatencyConfig c = parse(Json::object());
  const double p = 1 / 90.0;
  EXPECT_EQ(gaze_phase(tr, 0.2, p, c), GazePhase::Fixation);
  EXPECT_EQ(gaze_phase(tr, 0.33, p, c), GazePhase::Saccade);
  EXPECT_EQ(gaze_phase(tr, 0.40, p, c), GazePhase::Suppression);  // 35 ms after landing
  EXPECT_EQ(gaze_phase(tr, 0.45, p, c), GazePhase::Fixation);     // > 50 ms + half a period
  LatencyConfig wide = parse(Json{{"saccade", {{"suppression_ms", 100}}}});
  EXPECT_EQ(gaze_phase(tr, 0.45, p, wide), GazePhase::Suppression);
}

TEST(Latency, MainSequencePredictorLandsNearTheTarget) {
  Trace tr = step_trace();
  LatencyConfig none = parse(Json::object());
  LatencyConfig ms = parse(Json{{"predictor", "main_sequence"}});
  const double p = 1 / 90.0;
  auto err = [&](const LatencyConfig& c, double t) {
    return angle_deg(estimated_gaze(tr, t, 0.08, p, c).gaze_dir, dir_deg(10));
  };
  // The system has the gaze at 0.34 s (before the velocity peak is passed): the main-sequence
  // amplitude moves the estimate towards the landing point.
  EXPECT_LT(err(ms, 0.42), err(none, 0.42));
  // At 0.35 s (past the peak) the symmetric-profile estimate lands close to the target.
  EXPECT_GT(err(none, 0.43), 2.0);
  EXPECT_LT(err(ms, 0.43), 0.5 * err(none, 0.43));
  // In fixation the predictor changes nothing.
  EXPECT_EQ(estimated_gaze(tr, 0.7, 0.08, p, ms).gaze_dir,
            estimated_gaze(tr, 0.7, 0.08, p, none).gaze_dir);
}

TEST(Latency, DetectorFindsTheGeneratorsSaccades) {
  Display d = Display::load("htc_vive_pro_eye", std::string(FOVSIM_SOURCE_DIR) + "/models");
  EyeModel m;
  SynthOptions o;
  o.scenario = "free-viewing";
  o.duration_s = 30;
  o.seed = 5;
  SynthDebug dbg;
  Trace truth = synth_internal(m, o, d, &dbg);
  Trace tracked = synthesize(m, o, d);  // 90 Hz, tracker noise
  LatencyConfig c = parse(Json::object());
  const double p = 1 / 90.0;
  // Events of the ground truth with amplitude >= 4 deg: detected on at least one frame.
  int events = 0, found = 0, det = 0, det_true = 0;
  const auto& ph = dbg.phase;
  for (size_t i = 1; i < ph.size(); ++i) {
    if (ph[i] == SynthDebug::Saccade && ph[i - 1] != SynthDebug::Saccade) {
      size_t j = i;
      while (j + 1 < ph.size() && ph[j + 1] == SynthDebug::Saccade) ++j;
      double amp = angle_deg(truth.samples[i - 1].gaze_dir, truth.samples[j].gaze_dir);
      if (amp < 4) continue;
      ++events;
      bool hit = false;
      for (double t = truth.samples[i].t; t <= truth.samples[j].t + p; t += p / 4)
        hit = hit || gaze_phase(tracked, t, p, c) == GazePhase::Saccade;
      found += hit;
    }
  }
  // Every detected saccade frame lies within one period of a true saccade sample.
  for (const auto& s : tracked.samples) {
    if (gaze_phase(tracked, s.t, p, c) != GazePhase::Saccade) continue;
    ++det;
    bool near = false;
    for (double t = s.t - p; t <= s.t + p && !near; t += 1e-3) {
      size_t k = size_t(std::lround(t * 1000));
      near = k < ph.size() && ph[k] == SynthDebug::Saccade;
    }
    det_true += near;
  }
  ASSERT_GT(events, 40);
  EXPECT_GE(double(found) / events, 0.95) << found << "/" << events;
  ASSERT_GT(det, 40);
  EXPECT_GE(double(det_true) / det, 0.9) << det_true << "/" << det;
}
