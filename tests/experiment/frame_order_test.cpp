// The run engine's stages that need no scene: FrameOrder (trace order, frames.warmup, --target's
// units) and GazeSource (true gaze, latency estimate with the cost feedback, tracking loss).
#include "sim/experiment/frame_order.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "sim/experiment/gaze_source.h"
#include "sim/experiment/intervals.h"

using namespace fovsim;

namespace {

struct Log {
  std::vector<std::pair<int, bool>> frames;  // (k, record)
  int discontinuities = 0;
};

FrameOrder::Steps logging(Log& log, int stop_after_units = -1) {
  FrameOrder::Steps s;
  s.frame = [&log](int k, bool record) { log.frames.push_back({k, record}); };
  s.discontinuity = [&log] { ++log.discontinuities; };
  s.unit_done = [stop_after_units](int units_done) { return units_done == stop_after_units; };
  return s;
}

TEST(FrameOrder, TraceOrderWithWarmupFramesFirst) {
  FrameOrder order(5, 2, false, true, 1);  // shuffled is ignored without --target
  Log log;
  order.run(logging(log));
  const std::vector<std::pair<int, bool>> want = {{-2, false}, {-1, false}, {0, true}, {1, true},
                                                  {2, true},   {3, true},   {4, true}};
  EXPECT_EQ(log.frames, want);
  EXPECT_EQ(log.discontinuities, 0);
  EXPECT_FALSE(order.sampled());
  EXPECT_FALSE(order.shuffled());
  EXPECT_EQ(order.unit_frames(), 5);
  EXPECT_EQ(order.recorded(), 5);
  EXPECT_EQ(order.warmup(), 2);
}

TEST(FrameOrder, TargetUnitsEachFrameOnceWithAWarmupFrameBeforeAJump) {
  const int count = 5 * kTargetUnitFrames + 3;  // the last unit is short
  FrameOrder order(count, 0, true, true, 7);
  ASSERT_TRUE(order.shuffled());
  Log log;
  order.run(logging(log));
  std::multiset<int> recorded;
  int next = 0, jumps = 0;
  for (size_t i = 0; i < log.frames.size(); ++i) {
    const auto [k, record] = log.frames[i];
    if (!record) {  // an unrecorded frame directly precedes the unit it warms up
      ASSERT_LT(i + 1, log.frames.size());
      EXPECT_EQ(log.frames[i + 1].first, k + 1);
      continue;
    }
    if (k % kTargetUnitFrames == 0 && k != next) ++jumps;
    recorded.insert(k);
    next = k + 1;
  }
  EXPECT_EQ(int(recorded.size()), count);
  for (int k = 0; k < count; ++k) EXPECT_EQ(recorded.count(k), 1u) << k;
  EXPECT_EQ(log.discontinuities, jumps);
  EXPECT_GT(jumps, 0);
  EXPECT_EQ(order.recorded(), count);
  EXPECT_EQ(order.warmup(), int(log.frames.size()) - count);
  // The same seed gives the same order; units are whole units of kTargetUnitFrames frames.
  FrameOrder again(count, 0, true, true, 7);
  EXPECT_EQ(again.unit_order(), order.unit_order());
  EXPECT_EQ(order.unit_frames(), kTargetUnitFrames);
}

TEST(FrameOrder, TemporalMethodsKeepTraceOrderAndTheTargetStopsTheRun) {
  FrameOrder order(10 * kTargetUnitFrames, 1, true, false, 7);
  EXPECT_TRUE(order.sampled());
  EXPECT_FALSE(order.shuffled());
  Log log;
  order.run(logging(log, 3));
  ASSERT_EQ(int(log.frames.size()), 1 + 3 * kTargetUnitFrames);
  EXPECT_EQ(log.frames[0], std::make_pair(-1, false));
  for (int k = 0; k < 3 * kTargetUnitFrames; ++k)
    EXPECT_EQ(log.frames[size_t(k + 1)], std::make_pair(k, true));
  EXPECT_EQ(log.discontinuities, 0);
  EXPECT_EQ(order.recorded(), 3 * kTargetUnitFrames);
}

// A 90 Hz display of 8 x 8 pixels and a steady trace; frame 2 lost by the tracker.
struct GazeFixture {
  Display display;
  Trace trace;
  TrackingPolicy policy;
  FrameData fd;
  GazeFixture() {
    display.width = display.height = 8;
    display.refresh_hz = 90;
    for (int i = 0; i < 4; ++i) {
      TraceSample s;
      s.t = i / 90.0;
      s.valid = i != 2;
      trace.samples.push_back(s);
    }
    fd.camera = Camera::from_pose(display, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
    fd.gaze_dir = {0, 0, -1};
    fd.gaze_px = {4, 4};
    fd.eccentricity = eccentricity_map(fd.camera, fd.gaze_dir);
  }
};

TEST(GazeSource, TrueGazeWithoutLatencyAndPolicyGazeWhenLost) {
  GazeFixture f;
  LatencyConfig lat;  // disabled
  GazeSource gs(lat, f.trace, f.trace, f.policy, f.display);
  FrameContext ctx;
  gs.begin_frame(1, 2, ctx);
  EXPECT_EQ(gs.gaze_for(0, f.fd, ctx), 0.0);
  EXPECT_EQ(ctx.eccentricity, &f.fd.eccentricity);  // the frame's own map, no copy
  EXPECT_TRUE(ctx.gaze_valid);
  EXPECT_EQ(gs.phase(), nullptr);
  EXPECT_STREQ(gs.tracked().state, "valid");
  gs.begin_frame(2, 2, ctx);  // lost: hold shows the last valid gaze, flagged invalid
  gs.gaze_for(1, f.fd, ctx);
  EXPECT_FALSE(ctx.gaze_valid);
  EXPECT_NE(ctx.eccentricity, &f.fd.eccentricity);
  EXPECT_STREQ(gs.tracked().state, "held");
}

TEST(GazeSource, RenderPartOfTheLatencyIsTheMethodsOwnPreviousEstimate) {
  GazeFixture f;
  LatencyConfig lat;
  lat.enabled = true;
  lat.tracker_ms = 10;
  lat.render_ms = 5;
  lat.render_from_estimate = true;
  GazeSource gs(lat, f.trace, f.trace, f.policy, f.display);
  FrameContext ctx;
  gs.begin_frame(0, 2, ctx);
  EXPECT_DOUBLE_EQ(gs.gaze_for(0, f.fd, ctx), 15.0);  // no estimate yet: render_ms
  EXPECT_NE(gs.phase(), nullptr);
  gs.feedback(0, 12.0);  // over one period (11.1 ms): scanned out two periods later
  gs.feedback(1, 3.0);   // under one: one period
  gs.begin_frame(1, 2, ctx);
  EXPECT_DOUBLE_EQ(gs.gaze_for(0, f.fd, ctx), 10.0 + 2000.0 / 90);
  EXPECT_DOUBLE_EQ(gs.gaze_for(1, f.fd, ctx), 10.0 + 1000.0 / 90);
  gs.reset();  // a jump in the frame order: no feedback from before it
  gs.begin_frame(3, 2, ctx);
  EXPECT_DOUBLE_EQ(gs.gaze_for(0, f.fd, ctx), 15.0);
}

}  // namespace
