// Budget what-if maths (see budget.h).
#include "sim/cost/budget.h"

#include <cmath>

namespace fovsim {

GpuProfile apply_what_if(const GpuProfile& g, const WhatIf& w) {
  return g.scaled(Resource::Shading, w.shading)
      .scaled(Resource::Geometry, w.geometry)
      .scaled(Resource::Raster, w.raster)
      .scaled(Resource::Memory, w.memory)
      .scaled(Resource::Fixed, w.fixed);
}

const std::vector<std::string>& budget_resources() {
  static const std::vector<std::string> r = {"shading", "geometry", "raster", "memory", "fixed"};
  return r;
}

BudgetFactors budget_factors(const FrameCost& fc, double budget) {
  BudgetFactors out;
  const double T = fc.total_ms;
  for (const std::string& rn : budget_resources()) {
    auto it = fc.resource_ms.find(rn);
    const double part = it == fc.resource_ms.end() ? 0.0 : it->second;
    const double room = budget - (T - part);
    out.x[rn] = part <= 0 ? (T <= budget ? 0.0 : INFINITY) : (room > 0 ? part / room : INFINITY);
  }
  auto it = fc.resource_ms.find("fixed");
  const double fixed = it == fc.resource_ms.end() ? 0.0 : it->second;
  out.x_all = (budget - fixed) > 0 ? (T - fixed) / (budget - fixed) : INFINITY;
  return out;
}

}  // namespace fovsim
