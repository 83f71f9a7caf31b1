// `fir` lighting strategy: Foveated Instant Radiosity (Wang et al., ISMAR 2020) as Yang et al.,
// "Foveated light culling", describe it (§1, §2, §7): its VPLs come from the camera and their
// importance depends only on visibility and position relative to the fovea, not on the VPLs'
// intensity — the reason the FLC paper gives for FIR's larger foveal error (§7, Figs. 4-5).
//
// Model here (the FIR paper itself is not among our sources): FIR selects from the frame's
// shared VPL set (so every row shades the same lighting model and only the selection differs).
// "From the camera" becomes the visibility term: a VPL counts only when the eye sees it (it
// projects onto the screen, faces the eye and an Embree ray from the eye reaches it); its
// importance is then the acuity of its screen position (the FLC paper's eqs. 3-6, the same
// fovea model the flc strategy uses); invisible VPLs get 0. Flux is ignored. The VPLs are then
// culled to `vpl_budget` with the same unbiased stochastic culling (FLC §5), so the difference
// to `flc` is the importance alone.
//
// Parameters: lighting_fir_params() at the end of this file.
#include <cmath>

#include "sim/core/hash.h"
#include "sim/core/param_table.h"
#include "sim/core/rng.h"
#include "sim/foveation/flc_contribution.h"
#include "sim/foveation/flc_importance.h"
#include "sim/foveation/lighting.h"
#include "sim/foveation/method.h"
#include "sim/render/renderer.h"

namespace fovsim {
namespace {

struct FirSettings {
  int vpl_budget = 1024;
  FlcImportanceParams imp;  // acuity model (omega_p, slope, fovea_frac)
  double culling_floor = 0.02;
  uint64_t seed = 1;
};

class FirLighting final : public LightingStrategy {
 public:
  explicit FirLighting(const FirSettings& s) : s_(s) {}
  std::string name() const override { return "fir"; }
  std::vector<std::pair<std::string, double>> param_columns() const override {
    return {{"vpl_budget", s_.vpl_budget}};
  }
  const VplSoA& selected(const FrameContext&) const override { return selected_; }
  // One visibility-based importance per VPL.
  void analytic_selection_counters(Counters& c, double vpls, double) const override {
    c.set(Counter::contribution_evals, vpls);
  }
  // One importance per VPL and the culling to the budget: no importance-map pass.
  void declare_passes(CostPasses& p) const override { p.frame_rsm = p.culling = true; }

  void begin_frame(const FrameContext& ctx, Counters& c) override {
    const FrameVpls& fv = *ctx.vpls;
    const Camera& cam = *ctx.camera;
    const int W = ctx.gbuffer->width, H = ctx.gbuffer->height;
    const double half_diag = 0.5 * std::sqrt(double(W) * W + double(H) * H);
    const double tan_diag =
        std::sqrt(cam.tan_half_h * cam.tan_half_h + cam.tan_half_v * cam.tan_half_v);
    const glm::vec3 eye(cam.position);
    const size_t n = fv.vpls.size();
    std::vector<double> imp(n, 0.0);
    uint64_t rays = 0;
    for (size_t k = 0; k < n; ++k) {
      const VPL& v = fv.vpls[k];
      glm::dvec2 px;
      double depth = 0;
      if (!cam.project_world(glm::dvec3(v.position), px, &depth) || !(depth > 0)) continue;
      if (px.x < 0 || px.y < 0 || px.x >= W || px.y >= H) continue;
      if (glm::dot(v.normal, eye - v.position) <= 0.f) continue;  // faces away from the eye
      ++rays;
      if (ctx.renderer->occluded(eye, v.position + v.normal * fv.shading.ray_offset)) continue;
      const double dist = glm::length(px - ctx.gaze_px);
      imp[k] = flc_acuity(dist, half_diag, tan_diag, s_.imp);  // position vs. the fovea only
    }
    const uint64_t fseed = splitmix64(s_.seed ^ splitmix64(uint64_t(ctx.frame) + 0xf1ull));
    const CullResult kept = flc_cull(imp, s_.vpl_budget, s_.culling_floor, fseed);
    selected_ = make_soa(fv.vpls, kept.kept, kept.weight);
    c.set(Counter::vpls_total, double(n));
    c.set(Counter::vpls_kept, double(kept.kept.size()));
    c.set(Counter::contribution_evals, double(n));  // one importance per VPL
    c.set(Counter::visibility_rays, double(rays));
  }

 private:
  FirSettings s_;
  VplSoA selected_;
};

const ParamTable<FirSettings>& fir_table() {
  using S = FirSettings;
  static const auto t =
      ParamTable<S>()
          .integer("vpl_budget", 1024, Range::closed(0, 1e6), &S::vpl_budget)
          .doc("FLC §7", "VPLs kept for shading")
          .number(
              "omega_p", 0.2, Range::closed(0, 1), [](auto& s) -> auto& { return s.imp.omega_p; })
          .doc("FLC eq. 3", "acuity floor")
          .number(
              "acuity_slope", 2.25, Range::closed(0, 1e3),
              [](auto& s) -> auto& { return s.imp.slope; })
          .doc("FLC eq. 4", "acuity slope s (1/rad)")
          .number(
              "fovea_frac", 150.0 / (512.0 * std::sqrt(2.0)), Range::above(0, 10),
              [](auto& s) -> auto& { return s.imp.fovea_frac; })
          .doc("FLC eq. 5", "foveal radius / half diagonal (150 px at 1024x1024)")
          .number("culling_floor", 0.02, Range::closed(0, 1), &S::culling_floor)
          .doc("FLC §5", "uniform share of culling probabilities")
          .integer("seed", 1, Range::closed(0, 2e9), &S::seed)
          .doc("", "random seed");
  return t;
}

}  // namespace

std::unique_ptr<LightingStrategy> create_lighting_fir(Params& p) {
  return std::make_unique<FirLighting>(fir_table().read(p));
}

const std::vector<ParamInfo>& lighting_fir_params() {
  return fir_table().info();
}

}  // namespace fovsim
