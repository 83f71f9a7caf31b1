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

// Hyperbolic (Guenter et al. 2012 as set up in Ye et al. 2022 §5.1): layer i covers the
// screen-aligned square of half-side R_i around the gaze (R_i = pixel radius of eccentricity r_i,
// clipped to the screen; the outer layer is the whole screen) at pixel size s_i.
struct HyperLayer {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // screen rectangle (pixels)
  double s = 1;                           // pixel size, simulated pixels
  double ds = 1;                          // pixel size, display pixels (s1, s2, s3)
  double weight = 1;                      // display samples per layer pixel: (s / ds)^2
  int w = 0, h = 0;                       // layer buffer size = ceil(extent / s)
  double ecc_limit = 1e9;                 // eccentricity (deg) up to which the layer is used
};

// hyperbolic's parameters and sampling geometry (density, samples, iso-budget free parameter);
// the keys are the table params_table() at the end of this file.
struct HyperbolicGeometry final : GeometryOf<HyperbolicGeometry>, RadialThresholds {
  static constexpr const char* kMethod = method_id::hyperbolic;
  // Defaults: params_table() (read_mapping_spec sets them).
  double s1 = 0, s2 = 0, s3 = 0;  // layer pixel sizes
  double blend_deg = 0;           // width of the smoothstep blend inside each layer edge

  static const ParamTable<MappingSpec>& params_table();
  double density(const MappingView& v, double x, double y) const override;
  void density_image(const MappingView& v, Image& d) const override;
  double expected_samples(const MappingView& v) const override;
  bool shades_whole_buffer() const override { return false; }
  FreeParam free_param() const override { return {"radius_scale", 1e-4, 1e3, nullptr}; }
  double& free_ref() override { return radius_scale; }
  void widen_keys(double k, Json& p) const override { widen_radius_keys(k, p); }
};

// Blend weight of an inner layer at eccentricity e: 1 inside limit - band, smoothstep to 0 at
// the limit (Guenter's blend between layers).
inline float hyper_weight(double e, double limit, double band) {
  if (e >= limit) return 0.f;
  if (band <= 0 || e <= limit - band) return 1.f;
  const double t = (limit - e) / band;
  return float(t * t * (3 - 2 * t));
}

// The three layers for this view (pixel sizes s1, s2, s3; inner radii r1, r2 scaled).
// Scale invariance (docs/fidelity.md "Scale invariance of the methods"): s1, s2, s3 are display
// pixels (Ye et al. 2022 §5.1's 1, 2, 12.35 at the display's resolution); at render.scale k a
// layer pixel is max(1, k s_i) simulated pixels, and each counts for (max(1, k s_i) / s_i)^2
// display samples in units of a simulated pixel (HyperLayer::weight), so shaded_samples stays the
// display's count. A layer below one simulated pixel is held at one (*below_pixel).
std::vector<HyperLayer> hyperbolic_layers(const HyperbolicGeometry& s, const MappingView& v,
                                          bool* below_pixel = nullptr) {
  std::vector<HyperLayer> out;
  const double max_px = 4.0 * (v.W + v.H) + std::abs(v.gaze_px.x) + std::abs(v.gaze_px.y);
  auto ecc = [&](double x, double y) { return v.ecc_deg(x, y); };
  const double radii[2] = {s.r1_eff(), s.r2_eff()};
  const double sizes[3] = {s.s1, s.s2, s.s3};
  for (int i = 0; i < 3; ++i) {
    HyperLayer L;
    L.ds = sizes[i];
    L.s = sizes[i] * v.render_scale;
    if (L.s < 1.0) {
      if (below_pixel && i > 0) *below_pixel = true;  // s1 = 1: the simulation's own pixel
      L.s = 1.0;
    }
    L.weight = v.render_scale == 1.0 ? 1.0 : (L.s / L.ds) * (L.s / L.ds);
    if (i < 2) {
      const double R = radius_px_for_deg(ecc, v.gaze_px, radii[i], max_px);
      // Snap to whole pixels so an s = 1 layer samples pixel centres exactly.
      L.x0 = std::max(0.0, std::floor(v.gaze_px.x - R));
      L.y0 = std::max(0.0, std::floor(v.gaze_px.y - R));
      L.x1 = std::min(double(v.W), std::ceil(v.gaze_px.x + R));
      L.y1 = std::min(double(v.H), std::ceil(v.gaze_px.y + R));
      L.ecc_limit = radii[i];
    } else {
      L.x0 = 0, L.y0 = 0, L.x1 = v.W, L.y1 = v.H;
      L.ecc_limit = 1e9;
    }
    if (L.x1 > L.x0 && L.y1 > L.y0 && (i == 2 || L.ecc_limit > 0)) {
      L.w = std::max(1, int(std::ceil((L.x1 - L.x0) / L.s - 1e-9)));
      L.h = std::max(1, int(std::ceil((L.y1 - L.y0) / L.s - 1e-9)));
    }
    out.push_back(L);
  }
  return out;
}

