// `full`: full-resolution deferred shading, the reference pipeline (for cost). With the
// default lighting (all_vpls, the FLC paper's TBDS) it *is* the shared reference; with another
// strategy it shades the strategy's VPLs at every pixel on top of the shared direct light.
//
// Parameters: the declaration full_params() at the end of this file (name, type, default,
// range, seed section, meaning); docs/methods.md and configs/README.md are generated from it.
#include <algorithm>

#include "sim/foveation/methods.h"

namespace fovsim {
namespace {

class FullMethod final : public FoveationMethod {
 public:
  std::string name() const override { return "full"; }
  uint32_t required_channels() const override { return kShadingChannels; }
  void render(const FrameContext& ctx, FrameOutput& out) override {
    const double n = double(ctx.gbuffer->size());
    out.counters.set("shaded_samples", n);
    out.counters.set("gbuffer_samples", n);
    out.counters.set("fullres_pixels", n);
    if (!ctx.lighting || !ctx.vpls || ctx.lighting->uses_all_vpls()) {
      // The shared reference *is* full-resolution shading: reuse it, no copy, no second shade.
      out.image_is_reference = true;
      if (ctx.vpls) {
        double hits = 0;
        for (size_t i = 0; i < ctx.gbuffer->size(); ++i) hits += ctx.gbuffer->hit(i) ? 1 : 0;
        out.counters.set("shaded_sample_vpls", hits * double(ctx.vpls->vpls.size()));
      }
      return;
    }
    out.image.resize(ctx.direct->width, ctx.direct->height, 3);
    std::copy(ctx.direct->data.begin(), ctx.direct->data.end(), out.image.data.begin());
    ctx.lighting->shade(ctx, *ctx.gbuffer, nullptr, out.image, out.counters);
  }
};

}  // namespace

std::unique_ptr<FoveationMethod> create_full(Params&) {
  return std::make_unique<FullMethod>();
}
const std::vector<ParamInfo>& full_params() {
  static const std::vector<ParamInfo> t;
  return t;
}

}  // namespace fovsim
