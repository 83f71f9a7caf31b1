#include "sim/experiment/cost_queries.h"

#include <cmath>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/text.h"
#include "sim/cost/analytic.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/passes.h"
#include "sim/cost/tracking_cost.h"
#include "sim/experiment/config_cost.h"
#include "sim/experiment/info.h"
#include "sim/foveation/factory.h"
#include "sim/trace/tracking.h"

namespace fovsim {

namespace {

// "kfr:sigma=1.8,alpha=4": the one method syntax (parse_method_arg); keys are validated by the
// method's own parser inside analytic_counters.
CostMethod parse_cost_method(const std::string& s, const std::string& where) {
  MethodArg a = parse_method_arg(s, where);
  if (!is_cost_method(a.name))
    throw Error(where + " " + s, "no cost model for method \"" + a.name + "\"");
  return {a.text, a.name, a.params};
}

FrameCost cost_for(const GpuProfile& g, const CostMethod& m, const ResolvedCostTarget& r,
                   const std::string& where) {
  return analytic_frame(g, m.name, m.params, r.workload, r.display, where + " " + m.text,
                        r.indirect);
}

std::string models_of(const CostTarget& t) {
  return t.models.empty() ? default_models_dir() : t.models;
}

Json finite_or_inf(double f) {
  return std::isfinite(f) ? Json(f) : Json("inf");
}

}  // namespace

ResolvedCostTarget resolve_cost_target(const CostTarget& t,
                                       const std::vector<std::string>& default_methods) {
  // The overrides' ranges (the CLI's flags check them too): 0 keeps the display's value.
  check_cost_args(t.width, t.height, t.eyes, 0, {});
  const std::string models = models_of(t);
  ResolvedCostTarget r;
  r.gpus = t.gpus;
  if (!t.config.empty()) {
    if (!t.workload.empty())
      throw Error(t.where_workload,
                  "give either " + t.where_workload + " or a config (its scene), not both");
    const ConfigCostTarget c = config_cost_target(t.config, models);
    r.workload = c.workload;
    r.display = t.display.empty() ? c.display : Display::load(t.display, models);
    r.indirect = c.features.indirect;
    for (auto& m : c.methods) {
      if (!is_cost_method(m.method))
        throw Error(t.config, "no cost model for method \"" + m.method + "\"");
      r.methods.push_back({m.label, m.method, m.params});
    }
    if (r.gpus.empty()) r.gpus = c.gpus;
  } else {
    // A workload must be named (generic knows no scene): Workload::load_for_costing.
    r.workload = Workload::load_for_costing(t.workload, models, t.where_workload, t.workload_hint);
    r.display = Display::load(t.display.empty() ? std::string(kDefaultDisplay) : t.display, models);
  }
  if (t.width) r.display.width = t.width;
  if (t.height) r.display.height = t.height;
  if (t.eyes) r.display.eyes = t.eyes;
  if (!t.methods.empty() || r.methods.empty()) {
    r.methods.clear();
    for (auto& m : t.methods.empty() ? default_methods : t.methods)
      r.methods.push_back(parse_cost_method(m, t.where_method));
  }
  if (r.gpus.empty())
    throw Error(t.where_gpu,
                "required (a GPU profile name, e.g. " + std::string(kDefaultGpu) + ")");
  return r;
}

CostRows predict_rows(const CostTarget& t, const PredictLoss& loss) {
  CostRows out;
  out.target = resolve_cost_target(t, {"full"});
  const ResolvedCostTarget& res = out.target;
  const bool with_loss = loss.fraction >= 0;
  OnInvalid policy = OnInvalid::Hold;
  if (with_loss) {
    check_number("tracking_loss", loss.fraction, Range::closed(0, 1));
    if (!parse_on_invalid(loss.on_invalid, policy))
      throw Error("on_invalid", "unknown policy \"" + loss.on_invalid + "\" (" +
                                    join_names(on_invalid_choices()) + ")");
  }
  const std::string models = models_of(t);
  const Display& d = res.display;
  for (auto& gname : res.gpus) {
    GpuProfile g = GpuProfile::load(gname, models);
    out.gpus.push_back(g);
    const double full_total =
        cost_for(g, parse_cost_method("full", t.where_method), res, t.where_method).total_ms;
    for (auto& m : res.methods) {
      const FrameCost fc = cost_for(g, m, res, t.where_method);
      nlohmann::ordered_json j;
      j["gpu"] = g.name;
      j["calibrated"] = g.calibrated;
      j["method"] = m.name;
      j["params"] = m.params;
      j["workload"] = res.workload.name;
      j["display"] = {{"name", d.name}, {"width", d.width}, {"height", d.height}, {"eyes", d.eyes}};
      j["est_ms_total"] = fc.total_ms;
      if (fc.interval_level > 0) {
        j["est_ms_total_lo"] = fc.total_lo_ms;
        j["est_ms_total_hi"] = fc.total_hi_ms;
        j["interval_level"] = fc.interval_level;
      }
      j["model"] = model_name(g.model);
      for (auto& p : fc.passes) {
        j["est_ms_" + p.pass] = p.ms;
        if (fc.interval_level > 0) {
          j["est_ms_" + p.pass + "_lo"] = p.lo_ms;
          j["est_ms_" + p.pass + "_hi"] = p.hi_ms;
        }
      }
      j["resource_ms"] = fc.resource_ms;
      j["speedup_vs_full"] = fc.total_ms > 0 ? full_total / fc.total_ms : 0.0;
      if (!t.config.empty()) j["label"] = m.text, j["indirect"] = res.indirect;
      if (!fc.missing_counters.empty()) j["missing_counters"] = fc.missing_counters;
      if (with_loss) {
        CostMethod lm = m;
        lm.name = lost_frame_method(m.name, policy);
        if (lm.name == "full" && m.name != "full") lm.params = Json::object();
        bool modelled = true;
        if (policy == OnInvalid::Widen)
          lm.params = widened_method_params(lm.name, lm.params, loss.widen_k, &modelled, &d);
        const double lost = modelled ? cost_for(g, lm, res, t.where_method).total_ms : double(NAN);
        const double expect = expected_ms_with_loss(fc.total_ms, lost, loss.fraction);
        j["tracking_loss"] = {{"fraction", loss.fraction},
                              {"on_invalid", loss.on_invalid},
                              {"widen_k", policy == OnInvalid::Widen ? Json(loss.widen_k) : Json()},
                              {"lost_ms", modelled ? Json(lost) : Json()},
                              {"est_ms_total_with_loss", modelled ? Json(expect) : Json()}};
      }
      out.rows.push_back(j);
    }
  }
  return out;
}

WhatIf what_if_from(const std::map<std::string, double>& scale, const std::string& where) {
  WhatIf w;
  for (auto& [k, f] : scale) {
    const std::string at = where + "." + k;
    double* slot = k == "shading"    ? &w.shading
                   : k == "geometry" ? &w.geometry
                   : k == "raster"   ? &w.raster
                   : k == "memory"   ? &w.memory
                   : k == "fixed"    ? &w.fixed
                                     : nullptr;
    if (!slot)
      throw Error(where + "." + escape_control(k, 40),
                  "unknown resource (shading, geometry, raster, memory, fixed)");
    check_number(at, f, CostArgRanges::scale());
    *slot = f;
  }
  return w;
}

CostRows budget_rows(const CostTarget& t, double budget_ms, double level, const WhatIf& wi) {
  check_number("budget_ms", budget_ms, CostArgRanges::budget_ms());
  check_number("p", level, fit_level_range());
  for (double f : {wi.shading, wi.geometry, wi.raster, wi.memory, wi.fixed})
    check_number("scale", f, CostArgRanges::scale());
  CostRows out;
  out.target = resolve_cost_target(t, budget_default_methods());
  const ResolvedCostTarget& res = out.target;
  const std::string models = models_of(t);
  for (auto& gname : res.gpus) {
    GpuProfile g = apply_what_if(GpuProfile::load(gname, models), wi);
    out.gpus.push_back(g);
    for (const CostMethod& m : res.methods) {
      const FrameCost fc = cost_for(g, m, res, t.where_method);
      const double T = fc.total_ms;
      const bool iv = fc.interval_level > 0;
      // The same decision and factors everywhere (sim/cost/budget.h).
      const BudgetDecision bd = decide_budget(g.interval, T, budget_ms, level);
      BudgetQuery q;
      q.gpu = &g, q.method = m.name, q.params = m.params, q.workload = &res.workload;
      q.display = res.display, q.indirect = res.indirect, q.where = t.where_method + " " + m.text;
      const std::vector<BudgetChange> changes = fitting_changes(q, budget_ms, level);
      nlohmann::ordered_json j = {{"gpu", g.name},
                                  {"calibrated", g.calibrated},
                                  {"method", m.text},
                                  {"workload", res.workload.name},
                                  {"est_ms_total", T},
                                  {"budget_ms", budget_ms},
                                  {"fits", bd.fits},
                                  {"fit_level", level},
                                  {"verdict", bd.verdict},
                                  {"p_fit", bd.p_fit},
                                  {"headroom_ms", budget_ms - T},
                                  {"headroom", budget_ms > 0 ? (budget_ms - T) / budget_ms : 0.0}};
      nlohmann::ordered_json cj = nlohmann::ordered_json::array();
      for (auto& c : changes)
        cj.push_back({{"kind", c.kind},
                      {"change", c.text},
                      {"value", c.value},
                      {"est_ms_total", c.total_ms},
                      {"p_fit", c.probability}});
      j["changes_for_p"] = level;
      j["changes"] = cj;
      if (iv) {
        j["est_ms_total_lo"] = fc.total_lo_ms, j["est_ms_total_hi"] = fc.total_hi_ms;
        j["interval_level"] = fc.interval_level;
      }
      for (auto& pc : fc.passes) {
        j["est_ms_" + pc.pass] = pc.ms;
        if (iv)
          j["est_ms_" + pc.pass + "_lo"] = pc.lo_ms, j["est_ms_" + pc.pass + "_hi"] = pc.hi_ms;
      }
      j["resource_ms"] = fc.resource_ms;
      const BudgetFactors bf = budget_factors(fc, budget_ms);
      for (auto& rn : budget_resources()) j["factor_" + rn] = finite_or_inf(bf.x.at(rn));
      j["factor_all"] = finite_or_inf(bf.x_all);
      out.rows.push_back(j);
    }
  }
  return out;
}

}  // namespace fovsim
