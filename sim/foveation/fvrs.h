// `fvrs` (fvrs.cpp): what its analytic counters evaluate outside a render.
#pragma once
#include "sim/display/display.h"

namespace fovsim {

// Fraction of the screen's pixels shaded by fVRS rates (1, 1/4, 1/16 inside r1, r2 and beyond
// them, in degrees: pass the radius-scaled r1_eff, r2_eff), through the real projection
// (docs/architecture.md "Inputs: displays, traces, scenes, configs") at the gaze (gaze_u, gaze_v as
// fractions of W, H) on a grid of at most 256x256 points, per point rather than per 4x4 tile as a
// render chooses its rates.
double fvrs_shaded_fraction(const Display& d, double gaze_u, double gaze_v, double r1, double r2);

}  // namespace fovsim
