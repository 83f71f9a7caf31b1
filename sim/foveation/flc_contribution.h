// FLC light culling (Yang et al. 2021 §5): per-VPL contribution (eq. 14) over the importance
// samples with BLSO visibility (eqs. 11-13), and stochastic culling of VPLs to a budget.
#pragma once
#include <cstdint>
#include <vector>

#include "sim/core/counters.h"
#include "sim/core/math.h"
#include "sim/render/rsm.h"
#include "sim/render/vpl.h"

namespace fovsim {

class Renderer;

enum class FlcVisibility { None, Blso, Exact };

struct BlsoParams {
  double lambda = 0.5;     // eq. 11 mixing coefficient (seed §7)
  double k = 34.0;         // eq. 12 attenuation factor (seed §7)
  double xi = 0.01;        // eq. 12 threshold, in units of the scene diagonal (scene dependent)
  double radius = 0.1;     // local-space radius, in units of the scene diagonal
  double cone_deg = 30.0;  // half-angle of the local solid angle around d
  int samples = 4;         // N' of eq. 13 per side
};

// eq. 12: visibility probability of one local sample with light-space depth difference dh
// (sample depth minus shadow-map depth, in scene-diagonal units).
double blso_g(double dh, double xi, double k);
// eq. 13: T(d) = mean of g over N' positions sampled in the cone of half-angle cone_deg around
// `dir` at distances in [2 xi, min(radius, max_dist)] (scene units scaled by `scene_scale`)
// from `o`. `key` seeds the positions (deterministic per pair).
double blso_T(const RSM& rsm, const glm::vec3& o, const glm::vec3& dir, float max_dist,
              const BlsoParams& p, float scene_scale, uint64_t key);

struct FlcShadingPoint {
  glm::vec3 p{0.f}, n{0, 1, 0};
  float weight = 0.f;  // importance p_i (times the eq. 1 region weight)
};

struct ContributionSettings {
  FlcVisibility visibility = FlcVisibility::Blso;
  BlsoParams blso;
  float eps2 = 1e-4f;        // eq. 10 epsilon (world units squared)
  float scene_scale = 1.f;   // scene diagonal (world units)
  float ray_offset = 1e-3f;  // exact mode: shadow-ray end points pushed along normals
  uint64_t seed = 1;
};

// eq. 14 for every VPL: C(l_v) = 1/N_s sum_i I_v V_i cos(theta_p) cos(theta_l) p_i / (d_i^2 + eps),
// I_v = luma of the VPL flux. `rsms` must contain the RSM of each VPL's light (BLSO).
// Counters: contribution_evals (VPLs x samples), blso_lookups, visibility_rays.
std::vector<double> flc_contributions(const std::vector<VPL>& vpls, const std::vector<RSM>& rsms,
                                      const std::vector<FlcShadingPoint>& pts,
                                      const ContributionSettings& s, const Renderer* r,
                                      Counters* c = nullptr);

struct CullResult {
  std::vector<uint32_t> kept;  // indices of kept VPLs, ascending
  std::vector<float> weight;   // 1 / inclusion probability (Horvitz-Thompson), per kept VPL
};

// Stochastic culling (seed §5, "similar to [29]"): inclusion probabilities
// q_i = min(1, c * C'_i) with C'_i = (1 - floor_mix) C_i / sum C + floor_mix / N and c chosen so
// that sum q_i = budget; exactly `budget` VPLs are then drawn by systematic sampling over q and
// weighted 1 / q_i, so the culled estimate is unbiased. budget >= N keeps every VPL (weight 1);
// budget 0 keeps none. All-zero contributions fall back to uniform probabilities.
CullResult flc_cull(const std::vector<double>& C, int budget, double floor_mix, uint64_t seed);

}  // namespace fovsim
