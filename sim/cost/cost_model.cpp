// estimate_frame (DESIGN §6): sum over the passes that exist of overhead + sum coef * term.
#include "sim/cost/cost_model.h"

#include <cmath>

#include "sim/cost/gpu_profile.h"
#include "sim/cost/passes.h"
#include "sim/cost/workload.h"

namespace fovsim {

double FrameCost::pass_ms(const std::string& pass) const {
  for (auto& p : passes)
    if (p.pass == pass) return p.ms;
  return 0;
}

FrameCost estimate_frame(const GpuProfile& gpu, const CostInputs& in) {
  const Workload defaults;
  const Workload& w = in.workload ? *in.workload : defaults;
  FrameCost fc;
  for (const PassWork& pw : assemble_passes(in, w, &fc.missing_counters)) {
    double ms = 0;
    auto it = gpu.passes.find(pw.pass);
    if (it != gpu.passes.end()) {
      ms = it->second.overhead_ms;
      fc.resource_ms["fixed"] += it->second.overhead_ms;
      for (const Term& t : pw.terms) {
        auto c = it->second.terms.find(t.name);
        if (c == it->second.terms.end()) continue;
        ms += c->second * t.value;
        fc.resource_ms[resource_name(t.res)] += c->second * t.value;
      }
    }
    if (!std::isfinite(ms)) ms = HUGE_VAL;  // overflow on absurd inputs stays ordered
    fc.passes.push_back({pw.pass, ms});
    fc.total_ms += ms;
  }
  return fc;
}

}  // namespace fovsim
