// estimate_frame (docs/architecture.md "Cost model"): sum over the passes that exist of overhead +
// sum coef * term.
#include "sim/cost/cost_model.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "sim/core/error.h"
#include "sim/core/message_text.h"
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

Counters shared_counters(const CostInputs& in) {
  Counters out;
  const CostPasses decl = in.passes ? *in.passes : declared_passes(in.method);
  const bool own = in.counters && in.counters->has(Counter::rsm_texels);
  if (decl.frame_rsm && in.shared && !own && in.shared->has(Counter::rsm_texels))
    out.set(Counter::rsm_texels, in.shared->get(Counter::rsm_texels));
  return out;
}

// The profile as errors name it: its file, else its name.
static std::string profile_where(const GpuProfile& g) {
  return g.file.empty() ? "GPU profile '" + g.name + "'" : g.file;
}

FrameCost estimate_frame(const GpuProfile& gpu, const CostInputs& in) {
  const Workload defaults;
  const Workload& w = in.workload ? *in.workload : defaults;
  FrameCost fc;
  // A time that is not finite is an error naming the pass (assemble_passes checks the terms;
  // this checks coefficient x term and the sums), never an "infinitely slow" frame that sorts
  // last or an infinity charged as 0.
  auto finite = [&](double v, const std::string& pass, const char* what) {
    if (!std::isfinite(v))
      throw Error(profile_where(gpu), "method '" + in.method + "', pass '" + pass + "': " + what +
                                          " is " + shortest_number(v) +
                                          " (not finite: the workload's or the counters' values "
                                          "are too large for the cost model)");
    return v;
  };
  for (const PassWork& pw : assemble_passes(in, w, &fc.missing_counters)) {
    double ms = 0;
    auto it = gpu.passes.find(pw.pass);
    // A pass the method declares must be in the profile: without it the pass would cost
    // nothing, and a profile with "passes": {} would fit every budget.
    if (it == gpu.passes.end()) {
      std::string have;
      for (auto& [p, pc] : gpu.passes) have += (have.empty() ? "" : ", ") + p;
      throw Error(profile_where(gpu),
                  "GPU profile '" + gpu.name + "' has no coefficients for pass '" + pw.pass +
                      "', which method '" + in.method + "' declares (its passes: " +
                      (have.empty() ? "none" : have) + "; add passes." + pw.pass + ")");
    }
    ms = it->second.overhead_ms;
    fc.resource_ms["fixed"] += it->second.overhead_ms;
    std::vector<double> term_ms;  // work / throughput of each term (ms); 0 without a coefficient
    std::vector<bool> costed;     // the profile has the term's coefficient
    for (const Term& t : pw.terms) {
      auto c = it->second.terms.find(t.name);
      costed.push_back(c != it->second.terms.end());
      if (!costed.back()) {
        term_ms.push_back(0);
        continue;
      }
      const double ws = gpu.model == CostModelKind::Roofline
                            ? working_set_factor(pw.pass, t.name, gpu.spec, in.display)
                            : 1.0;
      double ms_t = c->second * t.value * ws;
      // A primitive or a fragment never goes faster than the spec sheet's peak rate, however
      // much of the working set the L2 holds (TWFR's sprites on a GPU whose L2 holds the eye's
      // buffers). No calibration row reaches this floor (the fit does not model it).
      if (ws < 1 && (t.res == Resource::Geometry || t.res == Resource::Raster))
        ms_t = std::max(ms_t, t.value / gpu.spec.rate_per_ms(t.res));
      term_ms.push_back(finite(ms_t, pw.pass, "a term's time"));
    }
    if (gpu.model == CostModelKind::Roofline) {
      // Bottleneck: each dispatch of the pass takes as long as its slowest resource
      // (docs/architecture.md "Cost model"); the time is charged to that resource in
      // resource_ms.
      std::vector<std::pair<Resource, double>> bound;
      ms += roofline_ms(pw.terms, term_ms, &bound);
      for (auto& [r, v] : bound)
        if (v > 0) fc.resource_ms[resource_name(r)] += v;
    } else {
      std::map<Resource, double> per_res;  // summed per resource first, then over resources
      for (size_t i = 0; i < pw.terms.size(); ++i)
        if (costed[i]) per_res[pw.terms[i].res] += term_ms[i];
      for (auto& [r, v] : per_res) {
        ms += v;
        fc.resource_ms[resource_name(r)] += v;
      }
    }
    finite(ms, pw.pass, "the pass time");
    PassCost pc{pw.pass, ms, ms, ms};
    if (gpu.interval.level > 0) {  // this pass's held-out error quantiles (docs/cost_model.md)
      const IntervalFactors f = gpu.interval.for_pass(pw.pass);
      pc.lo_ms = ms * f.lo_factor;
      pc.hi_ms = finite(ms * f.hi_factor, pw.pass, "the interval's upper end");
    }
    fc.passes.push_back(pc);
    fc.total_ms = finite(fc.total_ms + ms, pw.pass, "the frame total up to this pass");
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
    finite(fc.total_hi_ms, "total", "the total's interval upper end");
  }
  return fc;
}

}  // namespace fovsim
