// estimate_frame (docs/architecture.md §6): sum over the passes that exist of overhead + sum coef *
// term.
#include "sim/cost/cost_model.h"

#include <cmath>
#include <map>

#include "sim/cost/gpu_profile.h"
#include "sim/cost/passes.h"
#include "sim/cost/workload.h"
#include "sim/foveation/factory.h"

namespace fovsim {

double FrameCost::pass_ms(const std::string& pass) const {
  for (auto& p : passes)
    if (p.pass == pass) return p.ms;
  return 0;
}

const char* budget_verdict(const FrameCost& fc, double budget_ms) {
  if (fc.interval_level <= 0) return fc.total_ms <= budget_ms ? "fits" : "does not fit";
  if (fc.total_hi_ms <= budget_ms) return "fits";
  return fc.total_lo_ms > budget_ms ? "does not fit" : "uncertain";
}

Counters shared_counters(const CostInputs& in) {
  Counters out;
  const CostPasses decl = in.passes ? *in.passes : declared_passes(in.method);
  const bool own = in.counters && in.counters->has(Counter::rsm_texels);
  if (decl.frame_rsm && in.shared && !own && in.shared->has(Counter::rsm_texels))
    out.set(Counter::rsm_texels, in.shared->get(Counter::rsm_texels));
  return out;
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
      std::map<Resource, double> per_res;  // work / throughput per resource (ms)
      for (const Term& t : pw.terms) {
        auto c = it->second.terms.find(t.name);
        if (c == it->second.terms.end()) continue;
        const double ws = gpu.model == CostModelKind::Roofline
                              ? working_set_factor(pw.pass, t.name, gpu.spec, in.display)
                              : 1.0;
        per_res[t.res] += c->second * t.value * ws;
      }
      if (gpu.model == CostModelKind::Roofline) {
        // Bottleneck: the pass takes as long as its slowest resource (docs/architecture.md §6); the
        // time is charged to that resource in resource_ms.
        Resource bound = Resource::Fixed;
        double worst = 0;
        for (auto& [r, v] : per_res)
          if (v > worst) worst = v, bound = r;
        ms += worst;
        if (worst > 0) fc.resource_ms[resource_name(bound)] += worst;
      } else {
        for (auto& [r, v] : per_res) {
          ms += v;
          fc.resource_ms[resource_name(r)] += v;
        }
      }
    }
    if (!std::isfinite(ms)) ms = HUGE_VAL;  // overflow on absurd inputs stays ordered
    PassCost pc{pw.pass, ms, ms, ms};
    if (gpu.interval.level > 0) {  // this pass's held-out error quantiles (docs/cost_model.md)
      const IntervalFactors f = gpu.interval.for_pass(pw.pass);
      pc.lo_ms = ms * f.lo_factor;
      pc.hi_ms = ms * f.hi_factor;
    }
    fc.passes.push_back(pc);
    fc.total_ms += ms;
  }
  fc.total_lo_ms = fc.total_hi_ms = fc.total_ms;
  if (gpu.interval.level > 0) {
    fc.interval_level = gpu.interval.level;
    std::vector<PassSpan> parts;
    for (auto& pc : fc.passes) parts.push_back({pc.ms, pc.lo_ms, pc.hi_ms});
    const IntervalFactors tf = gpu.interval.for_total();
    if (tf.n > 0) {  // split-conformal on held-out frame totals (docs/cost_model.md)
      fc.total_lo_ms = fc.total_ms * tf.lo_factor;
      fc.total_hi_ms = fc.total_ms * tf.hi_factor;
    } else {
      combine_pass_intervals(parts, &fc.total_lo_ms, &fc.total_hi_ms);
    }
    if (!std::isfinite(fc.total_ms)) fc.total_lo_ms = fc.total_hi_ms = HUGE_VAL;
  }
  return fc;
}

}  // namespace fovsim
