// `hyperbolic`: Guenter et al. 2012 three-layer foveation with Ye et al. 2022 §5.1's parameters.
// Inner and middle layers are screen-aligned squares around the gaze whose half-side is the
// pixel radius of eccentricity r1 / r2 (largest of the four axis directions, through the real
// projection), the outer layer is the whole screen. Each layer is a G-buffer gathered at its
// pixel size s_i (nearest full-res sample at the layer pixel centre), bilinearly upsampled and
// blended with a smoothstep over the last blend_deg degrees inside each layer's eccentricity
// limit. Only the layer pixels the composite reads are shaded (a stencil-masked layer pass):
// Guenter shades whole layers, i.e. the fovea three times (Ye et al. 2022 §2); masking keeps
// shaded_samples <= W H and charges only visible work.
//
// Parameters: the declaration hyperbolic_params() at the end of this file (name, type, default,
// range, seed section, meaning); docs/methods.md and configs/README.md are generated from it.
#include <algorithm>
#include <cmath>

#include "sim/foveation/mapping_method.h"
#include "sim/foveation/methods.h"

namespace fovsim {
namespace {

class HyperbolicMethod final : public MappingMethodBase {
 public:
  using MappingMethodBase::MappingMethodBase;

  void render(const FrameContext& ctx, FrameOutput& out) override {
    const MappingSpec& s = resolve(ctx, out);
    const GBuffer& gb = *ctx.gbuffer;
    const int W = gb.width, H = gb.height;
    const MappingView view = view_of(ctx);
    const auto layers = hyperbolic_layers(s, view);
    const double shaded = hyperbolic_needed(s, view, layers, needed_);
    double alloc = 0;
    for (size_t i = 0; i < 3; ++i) {
      const HyperLayer& L = layers[i];
      if (L.w <= 0) continue;
      // Layer pixel centres, kept inside the layer rectangle for a partial last row/column.
      auto inv = [&](double a, double b) {
        return glm::dvec2(std::min(L.x0 + a * L.s, L.x1 - 1e-3),
                          std::min(L.y0 + b * L.s, L.y1 - 1e-3));
      };
      gather_gbuffer(gb, L.w, L.h, inv, index_[i], used_[i]);  // layer = index into gb
      // Only the pixels the composite reads.
      shade_buffer(ctx, GBufferRef(gb, index_[i].data(), L.w, L.h), col_[i], &needed_[i], out);
      alloc += double(L.w) * L.h;
    }

    out.image.resize(W, H, 3);
    std::vector<double> row_taps(size_t(H), 0.0);
    parallel_rows(H, [&](int y) {
      double taps = 0;
      for (int x = 0; x < W; ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double e = (*view.ecc)[size_t(y) * size_t(W) + size_t(x)];
        float eff[3];
        hyper_effective_weights(s, layers, px, py, e, eff);
        glm::vec3 c(0.f);
        for (size_t i = 0; i < 3; ++i) {
          if (eff[i] <= 0.f) continue;
          const HyperLayer& L = layers[i];
          c += eff[i] * bilinear(col_[i], (px - L.x0) / L.s, (py - L.y0) / L.s, false);
          taps += 4;
        }
        float* o = out.image.at(x, y);
        o[0] = c.x;
        o[1] = c.y;
        o[2] = c.z;
      }
      row_taps[size_t(y)] = taps;
    });
    double taps = 0;
    for (double t : row_taps) taps += t;
    set_counters(out, shaded, shaded, alloc, shaded, double(W) * H, taps);
    if (ctx.want_debug) {
      const char* names[3] = {"layer_inner", "layer_middle", "layer_outer"};
      for (size_t i = 0; i < 3; ++i)
        if (layers[i].w > 0) out.debug.emplace_back(names[i], col_[i]);
      debug_density(ctx, s, out);
    }
  }

 private:
  std::vector<uint32_t> index_[3];  // layer G-buffers: G-buffer sample per layer pixel
  Image col_[3];
  std::vector<uint8_t> used_[3], needed_[3];
};

}  // namespace

std::unique_ptr<FoveationMethod> create_hyperbolic(Params& p) {
  return std::make_unique<HyperbolicMethod>(MappingSpec::from_params("hyperbolic", p));
}

const std::vector<ParamInfo>& hyperbolic_params() {
  static const std::vector<ParamInfo> t = {
      {"r1", "number", "10", "[0, 180]", "Ye et al. 2022 §5.1", "inner layer eccentricity (deg)"},
      {"r2", "number", "20", "[r1, 180]", "Ye et al. 2022 §5.1", "middle layer eccentricity (deg)"},
      {"s1", "number", "1", "[1, 1e4]", "Ye et al. 2022 §5.1", "inner layer pixel size"},
      {"s2", "number", "2", "[1, 1e4]", "Ye et al. 2022 §5.1", "middle layer pixel size"},
      {"s3", "number", "12.35", "[1, 1e4]", "Ye et al. 2022 §5.1", "outer layer pixel size"},
      {"blend_deg", "number", "1", "[0, 90]", "Guenter 2012",
       "smoothstep blend band inside each layer edge (deg)"},
      {"radius_scale", "number", "1", "(0, inf)", "iso-budget", "multiplies r1 and r2"},
      {"target_shaded_fraction", "number", "none", "(0, 1]", "Ye et al. 2022 §5.1",
       "iso-budget: solve radius_scale"},
  };
  return t;
}

}  // namespace fovsim