// Effective weights (inner, middle, outer) of the three layers at screen pixel centre (px, py)
// with eccentricity e; they sum to 1.
void hyper_effective_weights(const HyperbolicGeometry& s, const std::vector<HyperLayer>& layers,
                             double px, double py, double e, float eff[3]) {
  float rem = 1.f;
  for (int i = 0; i < 3; ++i) {
    const HyperLayer& L = layers[size_t(i)];
    float w = 0.f;
    if (L.w > 0 && px >= L.x0 && px < L.x1 && py >= L.y0 && py < L.y1)
      w = i == 2 ? 1.f : hyper_weight(e, L.ecc_limit, std::min(s.blend_deg, L.ecc_limit));
    if (i == 2) w = 1.f;  // the outer layer covers the screen
    eff[i] = rem * w;
    rem *= 1.f - w;
  }
}

// Marks the layer pixels the composite reads (bilinear footprints of pixels with a non-zero
// effective weight): only those are shaded, like a stencil-masked layer pass, so hidden parts
// of coarser layers cost nothing. masks (optional) receives one w*h mask per layer.
// Returns the number of marked layer pixels.
double hyperbolic_needed(const HyperbolicGeometry& s, const MappingView& v,
                         const std::vector<HyperLayer>& layers, std::vector<uint8_t>* masks) {
  std::vector<uint8_t> local[3];
  std::vector<uint8_t>* m = masks ? masks : local;
  for (size_t i = 0; i < 3; ++i)
    m[i].assign(size_t(std::max(layers[i].w, 0)) * size_t(std::max(layers[i].h, 0)), 0);
  // Serial: footprints of neighbouring pixels overlap (no write races); ~W*H cheap steps.
  for (int y = 0; y < v.H; ++y)
    for (int x = 0; x < v.W; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double e =
          v.ecc ? double((*v.ecc)[size_t(y) * size_t(v.W) + size_t(x)]) : v.ecc_deg(px, py);
      float eff[3];
      hyper_effective_weights(s, layers, px, py, e, eff);
      for (size_t i = 0; i < 3; ++i) {
        const HyperLayer& L = layers[i];
        if (eff[i] <= 0.f || L.w <= 0) continue;
        // The bilinear taps of mapping.cpp's bilinear() at ((px - x0)/s, (py - y0)/s).
        const double fx = (px - L.x0) / L.s - 0.5, fy = (py - L.y0) / L.s - 0.5;
        const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            const int lx = std::clamp(x0 + dx, 0, L.w - 1), ly = std::clamp(y0 + dy, 0, L.h - 1);
            m[i][size_t(ly) * size_t(L.w) + size_t(lx)] = 1;
          }
      }
    }
  double n = 0;
  for (size_t i = 0; i < 3; ++i) {
    double k = 0;
    for (uint8_t b : m[i]) k += b;
    n += k * layers[i].weight;
  }
  return n;
}

class HyperbolicMethod final : public MappingMethod<HyperbolicGeometry> {
 public:
  using MappingMethod::MappingMethod;

