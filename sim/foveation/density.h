// Analytic sampling density of the mapping methods and baselines, and the sample counts their
// render passes shade (the theoretical shading reduction, Ye et al. 2022 §5.1 / Fig. 11). The same
// geometry functions (LP/RS buffer sizes, hyperbolic layers, linear probability, fvrs rates)
// are used by the methods' render() so analytic counts and measured counts agree.
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
  double ecc_deg(double x, double y) const {
    const double e = cam->eccentricity_deg(x, y, gaze_dir);
    return widen == 1.0 ? e : e / widen;
  }
  // View with the gaze at screen point (gx, gy) pixels; gaze_dir from the camera.
  static MappingView at(const Camera& cam, glm::dvec2 gaze_px);
};

// Hyperbolic (Guenter et al. 2012 as set up in Ye et al. 2022 §5.1): layer i covers the
// screen-aligned square of half-side R_i around the gaze (R_i = pixel radius of eccentricity r_i,
// clipped to the screen; the outer layer is the whole screen) at pixel size s_i.
struct HyperLayer {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // screen rectangle (pixels)
  double s = 1;                           // pixel size
  int w = 0, h = 0;                       // layer buffer size = ceil(extent / s)
  double ecc_limit = 1e9;                 // eccentricity (deg) up to which the layer is used
};
std::vector<HyperLayer> hyperbolic_layers(const MappingSpec& s, const MappingView& v);
// Blend weight of an inner layer at eccentricity e: 1 inside limit - band, smoothstep to 0 at
// the limit (Guenter's blend between layers).
inline float hyper_weight(double e, double limit, double band) {
  if (e >= limit) return 0.f;
  if (band <= 0 || e <= limit - band) return 1.f;
  const double t = (limit - e) / band;
  return float(t * t * (3 - 2 * t));
}
// Effective weights (inner, middle, outer) of the three layers at screen pixel centre (px, py)
// with eccentricity e; they sum to 1.
void hyper_effective_weights(const MappingSpec& s, const std::vector<HyperLayer>& layers, double px,
                             double py, double e, float eff[3]);
// Marks the layer pixels the composite reads (bilinear footprints of pixels with a non-zero
// effective weight): only those are shaded, like a stencil-masked layer pass, so hidden parts
// of coarser layers cost nothing. masks (optional) receives one w*h mask per layer.
// Returns the number of marked layer pixels.
double hyperbolic_needed(const MappingSpec& s, const MappingView& v,
                         const std::vector<HyperLayer>& layers, std::vector<uint8_t>* masks);

// Linear fall-off (Weier et al. 2016, Ye et al. 2022 §5.1): sampling probability 1 inside r1,
// falling linearly to p_min at r2, p_min beyond.
double linear_probability(const MappingSpec& s, double ecc_deg);

// fvrs (Patney et al. 2016 / Franke et al. 2021 §8.4): shading rate (coarse pixel edge 1, 2 or 4)
// of the 4x4 block whose top-left pixel is (bx*4, by*4), from the eccentricity at its centre.
int fvrs_rate(const MappingSpec& s, const MappingView& v, int bx, int by);

// Sampling density (shading samples per screen pixel) at screen point (x, y), from the
// method's SamplingGeometry (kfr.cpp, rmfr.cpp, ...): Jacobian of the forward map for
// kfr/rmfr, 1/s^2 of the finest covering layer for hyperbolic, p(e) for linear, 1/rate^2
// for fvrs.
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
