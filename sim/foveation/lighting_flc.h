// The `flc` lighting strategy (Yang et al., "Foveated light culling", §4-§5): importance map
// (eqs. 3-9), quasi-MH shading points (Alg. 1), VPL contributions with BLSO visibility
// (eqs. 10-14) and stochastic culling to `vpl_budget`. Used by any method through
// {"lighting": {"method": "flc", ...}} and by the `flc` method (full sampling + this strategy,
// with the paper's own log-polar / interleaved shading, §6).
#pragma once
#include <algorithm>
#include <vector>

#include "sim/core/param_info.h"
#include "sim/foveation/flc_contribution.h"
#include "sim/foveation/flc_importance.h"
#include "sim/foveation/lighting.h"

namespace fovsim {

struct FlcLightingSettings {
  int vpl_budget = 1024, samples = 256, chain_length = 16;
  FlcImportanceParams imp;
  double history_blend = 0.5, w_fovea = 1.0, w_periphery = 1.0, epsilon = 0.02;
  FlcVisibility visibility = FlcVisibility::Blso;
  BlsoParams blso;
  double culling_floor = 0.02;
  uint64_t seed = 1;
  // Reads every key of flc_lighting_params() from p.
  static FlcLightingSettings from_params(Params& p);
};
// The parameter declaration of the flc strategy (also part of the `flc` method's).
const ParamTable<FlcLightingSettings>& flc_lighting_table();
const std::vector<ParamInfo>& flc_lighting_params();

// Wall-clock ms of the strategy's stages in the last begin_frame (benchmarks; not in results).
struct FlcLightingTimes {
  double importance = 0, sampling = 0, contribution = 0, culling = 0;
};

class FlcLighting final : public LightingStrategy {
 public:
  explicit FlcLighting(const FlcLightingSettings& s) : s_(s) {}
  std::string name() const override { return "flc"; }
  bool temporal() const override { return true; }
  void reset() override { history_ = Image(); }
  void begin_frame(const FrameContext& ctx, Counters& c) override;
  const VplSoA& selected(const FrameContext&) const override { return selected_; }
  void end_frame(const FrameContext& ctx, const Image& linear) override;
  std::vector<std::pair<std::string, double>> param_columns() const override;
  // eq. 14 for every VPL and importance sample.
  void analytic_selection_counters(Counters& c, double vpls,
                                   double importance_samples) const override {
    c.set(Counter::importance_samples, importance_samples);
    c.set(Counter::contribution_evals, vpls * importance_samples);
    // eq. 11: two local-space estimates of N' lookups each per pair (every pair: a warp pays
    // for the pairs eq. 14's cosines reject when any of its lanes needs the lookups).
    c.set(Counter::blso_lookups,
          s_.visibility == FlcVisibility::Blso
              ? vpls * importance_samples * 2.0 * std::max(1, s_.blso.samples)
              : 0.0);
  }
  // Importance map + sampling (eqs. 3-9, Alg. 1), eq. 14 contributions and culling.
  void declare_passes(CostPasses& p) const override {
    p.frame_rsm = p.importance = p.culling = true;
  }
  void debug_images(std::vector<std::pair<std::string, Image>>& out) override;

  const FlcLightingSettings& settings() const { return s_; }
  const CullResult& kept() const { return kept_; }
  const FlcLightingTimes& times() const { return times_; }
  // eq. 8 history from an indirect-only image (linear RGB).
  void set_history(const FrameContext& ctx, const Image& indirect);

 private:
  FlcLightingSettings s_;
  Image history_;              // eq. 8 b(p), 1 channel
  Image color_, ind_, ind_d_;  // scratch, reused every frame
  FlcImportanceMaps maps_;
  CullResult kept_;
  VplSoA selected_;
  FlcLightingTimes times_;
  bool keep_debug_ = false;
};

}  // namespace fovsim
