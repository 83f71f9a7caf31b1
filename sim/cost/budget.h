// Budget what-if (docs/architecture.md "Layers and their dependencies" "Does it still fit 90 Hz if
// the GPU had 2x shading throughput?"): a GPU profile with scaled resource throughputs, and the
// throughput factor each resource would need for a frame to fit a budget. Used by `fovsim budget`
// (docs/cost_model.md).
#pragma once
#include <map>
#include <string>
#include <vector>

#include "sim/core/params.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/display/display.h"

namespace fovsim {

// The ranges of the what-if arguments, one declaration for `fovsim predict`/`budget` (their
// flags) and the Python API (fovsim.estimate/budget through the bindings): both check with
// check_number/check_integer (sim/core/params.h), so NaN, 0 and out-of-range values fail alike.
struct CostArgRanges {
  static Range pixels() { return Range::closed(1, 1 << 20); }  // --width, --height
  static Range eyes() { return Range::closed(1, 2); }
  static Range budget_ms() { return Range::above(0, 1e6); }
  static Range hz() { return Range::closed(1, 1e4); }
  static Range scale() { return Range::closed(1e-6, 1e6); }  // --scale-shading etc.
};
// The check of one estimate's overrides as the Python API passes them: 0 keeps the display's
// width/height/eyes and means "no budget"; anything else must be in its range above; every
// `scale` entry must name a resource (shading, geometry, raster, memory, fixed) and be in range.
// Throws fovsim::Error naming the argument ("width", "scale.shading").
void check_cost_args(double width, double height, double eyes, double budget_ms,
                     const std::map<std::string, double>& scale);

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

struct Workload;

// The cheapest change that makes a configuration fit a budget with probability >= target
// (fit_probability on the profile's interval, gpu_profile.h). Searched in order of what it
// costs the user: the method's own parameter as it declares it (FoveationMethod::budget_knob,
// sim/foveation/method_cost.h: kfr/rmfr sigma up in steps of 0.1 to 4; flc vpl_budget halved
// down to 64), then the per-eye resolution (steps of 5% down to 50%), then
// a faster GPU (one throughput factor on every resource but the fixed overheads). `kind`:
// "none" (already fits), "param", "resolution", "gpu", or "" when nothing found.
struct BudgetChange {
  std::string kind, text;  // text: e.g. "sigma 1.8 -> 2.3", "resolution x0.85", "GPU x1.40"
  double value = 0;        // the new sigma / vpl_budget / resolution scale / throughput factor
  double total_ms = 0, probability = 0;
};
struct BudgetQuery {
  const GpuProfile* gpu = nullptr;
  std::string method;
  Json params = Json::object();
  const Workload* workload = nullptr;
  Display display;
  bool indirect = false;
  std::string where;  // names the method in errors
};
double fit_probability(const GpuProfile& g, const FrameCost& fc, double budget_ms);

// The one definition of a budget decision, used by every command that decides one (`fovsim
// budget` and `budget --results`, a run's and a sweep's `fits_budget`, `sweep.search.p_fit`,
// `sweep.iso_budget` on a cost column, the plots' budget line, the Python API):
//   p_fit = P(true frame time <= budget) for a model estimate `ms`, under the GPU profile's
//           held-out frame-total errors (fit_probability, gpu_profile.h);
//   "fits" when p_fit >= level, "does not fit" when p_fit <= 1 - level, else "uncertain".
// Without an interval (a profile no calibration covers) p_fit is 1 or 0: the point estimate.
// The level must be above 1/2 so that "fits" and "does not fit" cannot both hold.
constexpr double kDefaultFitLevel = 0.8;
inline Range fit_level_range() {
  return Range::closed(0.5, 0.99);
}
struct BudgetDecision {
  double p_fit = 0;
  bool fits = false;
  const char* verdict = "";  // "fits", "does not fit", "uncertain"
};
BudgetDecision decide_budget(const PredictionInterval& iv, double ms, double budget_ms,
                             double level);
// The largest model estimate that still fits at `level`: ms <= fit_threshold_ms(...) exactly
// when decide_budget(...).fits (p_fit does not increase with ms). budget_ms itself without an
// interval; 0 when nothing fits at that level (too few held-out rows for it). For lines drawn
// on cost axes and for cost columns compared with a budget.
double fit_threshold_ms(const PredictionInterval& iv, double budget_ms, double level);

// A run's budget decisions: the level (`budget.p_fit`) and each GPU profile's interval by
// profile name (a name not in the map: no interval, the point estimate decides).
struct FitRule {
  double level = kDefaultFitLevel;
  std::map<std::string, PredictionInterval> intervals;
  const PredictionInterval& interval_of(const std::string& gpu) const;
  BudgetDecision decide(const std::string& gpu, double ms, double budget_ms) const {
    return decide_budget(interval_of(gpu), ms, budget_ms, level);
  }
};

std::vector<BudgetChange> fitting_changes(const BudgetQuery& q, double budget_ms, double target);
// The first of fitting_changes (kind "" when none).
BudgetChange cheapest_fitting_change(const BudgetQuery& q, double budget_ms, double target);

}  // namespace fovsim
