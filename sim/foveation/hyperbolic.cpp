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

#include "sim/core/param_table.h"
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

// The geometry (density, samples, iso-budget free parameter) and the keys of hyperbolic.
double hyper_density_in(const MappingSpec& s, const std::vector<HyperLayer>& layers, double x,
                        double y, double e) {
  // The finest layer that covers the point within its eccentricity limit.
  for (auto& L : layers)
    if (L.w > 0 && e < L.ecc_limit && x >= L.x0 && x < L.x1 && y >= L.y0 && y < L.y1)
      return 1.0 / (L.s * L.s);
  return 1.0 / (s.s3 * s.s3);
}

double hyper_density(const MappingSpec& s, const MappingView& v, double x, double y) {
  return hyper_density_in(s, hyperbolic_layers(s, v), x, y, v.ecc_deg(x, y));
}

// Layer geometry once, then per pixel (hyper_density would rebuild it per call).
void hyper_density_image(const MappingSpec& s, const MappingView& v, Image& d) {
  const auto layers = hyperbolic_layers(s, v);
  parallel_rows(v.H, [&](int y) {
    for (int x = 0; x < v.W; ++x) {
      double e = (*v.ecc)[size_t(y) * size_t(v.W) + size_t(x)], val = 1.0 / (s.s3 * s.s3);
      for (auto& L : layers)
        if (L.w > 0 && e < L.ecc_limit && x + 0.5 >= L.x0 && x + 0.5 < L.x1 && y + 0.5 >= L.y0 &&
            y + 0.5 < L.y1) {
          val = 1.0 / (L.s * L.s);
          break;
        }
      d.at(x, y)[0] = float(val);
    }
  });
}

double hyper_samples(const MappingSpec& s, const MappingView& v) {
  return hyperbolic_needed(s, v, hyperbolic_layers(s, v), nullptr);
}

const ParamTable<MappingSpec>& hyperbolic_table() {
  using S = MappingSpec;
  static const ParamTable<S> t = [] {
    ParamTable<S> t;
    add_radius_rows(t, "Ye et al. 2022 §5.1", "inner layer eccentricity (deg)",
                    "middle layer eccentricity (deg)");
    t.number("s1", 1.0, Range::closed(1, 1e4), &S::s1)
        .doc("Ye et al. 2022 §5.1", "inner layer pixel size")
        .column()
        .number("s2", 2.0, Range::closed(1, 1e4), &S::s2)
        .doc("Ye et al. 2022 §5.1", "middle layer pixel size")
        .column()
        .number("s3", 12.35, Range::closed(1, 1e4), &S::s3)
        .doc("Ye et al. 2022 §5.1", "outer layer pixel size")
        .column()
        .number("blend_deg", 1.0, Range::closed(0, 90), &S::blend_deg)
        .doc("Guenter 2012", "smoothstep blend band inside each layer edge (deg)");
    add_target_row(t, "radius_scale");
    return t;
  }();
  return t;
}

const SamplingGeometry kHyperbolicGeometry = {"hyperbolic",
                                              hyperbolic_table,
                                              hyper_density,
                                              hyper_density_image,
                                              hyper_samples,
                                              /*shades_whole_buffer=*/false,
                                              &MappingSpec::radius_scale,
                                              1e-4,
                                              1e3,
                                              nullptr};

}  // namespace

std::unique_ptr<FoveationMethod> create_hyperbolic(Params& p) {
  return std::make_unique<HyperbolicMethod>(read_mapping_spec(kHyperbolicGeometry, p));
}

const std::vector<ParamInfo>& hyperbolic_params() {
  return hyperbolic_table().info();
}

}  // namespace fovsim
