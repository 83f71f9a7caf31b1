// Analytic counters: the driver that hands each method its analytic frame (analytic.h); the
// counters themselves are the method's (FoveationMethod::analytic_counters, method_cost.h).
#include "sim/cost/analytic.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "sim/core/error.h"
#include "sim/cost/passes.h"
#include "sim/foveation/density.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/lighting.h"
#include "sim/foveation/mapping_spec.h"

namespace fovsim {

namespace {
// The method's columns, with an iso-budget target's free parameter as solved (`resolved`), and
// its lighting strategy's (flc: vpl_budget).
std::vector<std::pair<std::string, double>> method_columns(
    const FoveationMethod& inst, const std::optional<MappingSpec>& resolved) {
  std::vector<std::pair<std::string, double>> cols = inst.param_columns();
  if (resolved && inst.mapping_spec()->target_shaded_fraction() > 0)
    for (auto& [k, v] : resolved->columns())
      for (auto& c : cols)
        if (c.first == k) c.second = v;
  if (inst.lighting())
    for (auto& c : inst.lighting()->param_columns()) cols.push_back(c);
  return cols;
}

}  // namespace

// The iso-budget as a run resolves it (analytic.h).
MappingSpec resolved_mapping_spec(const MappingSpec& s, const Display& d) {
  if (!(s.target_shaded_fraction() > 0) || d.width <= 0 || d.height <= 0) return s;
  const Camera cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
  MappingView v = MappingView::at(cam, glm::dvec2(d.width * 0.5, d.height * 0.5));
  const std::vector<float> ecc = eccentricity_map(cam, v.gaze_dir);
  v.ecc = &ecc;
  MappingSpec r;
  solve_iso_budget(s, v, s.target_shaded_fraction(), r);
  return r;
}

AnalyticWorkload analytic_workload(const Workload& w) {
  AnalyticWorkload a;
  a.shaded_fraction = w.shaded_fraction;
  a.triangles = w.triangles;
  a.submitted_fraction = w.submitted_fraction;
  a.lights = w.lights;
  a.rsm_res = w.rsm_res;
  a.vpl_budget = w.vpl_budget;
  a.importance_samples = w.importance_samples;
  a.lpt_fraction = w.lpt_fraction;
  a.interleave = w.interleave;
  a.redraw_fraction = w.twfr_redraw_fraction;
  a.prims_fraction = w.twfr_prims_fraction;
  return a;
}

Counters analytic_counters(const std::string& method, const Json& params, const Workload& w,
                           const Display& d, const std::string& where, bool indirect,
                           CostPasses* passes) {
  const MethodEntry* entry = find_method(method);
  if (!entry) throw Error(where, "unknown method '" + method + "'");
  const Json all = params.is_null() ? Json::object() : params;
  if (!all.is_object()) throw Error(where, "method parameters must be an object");
  // Split: the analytic-only keys the method declares (MethodCost::analytic_keys) here; the
  // rest goes through the method's own parser (the one `run` uses: same keys, defaults and
  // ranges; unknown or mistyped keys are errors). An analytic key the method does not read
  // (kfr:shaded_fraction) stays unread and is reported by p.finish() below.
  Json own = Json::object(), extra = Json::object();
  const std::vector<std::string>& ak = entry->cost().analytic_keys;
  for (auto it = all.begin(); it != all.end(); ++it)
    (std::find(ak.begin(), ak.end(), it.key()) != ak.end() ? extra : own)[it.key()] = it.value();
  Params mp(own, where, "");
  const std::unique_ptr<FoveationMethod> inst = make_method(method, mp);
  const CostPasses decl = declared_passes(*inst);  // pipeline, strategy passes, shared work
  if (passes) *passes = decl;
  // An iso-budget target is solved before the columns are read (sigma, radius_scale, ...).
  const std::optional<MappingSpec> resolved =
      inst->mapping_spec()
          ? std::optional<MappingSpec>(resolved_mapping_spec(*inst->mapping_spec(), d))
          : std::nullopt;
  const std::vector<std::pair<std::string, double>> cols = method_columns(*inst, resolved);
  Params p(extra, where, "");
  const AnalyticWorkload aw = analytic_workload(w);
  AnalyticFrame f;
  f.display = &d;
  f.pixels = double(std::max(0, d.width)) * double(std::max(0, d.height));
  f.workload = &aw;
  f.keys = &p;
  f.given = &own;
  f.columns = &cols;
  f.geometry = resolved ? &*resolved : nullptr;
  Counters c;
  inst->analytic_counters(f, c);  // the method's own (method_cost.h)
  // Its TAA post pass (taa.h) runs over every pixel, as a run counts it (passes.cpp "taa").
  if (inst->taa().enabled) c.set(Counter::taa_pixels, f.pixels);
  if (indirect && decl.frame_rsm && !decl.own_vpls) {
    // One lighting model per scene: the method's samples also get the indirect light of its
    // strategy (lighting.h). all_vpls (the default) shades every VPL; flc / fir keep at most
    // their budget and pay for importance sampling and per-VPL culling. A method that builds
    // its own VPLs (own_vpls) counted them itself.
    const double total = w.rsm_res * w.rsm_res * std::max(1.0, w.lights);  // FLC paper §3
    const LightingStrategy* L = inst->lighting();
    double kept = total;
    c.set(Counter::rsm_texels, total);
    c.set(Counter::vpls_total, total);
    if (L && (decl.importance || decl.culling)) {
      kept = std::min(total, f.column("vpl_budget", w.vpl_budget));
      // The strategy's own selection passes (flc: importance + eq. 14 contributions; fir: one
      // importance per VPL), declared by the strategy.
      L->analytic_selection_counters(c, total, w.importance_samples);
    }
    c.set(Counter::vpls_kept, kept);
    c.set(Counter::shaded_sample_vpls, c.get(Counter::shaded_samples) * kept);
  }
  p.finish();
  return c;
}

FrameCost analytic_frame(const GpuProfile& gpu, const std::string& method, const Json& params,
                         const Workload& w, const Display& d, const std::string& where,
                         bool indirect) {
  CostInputs in;
  const Counters c = analytic_counters(method, params, w, d, where, indirect, &in.passes.emplace());
  in.features.indirect = indirect;
  in.method = method;
  in.counters = &c;
  in.display = d;
  in.workload = &w;
  return estimate_frame(gpu, in);
}

}  // namespace fovsim
