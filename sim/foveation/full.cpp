// `full`: full-resolution deferred shading, the reference pipeline (for cost).
//
// Parameters: the declaration full_params() at the end of this file (name, type, default,
// range, seed section, meaning); docs/methods.md and configs/README.md are generated from it.
#include "sim/foveation/methods.h"

namespace fovsim {
namespace {

class FullMethod final : public FoveationMethod {
 public:
  std::string name() const override { return "full"; }
  uint32_t required_channels() const override { return kShadingChannels; }
  void render(const FrameContext& ctx, FrameOutput& out) override {
    // At render.spp = 1 the shared reference *is* full-resolution shading: reuse it, no copy,
    // no second shade. A supersampled reference is not what `full` renders (one sample per
    // pixel): shade the pixel-centre G-buffer, so its difference to the reference is the
    // aliasing any 1-sample-per-pixel pipeline keeps (docs/metrics.md).
    const double n = double(ctx.gbuffer->size());
    if (ctx.renderer->settings().spp > 1) {
      Counters c;
      ctx.renderer->shade(*ctx.gbuffer, ctx.camera->position, out.image, nullptr, &c);
      for (auto& kv : c.items())
        if (kv.first != "shaded_samples") out.counters.add(kv.first, kv.second);
    } else {
      out.image_is_reference = true;
    }
    out.counters.set("shaded_samples", n);
    out.counters.set("gbuffer_samples", n);
    out.counters.set("fullres_pixels", n);
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
