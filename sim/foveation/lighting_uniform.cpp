// `uniform` lighting strategy: a uniform random subset of the frame's VPLs, the same size as the
// foveated strategies' budget, each kept VPL weighted by N / kept (Horvitz-Thompson). It is the
// control for `flc` and `fir`: the same number of VPLs shaded, the same unbiased stochastic
// culling (Yang et al., "Foveated light culling" §5, with every importance equal), but no
// foveation. A row's difference to `flc` at the same `vpl_budget` is what the importance
// (eqs. 3-14) buys; its difference to `all_vpls` is what the budget costs.
//
// Parameters: lighting_uniform_params() at the end of this file.
#include "sim/core/hash.h"
#include "sim/core/param_table.h"
#include "sim/core/rng.h"
#include "sim/foveation/flc_contribution.h"
#include "sim/foveation/lighting.h"
#include "sim/foveation/method.h"

namespace fovsim {
namespace {

struct UniformSettings {
  int vpl_budget = 1024;
  uint64_t seed = 1;
};

class UniformLighting final : public LightingStrategy {
 public:
  explicit UniformLighting(const UniformSettings& s) : s_(s) {}
  std::string name() const override { return "uniform"; }
  std::vector<std::pair<std::string, double>> param_columns() const override {
    return {{"vpl_budget", s_.vpl_budget}};
  }
  const VplSoA& selected(const FrameContext&) const override { return selected_; }
  // No importance per VPL: the culling pass only.
  void analytic_selection_counters(Counters& c, double, double) const override {
    c.set(Counter::contribution_evals, 0.0);
  }
  void declare_passes(CostPasses& p) const override { p.frame_rsm = p.culling = true; }

  void begin_frame(const FrameContext& ctx, Counters& c) override {
    const FrameVpls& fv = *ctx.vpls;
    const size_t n = fv.vpls.size();
    const std::vector<double> equal(n, 1.0);
    // Every VPL equally likely: flc_cull keeps min(budget, n) of them, weight n / kept.
    const uint64_t fseed = splitmix64(s_.seed ^ splitmix64(uint64_t(ctx.frame) + 0x75ull));
    const CullResult kept = flc_cull(equal, s_.vpl_budget, 0.0, fseed);
    selected_ = make_soa(fv.vpls, kept.kept, kept.weight);
    c.set(Counter::vpls_total, double(n));
    c.set(Counter::vpls_kept, double(kept.kept.size()));
    c.set(Counter::contribution_evals, 0.0);
  }

 private:
  UniformSettings s_;
  VplSoA selected_;
};

const ParamTable<UniformSettings>& uniform_table() {
  using S = UniformSettings;
  static const auto t = ParamTable<S>()
                            .integer("vpl_budget", 1024, Range::closed(0, 1e6), &S::vpl_budget)
                            .doc("FLC §7", "VPLs kept for shading, chosen uniformly at random")
                            .integer("seed", 1, Range::closed(0, 2e9), &S::seed)
                            .doc("", "random seed");
  return t;
}

}  // namespace

std::unique_ptr<LightingStrategy> create_lighting_uniform(Params& p) {
  return std::make_unique<UniformLighting>(uniform_table().read(p));
}

const std::vector<ParamInfo>& lighting_uniform_params() {
  return uniform_table().info();
}

}  // namespace fovsim
