// `rmfr`: Rectangular Mapping-based Foveated Rendering (Ye et al. 2022 §3.2).
// Pass 1: every RS-buffer pixel of the (W/sigma) x (H/sigma) buffer takes the nearest G-buffer
// sample at its inverse-mapped screen point (eqs. 6-7, all four quadrants: the normalisation
// of eq. 5 uses W - x^ right of the gaze and x^ left of it, likewise in y); the TG-buffer is
// shaded in full (RMFR uses the whole buffer, §3.3.3). Pass 2: each screen pixel maps forward
// (eqs. 4-5) and reads the RS-buffer bilinearly. A gaze off the screen is clamped to the
// nearest edge (eq. 5 needs 0 <= x^ <= W). Table 3's TAA: the shared pass of taa.h with Halton
// jitter of the RS-buffer's samples (rows taa*, on by default).
//
// Parameters: the declaration rmfr_params() at the end of this file (name, type, default,
// range, seed section, meaning); docs/methods.md and configs/README.md are generated from it.
#include <algorithm>
#include <cmath>

#include "sim/core/param_table.h"
#include "sim/foveation/mapping_method.h"
#include "sim/foveation/methods.h"

namespace fovsim {
namespace {

// rmfr's parameters and sampling geometry (density, samples, iso-budget free parameter, widening);
// the keys are the table params_table() at the end of this file.
struct RmfrGeometry final : GeometryOf<RmfrGeometry> {
  static constexpr const char* kMethod = method_id::rmfr;
  // Defaults: params_table() (read_mapping_spec sets them).
  double sigma = 0;             // W / w (= H / h)
  double fx = 0, fy = 0;        // as fractions of W / H ...
  double fx_px = 0, fy_px = 0;  // ... or in pixels when > 0 (keys fx_px / fy_px)
  double fx_pixels(int W) const { return fx_px > 0 ? fx_px : fx * W; }
  double fy_pixels(int H) const { return fy_px > 0 ? fy_px : fy * H; }

  static const ParamTable<MappingSpec>& params_table();
  double density(const MappingView& v, double x, double y) const override;
  // The whole RS-buffer is shaded (§3.3.3).
  double expected_samples(const MappingView& v) const override {
    return double(reduced_size(v.W, sigma)) * reduced_size(v.H, sigma);
  }
  bool shades_whole_buffer() const override { return true; }
  double buffer_reduction() const override { return sigma; }
  // The RS-buffer shades (W / sigma) x (H / sigma) samples (§3.2): sigma is the budget knob.
  BudgetKnob budget_knob() const override { return coarser_buffer_knob("sigma", sigma); }
  FreeParam free_param() const override { return {"sigma", 1.0, 1e4, sigma_for}; }
  double& free_ref() override { return sigma; }
  // Under tracking loss the RS-buffer grows by k per axis, sigma' = max(1, sigma / k) (§3.2:
  // every sampling rate of the map scales with 1 / sigma), and the foveal extents grow,
  // f' = k f (eq. 4: as f grows the map tends to the uniform 1 / sigma).
  void widen(double k) override {
    sigma = widened_sigma(sigma, k);
    fx *= k;
    fy *= k;
    fx_px *= k;  // 0 (unset) stays 0
    fy_px *= k;
  }
  void widen_keys(double k, Json& p) const override {
    RmfrGeometry g = *this;
    g.widen(k);
    p["sigma"] = g.sigma;
    if (fx_px > 0)  // the form given (fx_px or fx) is the one widened
      p["fx_px"] = g.fx_px;
    else
      p["fx"] = g.fx;
    if (fy_px > 0)
      p["fy_px"] = g.fy_px;
    else
      p["fy"] = g.fy;
  }
  // S = sigma^2 (§3.2): sigma = 1 / sqrt(target), at least 1.
  static bool sigma_for(double target, double* s) {
    *s = std::max(1.0, 1.0 / std::sqrt(target));
    return target <= 1.0;
  }
};

class RmfrMethod final : public MappingMethod<RmfrGeometry> {
 public:
  using MappingMethod::MappingMethod;

