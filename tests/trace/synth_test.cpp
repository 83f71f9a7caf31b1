#include "sim/trace/synth.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "sim/core/files.h"
#include "sim/trace/stats.h"
#include "test_util.h"

using namespace fovsim;
using namespace fovsim::test;

namespace {

struct Saccade {
  size_t on, off;  // sample indices: velocity above threshold on intervals (on, off]
  double amp_deg, dur_ms, peak_deg_s;
};

// Velocity-threshold saccade detection on an eye-in-head signal (I-VT, Salvucci & Goldberg 2000).
std::vector<Saccade> detect(const Trace& tr, double thr_deg_s) {
  std::vector<Saccade> out;
  const auto& x = tr.samples;
  size_t i = 1;
  while (i < x.size()) {
    double dt = x[i].t - x[i - 1].t;
    double v = rad2deg(angle_between(x[i].gaze_dir, x[i - 1].gaze_dir)) / dt;
    if (v <= thr_deg_s) {
      ++i;
      continue;
    }
    Saccade s{i - 1, i, 0, 0, 0};
    while (i < x.size()) {
      double vi = rad2deg(angle_between(x[i].gaze_dir, x[i - 1].gaze_dir)) / (x[i].t - x[i - 1].t);
      if (vi <= thr_deg_s) break;
      s.peak_deg_s = std::max(s.peak_deg_s, vi);
      s.off = i++;
    }
    s.amp_deg = rad2deg(angle_between(x[s.on].gaze_dir, x[s.off].gaze_dir));
    s.dur_ms = (x[s.off].t - x[s.on].t) * 1e3;
    out.push_back(s);
  }
  return out;
}

EyeModel model(const Json& overrides) {
  return load_eye_model(overrides, "test", "params", "");
}

SynthOptions opts(const std::string& scenario, double dur, uint64_t seed = 7) {
  SynthOptions o;
  o.scenario = scenario;
  o.duration_s = dur;
  o.seed = seed;
  return o;
}

}  // namespace

TEST(Synth, DefaultJsonEqualsBuiltInDefaults) {
  Json file = Params::parse_json_file(src("models/eyemodel/default.json"));
  EyeModel m = load_eye_model(Json(src("models/eyemodel/default.json")), "", "", "");
  EXPECT_EQ(m.to_json(), EyeModel().to_json());
  file.erase("comment");
  file.erase("sources");
  // Every key in the file is a model key (with the same value as the built-in default).
  Json flat_file = file.flatten(), flat_model = EyeModel().to_json().flatten();
  for (auto it = flat_file.begin(); it != flat_file.end(); ++it) {
    ASSERT_TRUE(flat_model.contains(it.key())) << it.key();
    EXPECT_DOUBLE_EQ(it.value().get<double>(), flat_model[it.key()].get<double>()) << it.key();
  }
  EXPECT_EQ(flat_file.size(), flat_model.size());
}

TEST(Synth, ParameterErrorsNameThePath) {
  expect_error(
      [] {
        load_eye_model(Json{{"saccade", {{"vmaxx", 500}}}}, "run.json", "trace.synthetic.params",
                       "");
      },
      {"run.json: trace.synthetic.params.saccade.vmaxx", "unknown key"});
  expect_error(
      [] {
        load_eye_model(Json{{"saccade", {{"vmax_deg_s", 5}}}}, "run.json", "trace.synthetic.params",
                       "");
      },
      {"trace.synthetic.params.saccade.vmax_deg_s", "out of range [50, 2000]"});
  expect_error(
      [] {
        load_eye_model(Json{{"fixation", {{"min_ms", 900}, {"max_ms", 500}}}}, "r.json", "p", "");
      },
      {"fixation.min_ms", "must not exceed"});
  expect_error(
      [] { load_eye_model(Json("no_such_file.json"), "r.json", "trace.synthetic.params", "/tmp"); },
      {"r.json: trace.synthetic.params", "not found"});
  EXPECT_THROW(synth_internal(EyeModel(), opts("dancing", 1), vive()), Error);
}

