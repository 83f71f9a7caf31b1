// What a tracking-loss policy costs (docs/tracking.md "What each policy costs"), for `fovsim
// predict --tracking-loss F --on-invalid P`: the analytic frame of a method on tracked frames,
// the frame it renders on lost frames under the policy, and the expected frame time of a
// deployment that loses tracking on a fraction F of its frames.
#pragma once
#include <string>

#include "sim/core/params.h"
#include "sim/display/display.h"
#include "sim/trace/tracking.h"

namespace fovsim {

// The method's parameters on a lost frame under `widen` with growth factor k (>= 1), as the
// methods widen them in a run (FrameContext::widen): the method writes them itself
// (FoveationMethod::widen_cost_keys, in its file; a mapping method through
// SamplingGeometry::widen_keys): kfr sigma' = max(1, sigma / k); rmfr the same and fx, fy
// (fx_px, fy_px) times k; hyperbolic, linear, fvrs radius_scale times k (their eccentricity
// thresholds); flc with log_polar lp_sigma' = max(1, lp_sigma / k) (its foveal region does not
// change its analytic cost: the VPL budget is a count); rmfr_auto its sigma as rmfr does.
// `modelled` is false for a method whose declaration says its widened cost cannot be stated
// from its keys (MethodCost::widening_modelled; twfr: its redraw fraction is measured, not
// derived from phi_f). With display d, an iso-budget target (target_shaded_fraction) is solved
// first and replaced by the widened solution, as a run widens the resolved geometry; without
// d the target stays and is solved unwidened.
Json widened_method_params(const std::string& method, const Json& params, double k, bool* modelled,
                           const Display* d = nullptr);

// The method a lost frame is costed as under `p` (for OnInvalid::Full the full-resolution
// method, full_resolution_method() in factory.h; else `method`), and the expected frame time
// (1 - fraction) valid_ms + fraction lost_ms.
std::string lost_frame_method(const std::string& method, OnInvalid p);
double expected_ms_with_loss(double valid_ms, double lost_ms, double fraction);

}  // namespace fovsim
