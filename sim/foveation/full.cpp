// `full`: full-resolution deferred shading, the reference pipeline (for cost). At render.spp 1
// with the default lighting (all_vpls, the FLC paper's TBDS) it *is* the shared reference;
// otherwise it is one sample per pixel centre (the shared 1-spp direct light) plus its
// strategy's VPLs at every pixel, so its difference to a supersampled reference is the
// aliasing any 1-sample-per-pixel pipeline keeps (docs/metrics.md).
//
// Parameters: the declaration full_params() at the end of this file (name, type, default,
// range, seed section, meaning); docs/methods.md and configs/README.md are generated from it.
#include <algorithm>

#include "sim/core/param_table.h"
#include "sim/foveation/methods.h"

namespace fovsim {
namespace {

struct FullParams {
  TaaSettings taa;
};

// Its keys: the TAA post pass only (off; `full` as the foveation-loss reference of a method
// with TAA is made with that method's settings, docs/metrics.md "Foveation loss").
const ParamTable<FullParams>& full_table() {
  static const ParamTable<FullParams> t = [] {
    ParamTable<FullParams> t;
    add_taa_rows(
        t, [](auto& s) -> auto& { return s.taa; },
        TaaDefaults{false, 0.1, "box3", false, "", false});
    return t;
  }();
  return t;
}

class FullMethod final : public FoveationMethod {
 public:
  explicit FullMethod(const FullParams& p) : p_(p) {}
  std::string name() const override { return method_id::full; }
  TaaSettings taa() const override { return p_.taa; }
  uint32_t required_channels() const override { return kShadingChannels; }
  // Every pixel is shaded (its declaration: full_resolution).
  void analytic_counters(const AnalyticFrame& f, Counters& c) const override {
    c.set(Counter::shaded_samples, f.pixels);
    c.set(Counter::gbuffer_samples, f.pixels);
  }
  void render(const FrameContext& ctx, FrameOutput& out) override {
    const double n = double(ctx.gbuffer->size());
    out.counters.set(Counter::shaded_samples, n);
    out.counters.set(Counter::gbuffer_samples, n);
    out.counters.set(Counter::fullres_pixels, n);
    const bool all = !ctx.lighting || !ctx.vpls || ctx.lighting->uses_all_vpls();
    if (all && ctx.renderer->settings().spp <= 1) {
      // The shared reference *is* full-resolution shading: reuse it, no copy, no second shade.
      out.image_is_reference = true;
      if (ctx.vpls) {
        double hits = 0;
        for (size_t i = 0; i < ctx.gbuffer->size(); ++i) hits += ctx.gbuffer->hit(i) ? 1 : 0;
        out.counters.set(Counter::shaded_sample_vpls, hits * double(ctx.vpls->vpls.size()));
      }
      return;
    }
    out.image.resize(ctx.direct->width, ctx.direct->height, 3);
    std::copy(ctx.direct->data.begin(), ctx.direct->data.end(), out.image.data.begin());
    if (ctx.vpls && ctx.lighting)
      ctx.lighting->shade(ctx, *ctx.gbuffer, nullptr, out.image, out.counters);
  }

 private:
  FullParams p_;
};

}  // namespace

std::unique_ptr<FoveationMethod> create_full(Params& p) {
  return std::make_unique<FullMethod>(full_table().read(p));
}
const std::vector<ParamInfo>& full_params() {
  return full_table().info();
}

// Deferred shading of every pixel: the unfoveated pipeline the others are compared with.
const MethodCost& full_cost() {
  static const MethodCost m = [] {
    MethodCost d;
    d.passes.full_resolution = true;
    return d;
  }();
  return m;
}

}  // namespace fovsim