// Main sequence (docs/architecture.md "Inputs: displays, traces, scenes, configs"): duration = 21
// ms + 2.2 ms/deg; Vpeak = Vmax (1 - exp(-A/C)).
TEST(Synth, SaccadesFollowTheMainSequence) {
  EyeModel m =
      model(Json{{"head", {{"eye_only_range_deg", 90}}}});  // head still: eye-in-head = gaze
  Trace tr = synth_internal(m, opts("free-viewing", 60), vive());
  auto sac = detect(tr, 5.0);
  std::vector<double> A, D;
  for (auto& s : sac)
    if (s.amp_deg >= 2.0) {
      A.push_back(s.amp_deg);
      D.push_back(s.dur_ms);
      double vp = m.sac_vmax_deg_s * (1 - std::exp(-s.amp_deg / m.sac_c_deg));
      EXPECT_NEAR(s.peak_deg_s, vp, 0.1 * vp) << "A=" << s.amp_deg;
    }
  ASSERT_GT(A.size(), 80u);
  double ma = std::accumulate(A.begin(), A.end(), 0.0) / A.size(),
         md = std::accumulate(D.begin(), D.end(), 0.0) / D.size();
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < A.size(); ++i) {
    sxy += (A[i] - ma) * (D[i] - md);
    sxx += (A[i] - ma) * (A[i] - ma);
  }
  double slope = sxy / sxx, icpt = md - slope * ma;
  EXPECT_NEAR(slope, 2.2, 0.25);
  EXPECT_NEAR(icpt, 21.0, 3.0);
  // Peak velocity saturates below Vmax.
  double vmax = 0;
  for (auto& s : sac) vmax = std::max(vmax, s.peak_deg_s);
  EXPECT_LT(vmax, m.sac_vmax_deg_s);
  EXPECT_GT(vmax, 350.0);
}

TEST(Synth, FixationDurationsInRange) {
  EyeModel m = model(Json{{"head", {{"eye_only_range_deg", 90}}}});
  Trace tr = synth_internal(m, opts("free-viewing", 60, 11), vive());
  auto sac = detect(tr, 5.0);
  ASSERT_GT(sac.size(), 100u);
  std::vector<double> fix;
  for (size_t i = 1; i < sac.size(); ++i)
    fix.push_back((tr.samples[sac[i].on].t - tr.samples[sac[i - 1].off].t) * 1e3);
  double mean = std::accumulate(fix.begin(), fix.end(), 0.0) / fix.size();
  EXPECT_GT(mean, 240.0);
  EXPECT_LT(mean, 310.0);
  std::sort(fix.begin(), fix.end());
  EXPECT_GE(fix.front(), m.fix_min_ms - 2);
  double median = fix[fix.size() / 2];
  EXPECT_GT(median, 200.0);
  EXPECT_LT(median, 400.0);
}

TEST(Synth, PursuitGainAndCatchUpSaccades) {
  EyeModel m;
  SynthDebug dbg;
  Trace tr = synth_internal(m, opts("pursuit", 20), vive(), &dbg);
  std::vector<double> ratio;
  int saccades = 0;
  double max_err = 0;
  for (size_t i = 1; i < dbg.phase.size(); ++i) {
    if (dbg.phase[i] == SynthDebug::Saccade && dbg.phase[i - 1] != SynthDebug::Saccade) ++saccades;
    if (dbg.phase[i] != SynthDebug::Pursuit || dbg.phase[i - 1] != SynthDebug::Pursuit) continue;
    double vt = angle_between(dbg.target_world[i], dbg.target_world[i - 1]);
    double ve = angle_between(dbg.gaze_world[i], dbg.gaze_world[i - 1]);
    if (rad2deg(vt) * 1000 > 2.0) ratio.push_back(ve / vt);
    max_err = std::max(max_err, rad2deg(angle_between(dbg.gaze_world[i], dbg.target_world[i])));
  }
  ASSERT_GT(ratio.size(), 5000u);
  std::sort(ratio.begin(), ratio.end());
  EXPECT_NEAR(ratio[ratio.size() / 2], 0.9, 0.02);
  EXPECT_GT(ratio.front(), 0.8);
  EXPECT_LT(ratio.back(), 1.0);
  EXPECT_GE(saccades, 5);  // catch-up saccades happen
  EXPECT_LT(max_err, m.pursuit_catchup_deg + 2.0);
  // Head still: eye-in-head equals the world gaze.
  EXPECT_NEAR(glm::length(tr.samples[5000].gaze_dir - dbg.gaze_world[5000]), 0, 1e-9);
}

