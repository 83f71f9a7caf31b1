#include "sim/trace/trace.h"
#include "test_util.h"

using namespace fovsim;
using namespace fovsim::test;

namespace {
// Loads {"trace": block} as if from run.json in `base`, then checks unknown keys like a run does.
Trace load(const Json& block, const std::string& base, const Display& d) {
  Params root(Json{{"trace", block}}, "run.json");
  Params tp = root.child("trace");
  Trace tr = load_trace(tp, d, base);
  root.finish();
  return tr;
}
}  // namespace

TEST(LoadTrace, FileRelativeToConfigWithRange) {
  Display d = vive();
  Trace all = load(Json{{"file", "traces/sample_walk.csv"}}, src(""), d);
  EXPECT_NEAR(all.samples[1].t - all.samples[0].t, 1 / 90.0, 1e-9);
  Trace part =
      load(Json{{"file", "traces/sample_walk.csv"}, {"start", 1.0}, {"duration", 2.0}}, src(""), d);
  ASSERT_EQ(part.samples.size(), 180u);
  EXPECT_NEAR(part.samples.front().t - all.samples.front().t, 1.0, 1e-6);
  // Resampled to an explicit rate.
  Trace r60 = load(Json{{"file", "traces/sample_walk.csv"}, {"rate_hz", 60}, {"duration", 1.0}},
                   src(""), d);
  EXPECT_EQ(r60.samples.size(), 60u);
}

TEST(LoadTrace, ErrorsNameTheJsonPath) {
  Display d = vive();
  expect_error(
      [&] {
        load(Json{{"file", "traces/sample_walk.csv"}, {"strat", 1}}, src(""), d);
      },
      {"run.json: trace.strat", "unknown key"});
  expect_error([&] { load(Json::object(), src(""), d); }, {"run.json: trace", "needs \"file\""});
  expect_error(
      [&] {
        load(Json{{"file", "nope.csv"}}, src(""), d);
      },
      {"run.json: trace.file", "not found"});
  expect_error(
      [&] {
        load(Json{{"file", "traces/sample_walk.csv"}, {"on_bad_sample", "ignore"}}, src(""), d);
      },
      {"trace.on_bad_sample", "allowed: fail, skip, hold"});
  expect_error(
      [&] {
        load(Json{{"file", "traces/sample_walk.csv"}, {"start", 100}}, src(""), d);
      },
      {"trace.start", "past the end"});
}

TEST(LoadTrace, ShortTracePolicy) {
  Display d = vive();
  Json b{{"file", "traces/sample_walk.csv"}, {"duration", 10.0}};
  expect_error([&] { load(b, src(""), d); }, {"run.json: trace.duration", "on_short"});
  b["on_short"] = "truncate";
  Trace t = load(b, src(""), d);
  EXPECT_LT(t.samples.size(), 900u);
  ASSERT_FALSE(t.warnings.empty());
  EXPECT_NE(t.warnings.back().find("truncated"), std::string::npos);
  b["on_short"] = "hold";
  Trace h = load(b, src(""), d);
  EXPECT_EQ(h.samples.size(), 900u);
  EXPECT_EQ(h.samples.back().gaze_dir, t.samples.back().gaze_dir);
}

TEST(LoadTrace, SyntheticBlock) {
  Display d = vive();
  Json b{{"synthetic",
          {{"scenario", "reading"},
           {"seed", 5},
           {"duration", 3},
           {"params", {{"tracker", {{"noise_deg", 0}}}}}}}};
  Trace a = load(b, "", d), c = load(b, "", d);
  EXPECT_EQ(a.source, "synthetic:reading:5");
  EXPECT_EQ(a.samples.size(), 3u * 90u + 1u);
  for (size_t i = 0; i < a.samples.size(); ++i)
    ASSERT_EQ(a.samples[i].gaze_dir, c.samples[i].gaze_dir);
  expect_error(
      [&] {
        load(Json{{"synthetic", {{"scenario", "jogging"}}}}, "", d);
      },
      {"run.json: trace.synthetic.scenario", "free-viewing"});
  expect_error(
      [&] {
        load(Json{{"synthetic",
                   {{"scenario", "pursuit"}, {"params", {{"pursuit", {{"gian", 1}}}}}}}},
             "", d);
      },
      {"run.json: trace.synthetic.params.pursuit.gian", "unknown key"});
  // Params from a file relative to the config directory.
  std::string dir = tmpdir();
  write_file_atomic(dir + "/eye.json", R"({"saccade": {"vmax_deg_s": 650}})");
  Trace f =
      load(Json{{"synthetic", {{"scenario", "fixate"}, {"duration", 1}, {"params", "eye.json"}}}},
           dir, d);
  EXPECT_EQ(f.samples.size(), 91u);
}

TEST(LoadTrace, RawRecordingThroughAMap) {
  std::string dir = tmpdir();
  write_file_atomic(dir + "/map.json",
                    R"({"delimiter": "comma", "header": true, "coordinates": "fovsim",
    "time": {"column": "ms", "unit": "ms"}, "head_position": {"constant": [0, 1.6, 0]},
    "head_orientation": {"constant": [1, 0, 0, 0]},
    "gaze": {"type": "direction", "space": "head", "columns": ["x", "y", "z"]}})");
  write_file_atomic(dir + "/rec.csv",
                    "ms,x,y,z\n1000,0,0,-1\n1010,0.9,0,-0.43589\n1020,0,0,-1\n1030,0,0,-1\n");
  Display d = vive();
  expect_error(
      [&] {
        load(Json{{"file", "rec.csv"}, {"map", "map.json"}, {"resample", false}}, dir, d);
      },
      {"rec.csv:3:6", "outside the display FOV", "on_bad_sample skip or hold"});
  Trace t = load(
      Json{
          {"file", "rec.csv"}, {"map", "map.json"}, {"resample", false}, {"on_bad_sample", "skip"}},
      dir, d);
  EXPECT_EQ(t.samples.size(), 3u);
  ASSERT_EQ(t.warnings.size(), 1u);
}
