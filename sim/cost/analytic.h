// Analytic counters (issue 7 item 2): the counters a method would report for a workload on a
// display, without rendering, so `fovsim predict` and calibration run from descriptors.
//
// Parameters (method block, JSON; unknown keys are ignored here, the method validates them):
//   name             type    default  range        source
//   sigma            number  1.8      [1, 64]      kfr/rmfr buffer ratio: shaded = W*H/sigma^2 (seed 004 §2, seed 003 §3.2)
//   shaded_fraction  number  -       [0, 1]       hyperbolic/linear/fvrs override; hyperbolic/linear
//                                                  default to 1/sigma^2 (iso-density, seed 003 §5.1)
//   r1, r2           number  10, 20   degrees      fvrs: 1x1 inside r1, 2x2 to r2, 4x4 beyond (seed 002 §8.4)
//   gaze_u, gaze_v   number  0.5      [-1, 2]      normalized gaze point for fvrs
//   redraw_fraction  number  workload [0, 1]       twfr pixels redrawn / W*H (seed 002 §8.4: 6%)
//   prims_fraction   number  workload [0, 1]       twfr primitives kept by foveation culling (seed 002 Fig. 12)
//   vpl_budget       number  workload >= 0         flc VPLs kept (seed 001 §5)
//   filter_taps      number  4        >= 0         pass-2 taps per full-res pixel (bilinear)
#pragma once
#include <string>

#include "sim/core/counters.h"
#include "sim/core/params.h"
#include "sim/cost/workload.h"
#include "sim/display/display.h"

namespace fovsim {

// Counters per eye at the display's resolution (pixel_scale = 1). `where` prefixes errors.
Counters analytic_counters(const std::string& method, const Json& params, const Workload& w,
                           const Display& d, const std::string& where = "params");

// Fraction of the screen's pixels shaded by fVRS rates (1, 1/4, 1/16 by eccentricity band),
// through the real projection (DESIGN §3) on a grid of at most 256x256 points.
double fvrs_shaded_fraction(const Display& d, double gaze_u, double gaze_v, double r1, double r2);

}  // namespace fovsim
