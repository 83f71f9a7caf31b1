// How a method costs itself (docs/architecture.md "Methods and lighting strategies", "Cost model"):
// what it declares to the GPU cost model (sim/cost/), so that the cost layer never knows a method
// by its name.
//
// A method's cost has two parts, both in the method's own file:
//  - its declaration `MethodCost <name>_cost()` (beside `<name>_params()`, read through the
//    factory table, MethodEntry::cost): the passes of its pipeline, the keys only the analytic
//    counters understand, and whether its widened cost under tracking loss is modelled;
//  - what its instance computes from its parsed parameters (FoveationMethod, method.h):
//    analytic_counters (the counters it would report, for `fovsim predict`, `budget` and
//    calibration), budget_knob (the parameter `fovsim budget` may turn first) and
//    widen_cost_keys (its keys on a frame under tracking loss, `predict --tracking-loss`).
// Its lighting strategy declares its own part the same way (LightingStrategy::declare_passes,
// analytic_selection_counters).
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "sim/core/counters.h"
#include "sim/core/params.h"
#include "sim/display/display.h"
#include "sim/foveation/cost_passes.h"

namespace fovsim {

class MappingSpec;  // mapping_spec.h

// A method's declaration to the cost model (MethodEntry::cost, `<name>_cost()` in its file).
struct MethodCost {
  // The passes of its own pipeline (CostPasses's pipeline flags); the lighting strategy adds
  // its own (declared_passes, factory.h).
  CostPasses passes;
  // Keys that only the analytic counters understand (assumptions that replace what a render
  // would measure: a baseline's shaded_fraction, TWFR's redraw_fraction, ...). `predict`,
  // `budget` and the calibration tables pass them beside the method's own keys; the method
  // reads them from AnalyticFrame::keys. A key the method does not read is an error.
  std::vector<std::string> analytic_keys;
  // False when its cost on a frame under tracking loss cannot be stated from its keys (twfr:
  // the redraw fraction is measured, not derived from phi_f); `predict --tracking-loss` says so.
  bool widening_modelled = true;
};

// The numbers of a scene's workload (sim/cost/workload.h, models/workloads/*.json) that
// methods read for their analytic counters; the cost layer fills it from its Workload
// (analytic_counters, sim/cost/analytic.cpp).
struct AnalyticWorkload {
  double shaded_fraction = -1;    // a baseline's shaded fraction when given (< 0: computed)
  double triangles = -1;          // triangles of the scene (< 0: not known, counted as 0)
  double submitted_fraction = 1;  // left after frustum culling
  double lights = -1;             // lights evaluated per shaded sample (< 0: not known)
  double rsm_res = 64;            // RSM texels per side (one VPL per texel, Yang et al. 2021 §3)
  double vpl_budget = 1024;       // VPLs kept for shading
  double importance_samples = 4096;  // importance samples per frame
  double lpt_fraction = 1;           // shaded samples / pixels with the log-polar transform
  double interleave = 4;             // interleaved-sampling factor
  double redraw_fraction = 0.059;    // TWFR: pixels redrawn / W*H (Franke et al. 2021 §8.4)
  double prims_fraction = 0.667;     // TWFR: primitives kept by foveated culling
};

// One analytic frame of a method: what FoveationMethod::analytic_counters gets.
struct AnalyticFrame {
  const Display* display = nullptr;  // the real display (pixel_scale 1)
  double pixels = 0;                 // W x H of one eye
  const AnalyticWorkload* workload = nullptr;
  // The analytic-only keys given (MethodCost::analytic_keys), read with their defaults; the
  // caller reports the unread ones.
  Params* keys = nullptr;
  // The method's own keys as given (before defaults).
  const Json* given = nullptr;
  // The method's parameter columns with an iso-budget target's free parameter as solved, then
  // its lighting strategy's.
  const std::vector<std::pair<std::string, double>>* columns = nullptr;
  // The sampling geometry with an iso-budget target solved at the centre gaze (nullptr
  // without one).
  const MappingSpec* geometry = nullptr;

  // The column `key`, `def` when the method has none.
  double column(const std::string& key, double def) const;
  // A baseline's shaded fraction: the key `shaded_fraction`, else the workload's, else
  // at_gaze(gaze_u, gaze_v) (the keys gaze_u, gaze_v: the gaze as fractions of W, H, default
  // the centre); `def` without pixels or geometry.
  template <class F>
  double baseline_fraction(double def, F at_gaze) const {
    const double gu = keys->number("gaze_u", 0.5, Range::closed(-1, 2)),
                 gv = keys->number("gaze_v", 0.5, Range::closed(-1, 2));
    const double f = keys->number("shaded_fraction",
                                  workload->shaded_fraction >= 0 ? workload->shaded_fraction : -1,
                                  Range::closed(-1, 1));
    if (f >= 0 || pixels <= 0) return f >= 0 ? f : def;
    if (!geometry) return def;
    return at_gaze(gu, gv);
  }
};

// The parameter `fovsim budget` turns first to make a frame fit (budget.h fitting_changes):
// its key, its value when the configuration does not give it, and the values to try from a
// start value, each cheaper than the one before. No key: the method has none.
struct BudgetKnob {
  std::string key;
  double value = 0;
  std::vector<double> (*steps)(double from) = nullptr;
  int decimals = 1;      // printed with this many decimals ("sigma 1.8 -> 2.3")
  bool integer = false;  // written into the configuration as an integer
};

// The knob of a whole reduced buffer (kfr, rmfr: W / w = sigma): raised in steps of 0.1 up to 4.
BudgetKnob coarser_buffer_knob(const char* key, double value);
// A count halved (rounded down) while it stays at least 64 (flc's vpl_budget).
BudgetKnob halved_count_knob(const char* key, double value);

}  // namespace fovsim
