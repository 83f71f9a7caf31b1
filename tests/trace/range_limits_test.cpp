// A trace is resampled only over the range a run uses, and the resampled size is
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

// `trace validate --max-gap` flags implausible gaps (located, counted, longest);
// a time beyond 2^53 us (where exact integer arithmetic on nanoseconds overflows) is a
// located "time value out of range".
TEST(TraceRange, GapsAreFlaggedWithTheirLocation) {
  std::string f = write_tmp("gaps.csv", longspan_csv() +
                                            "10000001.5,0,0,0,1,0,0,0,0,0,-1,1\n"
                                            "10000001.6,0,0,0,1,0,0,0,0,0,-1,1\n");
  Trace all = read_trace_csv(f, vive());
  EXPECT_TRUE(all.warnings.empty());  // no gap check unless asked
  TraceReadOptions o;
  o.max_gap_s = 1;
  Trace tr = read_trace_csv(f, vive(), o);
  ASSERT_EQ(tr.samples.size(), 5u);
  ASSERT_EQ(tr.warnings.size(), 1u);
  const std::string& w = tr.warnings[0];
  EXPECT_NE(w.find("2 gaps longer than max_gap 1 s (longest 1e+07 s); first: "), std::string::npos)
      << w;
  EXPECT_NE(w.find("gaps.csv:4:1: t=10000000 after t=0.011111 (line 3)"), std::string::npos) << w;
  o.max_gap_s = 2;
  EXPECT_NE(read_trace_csv(f, vive(), o).warnings.at(0).find("1 gap longer than max_gap 2 s"),
            std::string::npos);
}

TEST(TraceRange, TimeBeyondExactIntegerRangeIsLocated) {
  for (const char* t : {"9007199255", "-1e300", "1e19"}) {
    std::string f = write_tmp("far.csv", std::string("t,px,py,pz,qw,qx,qy,qz,gx,gy,gz\n"
                                                     "0,0,0,0,1,0,0,0,0,0,-1\n") +
                                             t + ",0,0,0,1,0,0,0,0,0,-1\n");
    expect_error([&] { read_trace_csv(f, vive()); }, {"far.csv:3:1", "time value out of range"});
  }
  // Just inside the limit it is a valid (if absurd) time; skip drops the row and says so.
  std::string g = write_tmp("far2.csv", std::string("t,px,py,pz,qw,qx,qy,qz,gx,gy,gz\n"
                                                    "0,0,0,0,1,0,0,0,0,0,-1\n"
                                                    "9007199254,0,0,0,1,0,0,0,0,0,-1\n"
                                                    "9e15,0,0,0,1,0,0,0,0,0,-1\n"));
  TraceReadOptions o;
  o.on_bad = BadSamplePolicy::Skip;
  Trace tr = read_trace_csv(g, vive(), o);
  EXPECT_EQ(tr.samples.size(), 2u);
  ASSERT_EQ(tr.warnings.size(), 1u);
  EXPECT_NE(tr.warnings[0].find("time out of range"), std::string::npos) << tr.warnings[0];
}
