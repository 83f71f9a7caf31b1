// Gaze at any time (sim/trace/gaze_at.cpp): agrees with resample(), holds the ends,
// keeps a steady gaze bit-identical, and measures angular speed.
#include <cmath>

#include "sim/trace/trace.h"
#include "test_util.h"

using namespace fovsim;

namespace {

glm::dvec3 yaw_dir(double deg) {
  double a = deg * 3.14159265358979323846 / 180.0;
  return {std::sin(a), 0.0, -std::cos(a)};
}

// 100 Hz, gaze turning at 40 deg/s.
Trace turning() {
  Trace tr;
  for (int i = 0; i <= 50; ++i) {
    TraceSample s;
    s.t = i * 0.01;
    s.gaze_dir = yaw_dir(40.0 * s.t);
    s.valid = i != 20;
    tr.samples.push_back(s);
  }
  return tr;
}

}  // namespace

TEST(GazeAt, AgreesWithResampleAndHoldsTheEnds) {
  Trace tr = turning();
  Trace r = resample(tr, 90);
  for (const auto& s : r.samples) {
    TraceSample q = sample_at(tr, s.t);
    EXPECT_LT(angle_deg(q.gaze_dir, s.gaze_dir), 1e-9) << s.t;
    EXPECT_EQ(q.valid, s.valid) << s.t;
  }
  EXPECT_EQ(sample_at(tr, -1.0).gaze_dir, tr.samples.front().gaze_dir);
  EXPECT_EQ(sample_at(tr, 9.0).gaze_dir, tr.samples.back().gaze_dir);
  EXPECT_EQ(sample_at(tr, 0.2).gaze_dir, tr.samples[20].gaze_dir);  // exactly on a sample
  EXPECT_NEAR(angle_deg(sample_at(tr, 0.255).gaze_dir, yaw_dir(40.0 * 0.255)), 0.0, 1e-3);
}

TEST(GazeAt, SteadyGazeIsBitIdenticalAndSpeedIsMeasured) {
  Trace tr;
  for (int i = 0; i < 10; ++i)
    tr.samples.push_back({i * 0.011, {}, {1, 0, 0, 0}, yaw_dir(7.3), true});
  for (double t : {0.0, 0.0031, 0.05, 0.0987})
    EXPECT_EQ(sample_at(tr, t).gaze_dir, tr.samples[0].gaze_dir) << t;
  EXPECT_EQ(gaze_speed_deg_s(tr, 0.05, 0.005), 0.0);
  Trace turn = turning();
  EXPECT_NEAR(gaze_speed_deg_s(turn, 0.25, 0.5 / 90), 40.0, 1e-3);
  EXPECT_NEAR(angle_deg(yaw_dir(0), yaw_dir(1e-6)), 1e-6, 1e-12);  // stable for tiny angles
}
