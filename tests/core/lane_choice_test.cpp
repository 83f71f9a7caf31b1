// LaneChoice (sim/core/lane_choice.h): the one rule by which the run-time-dispatched kernels pick
// their width.
#include "sim/core/lane_choice.h"

#include <gtest/gtest.h>

using namespace fovsim;

TEST(LaneChoice, ForcedWidthsAndTheAutomaticOne) {
  LaneChoice c{2, 4, 8};
  EXPECT_TRUE(cpu_has(LaneIsa::sse2));
  EXPECT_TRUE(c.runs(2));
  EXPECT_FALSE(c.runs(3));
  EXPECT_EQ(c.runs(4), cpu_has(LaneIsa::avx2));
  EXPECT_EQ(c.runs(8), cpu_has(LaneIsa::avx512f));
  // Automatic: the entry of the instruction set FOVSIM_SIMD and the CPU allow.
  const int automatic = auto_lane_isa() == LaneIsa::avx512f ? 8
                        : auto_lane_isa() == LaneIsa::avx2  ? 4
                                                            : 2;
  EXPECT_EQ(c.width(), automatic);
  EXPECT_TRUE(cpu_has(auto_lane_isa()));
  c.force(2);
  EXPECT_EQ(c.width(), 2);
  c.force(3);  // no instruction set uses 3: the SSE2 width
  EXPECT_EQ(c.width(), 2);
  c.force(8);
  EXPECT_EQ(c.width(), cpu_has(LaneIsa::avx512f) ? 8 : 2);
  c.force(0);
  EXPECT_EQ(c.width(), automatic);
  // A kernel that repeats a width on a wider instruction set (the tone map: 4, 8, 8).
  LaneChoice t{4, 8, 8};
  EXPECT_EQ(t.runs(8), cpu_has(LaneIsa::avx2));
  EXPECT_EQ(t.width(), auto_lane_isa() == LaneIsa::sse2 ? 4 : 8);
}
