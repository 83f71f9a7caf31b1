// Analytic sampling density of the mapping methods and baselines, and the sample counts their
// render passes shade (the theoretical shading reduction, Ye et al. 2022 §5.1 / Fig. 11),
// through each method's SamplingGeometry (mapping_spec.h). The geometry functions a method
// defines in its own file (LP/RS buffer sizes, hyperbolic layers, linear probability, fvrs
// rates) are the ones its render() uses, so analytic counts and measured counts agree.
#pragma once
#include <functional>
#include <vector>

#include "sim/display/display.h"
#include "sim/foveation/mapping_spec.h"

namespace fovsim {

// The view a density is evaluated for: screen size, camera (eccentricity through the real
// projection), gaze pixel and direction, optionally the frame's eccentricity map (W*H degrees).
struct MappingView {
  int W = 0, H = 0;
  const Camera* cam = nullptr;
  glm::dvec2 gaze_px{0, 0};
  glm::dvec3 gaze_dir{0, 0, -1};
  const std::vector<float>* ecc = nullptr;
  // Tracking loss (FrameContext::widen): eccentricities are divided by this, as the frame's
  // eccentricity map already is, so every foveal radius of the baselines grows by it.
  double widen = 1.0;
  // render.scale (FrameContext::render_scale): a layer pixel or tile of s display pixels is
  // render_scale * s simulated pixels; 1 for `predict`, `density` and `budget` (the display).
  double render_scale = 1.0;
  double ecc_deg(double x, double y) const {
    const double e = cam->eccentricity_deg(x, y, gaze_dir);
    return widen == 1.0 ? e : e / widen;
  }
  // View with the gaze at screen point (gx, gy) pixels; gaze_dir from the camera.
  static MappingView at(const Camera& cam, glm::dvec2 gaze_px);
};

// Sampling density (shading samples per screen pixel) at screen point (x, y), from the
// method's SamplingGeometry (kfr.cpp, rmfr.cpp, ...; one virtual call per point): Jacobian of the
// forward map for kfr/rmfr, 1/s^2 of the finest covering layer for hyperbolic, p(e) for linear,
// 1/rate^2 for fvrs.
double sample_density(const MappingSpec& s, const MappingView& v, double x, double y);
// The density at every pixel centre (v.W x v.H, 1 channel).
void density_image(const MappingSpec& s, const MappingView& v, Image& d);

// Number of samples the method's render pass shades for this view (exact for kfr, rmfr,
// hyperbolic and fvrs without edge-aware extras; expected value for linear).
double expected_shaded_samples(const MappingSpec& s, const MappingView& v);

// Sum of row(i) for i in [0, n), rows evaluated in parallel and added in order.
double sum_rows(int n, const std::function<double(int)>& row);

// Iso-budget (Ye et al. 2022 §5.1): returns a copy of s whose free parameter (the geometry's
// free_param: sigma for kfr/rmfr, radius_scale for the baselines) makes
// expected_shaded_samples / (W H) as close as possible to `target`. `achieved` gets the resulting
// fraction; returns false (and the closest reachable setting) when the target lies outside the
// method's range.
bool solve_iso_budget(const MappingSpec& s, const MappingView& v, double target, MappingSpec& out,
                      double* achieved = nullptr);

}  // namespace fovsim
