// Analytic counters: the counters a method would report for a workload on a
// display, without rendering, so `fovsim predict` and calibration run from descriptors.
//
// Parameters: the method's own keys (the same as in a run config, parsed and validated by the
// method's own parser through the factory: same defaults and ranges, unknown keys are errors),
// plus these analytic assumptions, which replace what a rendered run would measure:
//   name                   methods                     default   range    meaning
//   shaded_fraction        hyperbolic, linear, fvrs    computed  [0, 1]   override of the shaded
//   fraction
//                                                                         (default: the method's
//                                                                         layers / probability /
//                                                                         rates at the gaze)
//   gaze_u, gaze_v         hyperbolic, linear, fvrs    0.5       [-1, 2]  gaze point as a fraction
//   of W, H filter_taps_per_pixel  kfr, rmfr, hyperbolic, lin. 4         >= 0     pass-2 taps per
//   full-res pixel redraw_fraction        twfr                        workload  [0, 1]   pixels
//   redrawn / W*H (Franke et al. 2021 §8.4) prims_fraction         twfr workload  [0, 1] primitives
//   kept by foveated culling
// kfr/rmfr shade their whole (W/sigma) x (H/sigma) buffer; flc's vpl_budget is FLC's own key
// (default: the workload's budget when not given).
#pragma once
#include <string>

#include "sim/core/counters.h"
#include "sim/core/params.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/workload.h"
#include "sim/display/display.h"
#include "sim/foveation/mapping_spec.h"

namespace fovsim {

// Counters per eye at the display's resolution (pixel_scale = 1). `where` prefixes errors.
// `indirect`: the scene has one-bounce indirect light (SceneFeatures::indirect), so every
// method also shades VPLs with its lighting strategy: RSM texels = workload.rsm_res^2 x lights,
// VPLs used per shaded sample = all of them (all_vpls) or min(all, vpl_budget) (flc, fir), and
// the selection work its strategy declares (LightingStrategy::declare_passes; the `flc` method
// always has it). `passes` (optional) receives the passes the method declares, for
// CostInputs::passes.
// The spec a run renders with on display d: an iso-budget target (target_shaded_fraction)
// solved for the geometry's free parameter at the centre gaze, with the frame's eccentricity
// map, as MappingMethodBase::resolve does (Ye et al. 2022 §5.1); s itself without a target.
// The result has no target (its free parameter holds the solution).
MappingSpec resolved_mapping_spec(const MappingSpec& s, const Display& d);

Counters analytic_counters(const std::string& method, const Json& params, const Workload& w,
                           const Display& d, const std::string& where = "params",
                           bool indirect = false, CostPasses* passes = nullptr);

// What `fovsim predict` and `budget` compute for one method: its analytic counters on this
// workload and display, costed with `gpu` (estimate_frame, pixel_scale 1).
FrameCost analytic_frame(const GpuProfile& gpu, const std::string& method, const Json& params,
                         const Workload& w, const Display& d, const std::string& where = "params",
                         bool indirect = false);

// Fraction of the screen's pixels shaded by fVRS rates (1, 1/4, 1/16 by eccentricity band),
// through the real projection (docs/architecture.md §3) on a grid of at most 256x256 points.
double fvrs_shaded_fraction(const Display& d, double gaze_u, double gaze_v, double r1, double r2);

}  // namespace fovsim
