// Analytic counters: the counters a method would report for a workload on a display, without
// rendering, so `fovsim predict`, `budget` and calibration run from descriptors.
//
// Parameters: the method's own keys (the same as in a run config, parsed and validated by the
// method's own parser through the factory: same defaults and ranges, unknown keys are errors),
// plus the analytic-only keys the method declares (MethodCost::analytic_keys, in its file:
// assumptions that replace what a rendered run would measure, e.g. a baseline's
// shaded_fraction and gaze_u / gaze_v, the mapping methods' filter_taps_per_pixel, TWFR's
// redraw_fraction and prims_fraction; docs/cost_model.md lists them). The counters are the
// method's own (FoveationMethod::analytic_counters, sim/foveation/method_cost.h); this file
// only builds the method, solves its iso-budget, hands it the workload and adds its lighting
// strategy's VPLs.
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

// The spec a run renders with on display d: an iso-budget target (target_shaded_fraction)
// solved for the geometry's free parameter at the centre gaze, with the frame's eccentricity
// map, as MappingMethodBase::resolve does (Ye et al. 2022 §5.1); s itself without a target.
// The result has no target (its free parameter holds the solution).
MappingSpec resolved_mapping_spec(const MappingSpec& s, const Display& d);

// Counters per eye at the display's resolution (pixel_scale = 1). `where` prefixes errors.
// `indirect`: the scene has one-bounce indirect light (SceneFeatures::indirect), so every
// method also shades VPLs with its lighting strategy: RSM texels = workload.rsm_res^2 x lights,
// VPLs used per shaded sample = all of them (all_vpls) or min(all, vpl_budget) (flc, fir), and
// the selection work its strategy declares (LightingStrategy::declare_passes; a method that builds
// its own VPLs, own_vpls, counts them itself). `passes` (optional) receives the passes the method
// declares, for CostInputs::passes.
Counters analytic_counters(const std::string& method, const Json& params, const Workload& w,
                           const Display& d, const std::string& where = "params",
                           bool indirect = false, CostPasses* passes = nullptr);

// The workload's numbers the methods' analytic counters read (method_cost.h).
AnalyticWorkload analytic_workload(const Workload& w);

// What `fovsim predict` and `budget` compute for one method: its analytic counters on this
// workload and display, costed with `gpu` (estimate_frame, pixel_scale 1).
FrameCost analytic_frame(const GpuProfile& gpu, const std::string& method, const Json& params,
                         const Workload& w, const Display& d, const std::string& where = "params",
                         bool indirect = false);

}  // namespace fovsim
