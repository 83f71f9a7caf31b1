// Budget what-if (DESIGN §1 "Does it still fit 90 Hz if the GPU had 2x shading throughput?"):
// a GPU profile with scaled resource throughputs, and the throughput factor each resource
// would need for a frame to fit a budget. Used by `fovsim budget` (docs/cost_model.md).
#pragma once
#include <map>
#include <string>
#include <vector>

#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"

namespace fovsim {

// Throughput multipliers per resource class (1 = the profile as calibrated); `fixed` divides
// the per-pass overheads.
struct WhatIf {
  double shading = 1, geometry = 1, raster = 1, memory = 1, fixed = 1;
};
GpuProfile apply_what_if(const GpuProfile& g, const WhatIf& w);

// The resource classes of FrameCost::resource_ms in report order.
const std::vector<std::string>& budget_resources();

struct BudgetFactors {
  // Per resource: the factor its throughput alone needs for the frame to fit, part / (budget -
  // rest): < 1 slack, +inf when it cannot fit by that resource alone (0 when the resource
  // carries no time and the frame fits).
  std::map<std::string, double> x;
  double x_all = 0;  // one factor on every resource but the fixed overheads
};
BudgetFactors budget_factors(const FrameCost& fc, double budget_ms);

}  // namespace fovsim
