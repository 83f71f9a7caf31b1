// The per-phase timers of manifest.json "phases" (sim/experiment/phase_times.h): the serial-work
// estimate and the JSON summary, on given figures (no timing is asserted).
#include "sim/experiment/phase_times.h"

#include <gtest/gtest.h>

using namespace fovsim;

TEST(PhaseTimes, SerialEstimateFromMainAndProcessCpu) {
  // All work on the frame-loop thread: serial. Evenly split over 2 threads: 0 serial.
  EXPECT_DOUBLE_EQ(PhaseTimes::serial_cpu_ms(2, 100, 100), 100);
  EXPECT_DOUBLE_EQ(PhaseTimes::serial_cpu_ms(2, 50, 100), 0);
  // S = 20 serial + P = 80 parallel over 2 threads: main = 20 + 40 = 60, cpu = 100.
  EXPECT_DOUBLE_EQ(PhaseTimes::serial_cpu_ms(2, 60, 100), 20);
  // 4 threads: S = 10, P = 40: main = 10 + 10 = 20, cpu = 50.
  EXPECT_DOUBLE_EQ(PhaseTimes::serial_cpu_ms(4, 20, 50), 10);
  // Clamped: the frame-loop thread did less than its share; one thread has no estimate.
  EXPECT_DOUBLE_EQ(PhaseTimes::serial_cpu_ms(2, 10, 100), 0);
  EXPECT_DOUBLE_EQ(PhaseTimes::serial_cpu_ms(1, 100, 100), 0);
}

TEST(PhaseTimes, JsonSumsPhasesAndFraction) {
  PhaseTimes t;
  t.add("methods", {300, 100, 60});  // wall, cpu, main: serial 20
  t.add("metrics", {200, 50, 50});   // serial 50
  PhaseTimes u;
  u.add("metrics", {0, 50, 25});  // merged: cpu 100, main 75 -> serial 50
  t.merge(u);
  const Json j = t.to_json(2);
  EXPECT_EQ(j["threads"], 2);
  EXPECT_DOUBLE_EQ(j["cpu_ms"].get<double>(), 200);
  EXPECT_DOUBLE_EQ(j["wall_ms"].get<double>(), 500);
  EXPECT_DOUBLE_EQ(j["phases"]["metrics"]["serial_cpu_ms"].get<double>(), 50);
  EXPECT_DOUBLE_EQ(j["serial_cpu_ms"].get<double>(), 70);
  EXPECT_DOUBLE_EQ(j["serial_fraction"].get<double>(), 0.35);
  EXPECT_FALSE(t.to_json(1).contains("serial_fraction"));
}
