#include <cmath>

#include "sim/trace/trace.h"
#include "test_util.h"

using namespace fovsim;
using namespace fovsim::test;

static Trace ramp(double hz, int n) {
  Trace tr;
  for (int i = 0; i < n; ++i) {
    TraceSample s;
    s.t = 1.0 + i / hz;
    s.head_pos = {i * 0.01, 1.6, 0};
    s.head_rot = glm::angleAxis(deg2rad(3.0 * i), glm::dvec3(0, 1, 0));
    s.gaze_dir = glm::normalize(glm::dvec3(0.01 * i, 0, -1));
    s.valid = (i % 7) != 3;
    tr.samples.push_back(s);
  }
  return tr;
}

TEST(Resample, IdentityAtSameRate) {
  Trace in = ramp(90, 50);
  Trace out = resample(in, 90);
  ASSERT_EQ(out.samples.size(), in.samples.size());
  for (size_t i = 0; i < in.samples.size(); ++i) {
    EXPECT_EQ(out.samples[i].t, in.samples[i].t);
    EXPECT_EQ(out.samples[i].head_rot, in.samples[i].head_rot);
    EXPECT_EQ(out.samples[i].gaze_dir, in.samples[i].gaze_dir);
    EXPECT_EQ(out.samples[i].valid, in.samples[i].valid);
  }
}

TEST(Resample, GridUnitQuaternionsAndSlerp) {
  Trace in = ramp(120, 121);  // 1 s at 120 Hz, yaw 3 deg per sample
  Trace out = resample(in, 90);
  ASSERT_EQ(out.samples.size(), 91u);  // frames past the end are not produced
  for (size_t k = 0; k < out.samples.size(); ++k) {
    const auto& s = out.samples[k];
    EXPECT_NEAR(s.t, 1.0 + k / 90.0, 1e-12);
    double qn = std::sqrt(s.head_rot.w * s.head_rot.w + s.head_rot.x * s.head_rot.x +
                          s.head_rot.y * s.head_rot.y + s.head_rot.z * s.head_rot.z);
    EXPECT_NEAR(qn, 1.0, 1e-12);
    EXPECT_NEAR(glm::length(s.gaze_dir), 1.0, 1e-12);
    // Slerp of a constant-rate yaw gives the exact yaw at t: 3 deg * 120 Hz * (t - 1).
    double yaw = rad2deg(2 * std::atan2(s.head_rot.y, s.head_rot.w));
    EXPECT_NEAR(yaw, 360.0 * (s.t - 1.0), 1e-7);
    EXPECT_NEAR(s.head_pos.x, 0.01 * 120 * (s.t - 1.0), 1e-9);
  }
}

TEST(Resample, ShortestArcAcrossSignFlip) {
  Trace in;
  TraceSample a, b;
  a.t = 0;
  b.t = 1;
  a.head_rot = glm::angleAxis(deg2rad(170.0), glm::dvec3(0, 1, 0));
  b.head_rot = -glm::angleAxis(deg2rad(-170.0), glm::dvec3(0, 1, 0));  // same as +190, sign flipped
  in.samples = {a, b};
  Trace out = resample(in, 2);
  ASSERT_EQ(out.samples.size(), 3u);
  glm::dvec3 f = out.samples[1].head_rot * glm::dvec3(0, 0, -1);
  EXPECT_NEAR(f.z, 1.0, 1e-9);  // midway = 180 deg, not 0 deg
  EXPECT_THROW(resample(in, 0), Error);
}
