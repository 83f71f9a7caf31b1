// Budget what-if maths (see budget.h).
#include "sim/cost/budget.h"

#include <cmath>
#include <cstdio>

#include "sim/core/error.h"
#include "sim/core/text.h"
#include "sim/cost/analytic.h"
#include "sim/cost/passes.h"
#include "sim/cost/workload.h"
#include "sim/foveation/factory.h"

namespace fovsim {

void check_cost_args(double width, double height, double eyes, double budget_ms,
                     const std::map<std::string, double>& scale) {
  if (width != 0) check_integer("width", width, CostArgRanges::pixels());
  if (height != 0) check_integer("height", height, CostArgRanges::pixels());
  if (eyes != 0) check_integer("eyes", eyes, CostArgRanges::eyes());
  if (budget_ms != 0) check_number("budget_ms", budget_ms, CostArgRanges::budget_ms());
  for (auto& [k, f] : scale) {
    if (k != "shading" && k != "geometry" && k != "raster" && k != "memory" && k != "fixed")
      throw Error("scale." + escape_control(k, 40),
                  "unknown resource (shading, geometry, raster, memory, fixed)");
    check_number("scale." + k, f, CostArgRanges::scale());
  }
}

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

double fit_probability(const GpuProfile& g, const FrameCost& fc, double budget_ms) {
  return fit_probability(g.interval, fc.total_ms, budget_ms);
}

BudgetDecision decide_budget(const PredictionInterval& iv, double ms, double budget_ms,
                             double level) {
  BudgetDecision d;
  d.p_fit = fit_probability(iv, ms, budget_ms);
  d.fits = d.p_fit >= level;
  d.verdict = d.fits ? "fits" : (d.p_fit <= 1 - level ? "does not fit" : "uncertain");
  return d;
}

double fit_threshold_ms(const PredictionInterval& iv, double budget_ms, double level) {
  if (!(budget_ms > 0)) return 0;
  if (iv.total_scores.empty() && iv.level <= 0) return budget_ms;  // the point estimate
  auto fits = [&](double ms) { return fit_probability(iv, ms, budget_ms) >= level; };
  // p_fit is a non-increasing function of ms (a step function with held-out scores, continuous
  // with only the factors): bisection on log(ms), keeping `lo` on the fitting side, so the
  // returned threshold itself fits.
  double lo = budget_ms * 1e-6, hi = budget_ms * 1e6;
  if (!fits(lo)) return 0;
  if (fits(hi)) return hi;
  for (int it = 0; it < 200 && hi - lo > 1e-12 * hi; ++it) {
    const double mid = std::sqrt(lo * hi);
    (fits(mid) ? lo : hi) = mid;
  }
  return lo;
}

const PredictionInterval& FitRule::interval_of(const std::string& gpu) const {
  static const PredictionInterval none;
  auto it = intervals.find(gpu);
  return it == intervals.end() ? none : it->second;
}

namespace {

FrameCost eval(const BudgetQuery& q, const GpuProfile& g, const Json& params, const Display& d) {
  return analytic_frame(g, q.method, params, *q.workload, d, q.where, q.indirect);
}

}  // namespace

std::vector<BudgetChange> fitting_changes(const BudgetQuery& q, double budget_ms, double target) {
  std::vector<BudgetChange> out;
  const GpuProfile& g = *q.gpu;
  const FrameCost base = eval(q, g, q.params, q.display);
  const double p0 = fit_probability(g, base, budget_ms);
  if (p0 >= target) {
    out.push_back({"none", "none needed", 0, base.total_ms, p0});
    return out;
  }
  // 1. The method's own quality knob, as the method declares it (budget_knob, method_cost.h:
  // kfr, rmfr, rmfr_auto raise sigma; flc halves vpl_budget), from the configured value or the
  // method's default.
  Params dp(Json::object(), "budget", "");
  const std::unique_ptr<FoveationMethod> inst = make_method(q.method, dp);
  const BudgetKnob knob = inst->budget_knob(analytic_workload(*q.workload));
  if (!knob.key.empty() && knob.steps) {
    const double v0 = q.params.value(knob.key, knob.value);
    const std::string f = "%." + std::to_string(knob.decimals) + "f";
    for (const double v : knob.steps(v0)) {
      Json p = q.params;
      p[knob.key] = knob.integer ? Json(int(v)) : Json(v);
      const FrameCost fc = eval(q, g, p, q.display);
      const double pr = fit_probability(g, fc, budget_ms);
      if (pr >= target) {
        out.push_back({"param", knob.key + " " + fmt(f.c_str(), v0) + " -> " + fmt(f.c_str(), v), v,
                       fc.total_ms, pr});
        break;
      }
    }
  }
  // 2. Per-eye resolution.
  for (int k = 1; k <= 10; ++k) {
    const double sc = 1 - 0.05 * k;
    Display d = q.display;
    d.width = std::max(1, int(std::lround(q.display.width * sc)));
    d.height = std::max(1, int(std::lround(q.display.height * sc)));
    const FrameCost fc = eval(q, g, q.params, d);
    const double pr = fit_probability(g, fc, budget_ms);
    if (pr >= target) {
      out.push_back({"resolution",
                     "resolution x" + fmt("%.2f", sc) + " (" + std::to_string(d.width) + "x" +
                         std::to_string(d.height) + " per eye)",
                     sc, fc.total_ms, pr});
      break;
    }
  }
  // 3. A faster GPU: one factor on every throughput but the fixed overheads (bisection; the
  // total falls monotonically with it).
  auto at = [&](double x) {
    WhatIf w;
    w.shading = w.geometry = w.raster = w.memory = x;
    return eval(q, apply_what_if(g, w), q.params, q.display);
  };
  double lo = 1, hi = 2;
  while (hi < 1e4 && fit_probability(g, at(hi), budget_ms) < target) lo = hi, hi *= 2;
  if (hi < 1e4) {
    for (int it = 0; it < 30; ++it) {
      const double mid = 0.5 * (lo + hi);
      (fit_probability(g, at(mid), budget_ms) >= target ? hi : lo) = mid;
    }
    const FrameCost fc = at(hi);
    out.push_back({"gpu", "GPU throughput x" + fmt("%.2f", hi), hi, fc.total_ms,
                   fit_probability(g, fc, budget_ms)});
  }
  return out;
}

BudgetChange cheapest_fitting_change(const BudgetQuery& q, double budget_ms, double target) {
  std::vector<BudgetChange> v = fitting_changes(q, budget_ms, target);
  return v.empty() ? BudgetChange{} : v.front();
}

}  // namespace fovsim