  void render(const FrameContext& ctx, FrameOutput& out) override {
    const HyperbolicGeometry& s = frame_geometry(ctx, out);
    const GBuffer& gb = *ctx.gbuffer;
    const int W = gb.width, H = gb.height;
    const MappingView view = view_of(ctx);
    bool below_pixel = false;
    const auto layers = hyperbolic_layers(s, view, &below_pixel);
    if (below_pixel) out.flags.push_back("hyperbolic_layer_below_pixel");
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
      shade_buffer(ctx, GBufferRef(gb, index_[i].data(), L.w, L.h), col_[i], &needed_[i], out,
                   L.weight);
      alloc += double(L.w) * L.h * L.weight;
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

// The density of the finest layer that covers the point within its eccentricity limit.
double hyper_density_in(const HyperbolicGeometry& s, const std::vector<HyperLayer>& layers,
                        double x, double y, double e) {
  for (auto& L : layers)
    if (L.w > 0 && e < L.ecc_limit && x >= L.x0 && x < L.x1 && y >= L.y0 && y < L.y1)
      return 1.0 / (L.ds * L.ds);  // display samples per pixel (= weight / s^2)
  return 1.0 / (s.s3 * s.s3);
}

double HyperbolicGeometry::density(const MappingView& v, double x, double y) const {
  return hyper_density_in(*this, hyperbolic_layers(*this, v), x, y, v.ecc_deg(x, y));
}

// Layer geometry once, then per pixel (density() would rebuild it per call).
void HyperbolicGeometry::density_image(const MappingView& v, Image& d) const {
  const auto layers = hyperbolic_layers(*this, v);
  parallel_rows(v.H, [&](int y) {
    for (int x = 0; x < v.W; ++x) {
      double e = (*v.ecc)[size_t(y) * size_t(v.W) + size_t(x)], val = 1.0 / (s3 * s3);
      for (auto& L : layers)
        if (L.w > 0 && e < L.ecc_limit && x + 0.5 >= L.x0 && x + 0.5 < L.x1 && y + 0.5 >= L.y0 &&
            y + 0.5 < L.y1) {
          val = 1.0 / (L.ds * L.ds);
          break;
        }
      d.at(x, y)[0] = float(val);
    }
  });
}

double HyperbolicGeometry::expected_samples(const MappingView& v) const {
  return hyperbolic_needed(*this, v, hyperbolic_layers(*this, v), nullptr);
}

const ParamTable<MappingSpec>& HyperbolicGeometry::params_table() {
  using G = HyperbolicGeometry;
  static const ParamTable<MappingSpec> t = [] {
    ParamTable<MappingSpec> t;
    add_radius_rows<G>(t, "Ye et al. 2022 §5.1", "inner layer eccentricity (deg)",
                       "middle layer eccentricity (deg)");
    t.number("s1", 1.0, Range::closed(1, 1e4), field<G>(&G::s1))
        .doc("Ye et al. 2022 §5.1", "inner layer pixel size")
        .column()
        .number("s2", 2.0, Range::closed(1, 1e4), field<G>(&G::s2))
        .doc("Ye et al. 2022 §5.1", "middle layer pixel size")
        .column()
        .number("s3", 12.35, Range::closed(1, 1e4), field<G>(&G::s3))
        .doc("Ye et al. 2022 §5.1", "outer layer pixel size")
        .column()
        .number("blend_deg", 1.0, Range::closed(0, 90), field<G>(&G::blend_deg))
        .doc("Guenter 2012", "smoothstep blend band inside each layer edge (deg)");
    add_target_row(t, "radius_scale");
    return t;
  }();
  return t;
}

}  // namespace

std::unique_ptr<FoveationMethod> create_hyperbolic(Params& p) {
  return std::make_unique<HyperbolicMethod>(read_mapping_spec<HyperbolicGeometry>(p));
}

const std::vector<ParamInfo>& hyperbolic_params() {
  return HyperbolicGeometry::params_table().info();
}

const MethodCost& hyperbolic_cost() {
  return mapping_method_cost();
}

}  // namespace fovsim
