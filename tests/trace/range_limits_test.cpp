// Issue 20: a trace is resampled only over the range a run uses, and the resampled size is
// checked against trace.max_samples before it is allocated; non-regular files are refused.
#include "sim/trace/trace.h"
#include "test_util.h"

using namespace fovsim;
using namespace fovsim::test;

namespace {

// Canonical trace whose third sample is at t = 1e7 s (valid, but absurd to resample whole).
std::string longspan_csv() {
  return "t,px,py,pz,qw,qx,qy,qz,gx,gy,gz,valid\n"
         "0,0,0,0,1,0,0,0,0,0,-1,1\n"
         "0.011111,0,0,0,1,0,0,0,0,0,-1,1\n"
         "10000000,0,0,0,1,0,0,0,0,0,-1,1\n";
}

Trace load(const Json& block, const Display& d, double needed_s = INFINITY) {
  Params root(Json{{"trace", block}}, "run.json");
  Params tp = root.child("trace");
  Trace tr = load_trace(tp, d, "", needed_s);
  root.finish();
  return tr;
}

}  // namespace

TEST(TraceRange, ResampleStopsAtTheEndOfTheRangeUsed) {
  Display d = vive();
  Trace all = load(Json{{"file", src("traces/sample_walk.csv")}}, d);
  Trace part = resample(all, 90.0, all.samples.front().t + 0.5);
  ASSERT_EQ(part.samples.size(), 46u);  // frames 0..45 (t <= t0 + 0.5)
  EXPECT_EQ(resampled_count(all, 90.0, all.samples.front().t + 0.5), 46.0);
  EXPECT_EQ(resampled_count(all, 90.0), double(resample(all, 90.0).samples.size()));
  for (size_t i = 0; i < part.samples.size(); ++i) {  // same frames as the full resampling
    EXPECT_EQ(part.samples[i].t, all.samples[i].t);
    EXPECT_EQ(part.samples[i].gaze_dir, all.samples[i].gaze_dir);
  }
}

TEST(TraceRange, LongSpanTraceResamplesOnlyWhatIsUsed) {
  Display d = vive();
  std::string f = write_tmp("longspan.csv", longspan_csv());
  // Whole trace: 9e8 samples at 90 Hz, refused before allocating, naming the limit.
  expect_error(
      [&] {
        load(Json{{"file", f}}, d);
      },
      {"run.json: trace.max_samples", "900000001 samples", "over the limit of 2000000"});
  // Two frames asked for: a few samples resampled, no error.
  Trace two = load(Json{{"file", f}}, d, 2.0 / 90.0);
  EXPECT_LE(two.samples.size(), 5u);
  EXPECT_GE(two.samples.size(), 2u);
  // A duration bounds it too; max_samples can be lowered (and raised).
  EXPECT_EQ(load(Json{{"file", f}, {"duration", 1.0}}, d).samples.size(), 90u);
  expect_error(
      [&] {
        load(Json{{"file", f}, {"duration", 1.0}, {"max_samples", 10}}, d);
      },
      {"trace.max_samples", "over the limit of 10"});
}

TEST(TraceRange, NonRegularTraceFileRefused) {
  Display d = vive();
  expect_error([&] { load(Json{{"file", "/dev/zero"}}, d); }, {"/dev/zero", "not a regular file"});
}
