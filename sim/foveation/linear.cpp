// `linear`: Weier et al. 2016 linear fall-off with Ye et al. 2022 §5.1's parameters. Each pixel is
// shaded with probability p(e): 1 inside r1, falling linearly to p_min at r2, p_min beyond
// (stochastic sampling as in Weier's ray tracer; per-pixel hash of (seed, frame, pixel), so the
// pattern is the same at any thread count and changes every frame). Unshaded pixels are
// reconstructed from the shaded ones by push-pull interpolation (Gortler et al. 1996, the
// sparse-sample fill Ye et al. 2022 §2 names for this family).
//
// Parameters: the declaration linear_params() at the end of this file (name, type, default,
// range, seed section, meaning); docs/methods.md and configs/README.md are generated from it.
// p(e) is per display pixel, applied at render.scale (sim_probability below).
#include <cmath>

#include "sim/core/param_table.h"
#include "sim/foveation/mapping_method.h"
#include "sim/foveation/methods.h"

namespace fovsim {
namespace {

// linear's parameters and sampling geometry (density, samples, iso-budget free parameter); the
// keys are the table params_table() at the end of this file.
struct LinearGeometry final : GeometryOf<LinearGeometry>, RadialThresholds {
  static constexpr const char* kMethod = method_id::linear;
  double p_min = 0;   // minimum sampling probability (default: params_table())
  uint64_t seed = 0;  // stochastic sample pattern

  static const ParamTable<MappingSpec>& params_table();
  double density(const MappingView& v, double x, double y) const override;
  double expected_samples(const MappingView& v) const override;
  bool shades_whole_buffer() const override { return false; }
  FreeParam free_param() const override { return {"radius_scale", 1e-4, 1e3, nullptr}; }
  double& free_ref() override { return radius_scale; }
  void widen_keys(double k, Json& p) const override { widen_radius_keys(k, p); }
};

// Linear fall-off (Weier et al. 2016, Ye et al. 2022 §5.1): sampling probability 1 inside r1,
// falling linearly to p_min at r2, p_min beyond.
double linear_probability(const LinearGeometry& s, double e) {
  const double r1 = s.r1_eff(), r2 = s.r2_eff();
  if (!(e > r1)) return 1.0;
  if (!(e < r2)) return s.p_min;
  return 1.0 - (1.0 - s.p_min) * (e - r1) / (r2 - r1);
}

// Scale invariance (docs/fidelity.md "Scale invariance of the methods"): p(e) is a probability
// per display pixel (Weier et al. 2016). A simulated pixel at render.scale s covers 1 / s^2
// display pixels, so it holds a sample with q = 1 - (1 - p)^(1 / s^2), and a sampled simulated
// pixel stands for p / q display samples in units of a simulated pixel (E = p per pixel: the
// expected count stays the display's, expected_samples). p itself at s = 1.
double sim_probability(double p, double s) {
  if (s == 1.0 || !(p < 1.0)) return p;
  return 1.0 - std::pow(1.0 - p, 1.0 / (s * s));
}

class LinearMethod final : public MappingMethod<LinearGeometry> {
 public:
  using MappingMethod::MappingMethod;

  void render(const FrameContext& ctx, FrameOutput& out) override {
    const LinearGeometry& s = frame_geometry(ctx, out);
    const GBuffer& gb = *ctx.gbuffer;
    const int W = gb.width, H = gb.height;
    const std::vector<float>& ecc = *ctx.eccentricity;
    const double scale = ctx.render_scale;
    mask_.assign(gb.size(), 0);
    std::vector<double> weighted_rows(size_t(H), 0.0);
    parallel_rows(H, [&](int y) {
      double wsum = 0;
      for (int x = 0; x < W; ++x) {
        const size_t i = size_t(y) * size_t(W) + size_t(x);
        const double p = linear_probability(s, ecc[i]), q = sim_probability(p, scale);
        mask_[i] = hash01(s.seed, uint64_t(ctx.frame), i) < q ? 1 : 0;
        if (mask_[i]) wsum += p / q;
      }
      weighted_rows[size_t(y)] = wsum;
    });
    double weighted = 0;
    for (double v : weighted_rows) weighted += v;
    size_t n_mask = 0;
    for (uint8_t b : mask_) n_mask += b;
    double shaded = shade_buffer(ctx, gb, out.image, &mask_, out,
                                 scale != 1.0 && n_mask > 0 ? weighted / double(n_mask) : 1.0);
    if (scale != 1.0) shaded = weighted;  // display samples (sim_probability)
    if (out.image.width != W || out.image.height != H) out.image.resize(W, H, 3);
    if (ctx.want_debug) {
      Image m(W, H, 1);
      for (size_t i = 0; i < mask_.size(); ++i) m.data[i] = mask_[i];
      out.debug.emplace_back("sample_mask", std::move(m));
    }
    const double taps = push_pull_fill(out.image, mask_);
    set_counters(out, shaded, shaded, double(W) * H, shaded, double(W) * H, taps);
    if (ctx.want_debug) debug_density(ctx, s, out);
  }

 private:
  std::vector<uint8_t> mask_;
};

double LinearGeometry::density(const MappingView& v, double x, double y) const {
  return linear_probability(*this, v.ecc_deg(x, y));
}

// Expected samples: the sum of p(e) over the pixels.
double LinearGeometry::expected_samples(const MappingView& v) const {
  return sum_rows(v.H, [&](int y) {
    double n = 0;
    for (int x = 0; x < v.W; ++x) {
      double e = v.ecc ? double((*v.ecc)[size_t(y) * size_t(v.W) + size_t(x)])
                       : v.ecc_deg(x + 0.5, y + 0.5);
      n += linear_probability(*this, e);
    }
    return n;
  });
}

const ParamTable<MappingSpec>& LinearGeometry::params_table() {
  using G = LinearGeometry;
  static const ParamTable<MappingSpec> t = [] {
    ParamTable<MappingSpec> t;
    add_radius_rows<G>(t, "Ye et al. 2022 §5.1", "full-rate region (deg)",
                       "end of the linear fall-off (deg)");
    t.number("p_min", 0.047, Range::above(0, 1), field<G>(&G::p_min))
        .doc("Ye et al. 2022 §5.1", "minimum sampling probability")
        .column()
        .integer("seed", 0, Range::closed(0, 2147483647), field<G>(&G::seed))
        .doc("", "stochastic sample pattern seed")
        .shown("0", "[0, 2^31)");
    add_target_row(t, "radius_scale");
    return t;
  }();
  return t;
}

}  // namespace

std::unique_ptr<FoveationMethod> create_linear(Params& p) {
  return std::make_unique<LinearMethod>(read_mapping_spec<LinearGeometry>(p));
}

const std::vector<ParamInfo>& linear_params() {
  return LinearGeometry::params_table().info();
}

const MethodCost& linear_cost() {
  return mapping_method_cost();
}

}  // namespace fovsim