// VOR: during fixations the gaze in world stays put while the head turns.
TEST(Synth, VorKeepsGazeInWorldSteady) {
  SynthDebug dbg;
  Trace tr = synth_internal(EyeModel(), opts("head-sweep", 12), vive(), &dbg);
  double worst = 0, max_head_turn = 0;
  size_t start = 0;
  for (size_t i = 1; i <= dbg.phase.size(); ++i) {
    bool end = i == dbg.phase.size() || dbg.phase[i] != SynthDebug::Fixation;
    if (dbg.phase[i - 1] == SynthDebug::Fixation && end) {
      glm::dvec3 w0 = tr.samples[start].head_rot * tr.samples[start].gaze_dir;
      for (size_t k = start; k < i; ++k) {
        glm::dvec3 w = tr.samples[k].head_rot * tr.samples[k].gaze_dir;
        worst = std::max(worst, rad2deg(angle_between(w0, w)));
      }
      glm::dquat d = glm::conjugate(tr.samples[start].head_rot) * tr.samples[i - 1].head_rot;
      max_head_turn =
          std::max(max_head_turn, rad2deg(2 * std::acos(std::min(1.0, std::fabs(d.w)))));
    }
    if (i < dbg.phase.size() && dbg.phase[i] == SynthDebug::Fixation &&
        dbg.phase[i - 1] != SynthDebug::Fixation)
      start = i;
  }
  EXPECT_GT(max_head_turn, 10.0);  // the head really turned during some fixation
  EXPECT_LT(worst, 0.01);
  // Eye-in-head counter-rotates: it moves during fixations.
  TraceStats st = trace_stats(tr);
  EXPECT_GT(st.head_speed_p99, 100.0);
}

TEST(Synth, AllScenariosStayInsideTheFov) {
  Display d = vive();
  for (const auto& sc : synth_scenarios()) {
    SynthOptions o = opts(sc, 8, 3);
    o.rate_hz = 90;
    Trace tr = synthesize(EyeModel(), o, d);
    ASSERT_EQ(tr.samples.size(), 8u * 90u + 1u) << sc;
    TraceStats st = trace_stats(tr);
    EXPECT_NEAR(st.rate_hz, 90.0, 1e-6) << sc;
    EXPECT_LT(st.invalid_fraction, 0.2) << sc;
    for (auto& s : tr.samples) {
      ASSERT_TRUE(gaze_inside_fov(d, s.gaze_dir)) << sc << " t=" << s.t;
      ASSERT_NEAR(glm::length(s.gaze_dir), 1.0, 1e-9);
    }
    if (sc == "walk-through") {
      EXPECT_NEAR(st.head_path_m, 1.3 * 8, 0.5);
    }
  }
  // A narrow display bounds the gaze too.
  Display desk = Display::load("desktop_1920x1080", src("models"));
  Trace tr = synthesize(EyeModel(), opts("free-viewing", 8), desk);
  for (auto& s : tr.samples) ASSERT_TRUE(gaze_inside_fov(desk, s.gaze_dir));
}

TEST(Synth, BlinksAreInvalidAndBounded) {
  EyeModel m = model(Json{{"blink", {{"rate_per_min", 40}}}, {"tracker", {{"noise_deg", 0}}}});
  SynthOptions o = opts("free-viewing", 30);
  o.rate_hz = 1000;
  Trace tr = synthesize(m, o, vive());
  int blinks = 0;
  double longest = 0, cur = 0;
  for (size_t i = 1; i < tr.samples.size(); ++i) {
    if (!tr.samples[i].valid) {
      if (tr.samples[i - 1].valid) {
        ++blinks;
        cur = 0;
      }
      cur += 1e-3;
      longest = std::max(longest, cur);
      EXPECT_EQ(tr.samples[i].gaze_dir, tr.samples[i - 1].gaze_dir);  // tracker holds the gaze
    }
  }
  EXPECT_GT(blinks, 8);
  EXPECT_LT(blinks, 35);
  EXPECT_LE(longest, 0.301);
}

TEST(Synth, LatencyShiftsGazeBySamples) {
  EyeModel a = model(Json{{"tracker", {{"noise_deg", 0}}}});
  EyeModel b = model(Json{{"tracker", {{"noise_deg", 0}, {"latency_samples", 3}}}});
  Trace ta = synthesize(a, opts("pursuit", 3), vive()),
        tb = synthesize(b, opts("pursuit", 3), vive());
  ASSERT_EQ(ta.samples.size(), tb.samples.size());
  for (size_t i = 3; i < ta.samples.size(); ++i) {
    if (ta.samples[i - 3].valid) {
      EXPECT_EQ(tb.samples[i].gaze_dir, ta.samples[i - 3].gaze_dir);
    }
  }
  EXPECT_EQ(tb.samples[5].head_rot, ta.samples[5].head_rot);  // head pose is not delayed
}

TEST(Synth, DeterministicForAFixedSeed) {
  Display d = vive();
  std::string dir = tmpdir();
  write_trace_csv(dir + "/a.csv", synthesize(EyeModel(), opts("walk-through", 5, 42), d));
  write_trace_csv(dir + "/b.csv", synthesize(EyeModel(), opts("walk-through", 5, 42), d));
  write_trace_csv(dir + "/c.csv", synthesize(EyeModel(), opts("walk-through", 5, 43), d));
  EXPECT_EQ(read_file(dir + "/a.csv"), read_file(dir + "/b.csv"));
  EXPECT_NE(read_file(dir + "/a.csv"), read_file(dir + "/c.csv"));
}
