// Cost model invariants (issue 7): passes that do not exist cost nothing, every pass is
// non-decreasing in each counter, predictions stay finite, errors name their location.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/core/error.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/passes.h"
#include "sim/cost/workload.h"

using namespace fovsim;

namespace {
const std::string kModels = std::string(FOVSIM_SOURCE_DIR) + "/models";

CostInputs base_inputs(const std::string& method, const Counters* c) {
  CostInputs in;
  in.method = method;
  in.counters = c;
  in.features.triangles = 100000;
  in.features.lights = 2;
  in.features.shadowed_lights = 1;
  in.display.width = 1440;
  in.display.height = 1600;
  in.display.eyes = 2;
  return in;
}
}  // namespace

TEST(CostModel, LoadsProfileAndEstimatesFull) {
  GpuProfile g = GpuProfile::load("gtx1080", kModels);
  EXPECT_EQ(g.name, "gtx1080");
  Counters c;
  CostInputs in = base_inputs("full", &c);
  FrameCost fc = estimate_frame(g, in);
  EXPECT_GT(fc.total_ms, 0);
  double sum = 0;
  for (auto& p : fc.passes) {
    EXPECT_GE(p.ms, 0) << p.pass;
    sum += p.ms;
  }
  EXPECT_NEAR(sum, fc.total_ms, 1e-9);
  EXPECT_GT(fc.pass_ms("lighting"), 0);
  EXPECT_EQ(fc.pass_ms("pass2"), 0);  // pass 2 only for mapping methods
}