  void render(const FrameContext& ctx, FrameOutput& out) override {
    // Tracking loss under trace.on_invalid = widen: a larger buffer (RmfrGeometry::widen).
    const RmfrGeometry& s = frame_geometry(ctx, out);
    const GBuffer& gb = *ctx.gbuffer;
    const int W = gb.width, H = gb.height;
    const int w = reduced_size(W, s.sigma), h = reduced_size(H, s.sigma);
    const RectMap map = RectMap::make(W, H, w, h, ctx.gaze_px, s.fx_pixels(W), s.fy_pixels(H));

    // Rectangular mapping of the G-buffer into the TG-buffer, shading into the RS-buffer.
    // The TG-buffer is an index into the shared G-buffer, shaded through it (gather_gbuffer).
    // TAA (Table 3): Halton sub-pixel jitter of the RS-buffer's samples (zero without TAA).
    const glm::dvec2 jit = taa_jitter(s.taa, ctx.frame);
    const size_t n_used = gather_gbuffer(
        gb, w, h, [&](double u, double v) { return map.inverse(u + jit.x, v + jit.y); }, rs_index_,
        used_);
    shade_buffer(ctx, GBufferRef(gb, rs_index_.data(), w, h), rs_col_, &used_, out);

    // Rendering to the screen: inverse rectangular mapping as a per-pixel gather (eqs. 4-5).
    out.image.resize(W, H, 3);
    std::vector<double> ux(static_cast<size_t>(W)),
        vy(static_cast<size_t>(H));  // separable: one forward map per column/row
    for (int x = 0; x < W; ++x) ux[size_t(x)] = map.ax.forward(x + 0.5);
    for (int y = 0; y < H; ++y) vy[size_t(y)] = map.ay.forward(y + 0.5);
    parallel_rows(H, [&](int y) {
      for (int x = 0; x < W; ++x) {
        glm::vec3 c = bilinear(rs_col_, ux[size_t(x)] - jit.x, vy[size_t(y)] - jit.y, false);
        float* o = out.image.at(x, y);
        o[0] = c.x;
        o[1] = c.y;
        o[2] = c.z;
      }
    });
    set_counters(out, double(n_used), double(n_used), double(w) * h, double(n_used), double(W) * H,
                 4.0 * W * H);
    if (ctx.want_debug) {
      out.debug.emplace_back("rs_buffer", rs_col_);
      debug_density(ctx, s, out);
    }
  }

 private:
  std::vector<uint32_t> rs_index_;  // TG-buffer: G-buffer sample per slot
  Image rs_col_;
  std::vector<uint8_t> used_;
};

double RmfrGeometry::density(const MappingView& v, double x, double y) const {
  auto m = RectMap::make(v.W, v.H, reduced_size(v.W, sigma), reduced_size(v.H, sigma), v.gaze_px,
                         fx_pixels(v.W), fy_pixels(v.H));
  return m.density(x, y);
}

const ParamTable<MappingSpec>& RmfrGeometry::params_table() {
  using G = RmfrGeometry;
  using S = MappingSpec;
  static const ParamTable<S> t = [] {
    auto px_given = [](const S& s) { return s.as<G>().fx_px > 0; };
    ParamTable<S> t;
    t.number("sigma", 2.6, Range::at_least(1), field<G>(&G::sigma))
        .doc("Ye et al. 2022 §3.2, §6.1", "W / w = H / h of the RS-buffer")
        .column()
        // fx, fy as fractions of W / H, or fx_px, fy_px in pixels (one of each pair). Lower
        // bounds (Ye et al. 2022 eq. 4): a pixel |x'| from the gaze maps to the buffer
        // coordinate N = |x'|(f + E) / (E (f + |x'|)), so half of the RS-buffer's samples lie
        // within f of the gaze. Below a pixel (f_px < 1, or fx = 1e-10) every sample falls on
        // the gaze pixel and the method outputs a one-colour image with a normal shaded
        // fraction; 0.01 of W is 6 px at 640 px, 26 px at 2560.
        .number("fx", 0.38, Range::at_least(0.01), field<G>(&G::fx))
        .doc("Ye et al. 2022 eq. 4, Fig. 7",
             "f_x as a fraction of W (at least 0.01: below, the samples collapse onto the gaze)")
        .read_if([](const Params& p) { return !p.has("fx_px"); })
        .column(nullptr, {}, [](const S& s) { return !(s.as<G>().fx_px > 0); })
        .number("fx_px", 0, Range::at_least(1), field<G>(&G::fx_px))
        .optional()
        .doc("Ye et al. 2022 eq. 4", "f_x in pixels (instead of fx)")
        .column(nullptr, {}, px_given)
        .number("fy", 0.38, Range::at_least(0.01), field<G>(&G::fy))
        .doc("Ye et al. 2022 eq. 4, Fig. 7", "f_y as a fraction of H (at least 0.01, as fx)")
        .read_if([](const Params& p) { return !p.has("fy_px"); })
        .column(nullptr, {}, [](const S& s) { return !(s.as<G>().fy_px > 0); })
        .number("fy_px", 0, Range::at_least(1), field<G>(&G::fy_px))
        .optional()
        .doc("Ye et al. 2022 eq. 4", "f_y in pixels (instead of fy)")
        .column(nullptr, {}, [](const S& s) { return s.as<G>().fy_px > 0; })
        .validate([](const S&, Params& p) {
          if (p.has("fx") && p.has("fx_px"))
            p.fail("fx_px", "give either fx (fraction of W) or fx_px, not both");
          if (p.has("fy") && p.has("fy_px"))
            p.fail("fy_px", "give either fy (fraction of H) or fy_px, not both");
        });
    // Table 3's pipeline ends with a TAA pass (0.87 ms of its full-resolution frame).
    add_taa_rows(
        t, [](auto& s) -> auto& { return s.template as<G>().taa; },
        TaaDefaults{true, 0.1, "box3", true, "Ye et al. 2022 Table 3", true});
    add_target_row(t, "sigma");
    return t;
  }();
  return t;
}

}  // namespace

std::unique_ptr<FoveationMethod> create_rmfr(Params& p) {
  return std::make_unique<RmfrMethod>(read_mapping_spec<RmfrGeometry>(p));
}

const std::vector<ParamInfo>& rmfr_params() {
  return RmfrGeometry::params_table().info();
}

const MethodCost& rmfr_cost() {
  return mapping_method_cost();
}

}  // namespace fovsim
