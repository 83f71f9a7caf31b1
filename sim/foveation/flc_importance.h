// FLC perceptual importance map (Yang et al. 2021 §4.1): visual acuity (eqs. 3-6), geometry
// silhouette (eq. 7) and indirect brightness from history (eq. 8), combined by eq. 9.
#pragma once
#include <vector>

#include "sim/core/image.h"
#include "sim/core/math.h"
#include "sim/render/gbuffer.h"

namespace fovsim {

struct FlcImportanceParams {
  double omega_p = 0.2;  // eq. 3: acuity floor in the outer periphery
  double slope = 2.25;   // eq. 4: acuity slope s (per radian of eccentricity)
  // eq. 5: ratio r of the foveal region to the screen, given as the foveal radius over the
  // half screen diagonal |d| (r = fovea_frac^2, so m(r, alpha) = e at the fovea's edge).
  // Seed §7: 150 px at 1024x1024 -> 150 / (512 sqrt 2) = 0.2072.
  double fovea_frac = 150.0 / (512.0 * 1.4142135623730951);
  bool exact_eccentricity = false;  // false: eq. 6; true: exact eccentricity of the projection
  // eq. 7 silhouette: a pixel whose depth, normal or colour differs from a 4-neighbour by
  // more than a threshold gets the constant `silhouette_value`, others 0.
  double silhouette_value = 1.0;
  double depth_threshold = 0.05;       // relative depth difference |z - z'| / z
  double normal_threshold_deg = 30.0;  // angle between normals
  double color_threshold = 48.0;       // delta c of eq. 7 (8-bit scaled units)
  double delta = 20.0;                 // eq. 8: indirect brightness influence factor
};

// eqs. 5-6 with alpha the diagonal field of view (|d| is the half diagonal): the acuity
// importance of a pixel at `dist_px` from the gaze (eqs. 3-4); `ecc_rad` overrides eq. 6
// when >= 0.
double flc_acuity(double dist_px, double half_diag_px, double tan_half_fov_diag,
                  const FlcImportanceParams& p, double ecc_rad = -1.0);
// eq. 7: weighted colour difference of two display-encoded RGB colours in [0,1].
double flc_color_difference(const float* c, const float* cn);

struct FlcImportanceMaps {
  Image acuity, silhouette, brightness, importance;  // 1-channel, W x H
};

// Builds p = max(p_a, p_g) * p_b (eq. 9) for every pixel; misses get 0.
// `color`: display-encoded RGB of the frame (for eq. 7); `history` (1-channel tone-mapped
// indirect luma, or nullptr when there is none yet -> p_b = 1); `ecc_deg` (W*H, optional,
// used when p.exact_eccentricity). `keep_parts`: also fill acuity/silhouette/brightness.
void flc_importance_map(const GBuffer& g, const Image& color, const Image* history,
                        const glm::dvec2& gaze_px, double tan_half_fov_diag,
                        const std::vector<float>* ecc_deg, const FlcImportanceParams& p,
                        FlcImportanceMaps& out, bool keep_parts);

}  // namespace fovsim
