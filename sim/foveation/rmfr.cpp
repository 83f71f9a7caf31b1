// `rmfr`: Rectangular Mapping-based Foveated Rendering (Ye et al. 2022 §3.2).
// Pass 1: every RS-buffer pixel of the (W/sigma) x (H/sigma) buffer takes the nearest G-buffer
// sample at its inverse-mapped screen point (eqs. 6-7, all four quadrants: the normalisation
// of eq. 5 uses W - x^ right of the gaze and x^ left of it, likewise in y); the TG-buffer is
// shaded in full (RMFR uses the whole buffer, §3.3.3). Pass 2: each screen pixel maps forward
// (eqs. 4-5) and reads the RS-buffer bilinearly. A gaze off the screen is clamped to the
// nearest edge (eq. 5 needs 0 <= x^ <= W). TAA (Table 3) is not simulated.
//
// Parameters: the declaration rmfr_params() at the end of this file (name, type, default,
// range, seed section, meaning); docs/methods.md and configs/README.md are generated from it.
#include "sim/foveation/mapping_method.h"
#include "sim/foveation/methods.h"

namespace fovsim {
namespace {

class RmfrMethod final : public MappingMethodBase {
 public:
  using MappingMethodBase::MappingMethodBase;

  void render(const FrameContext& ctx, FrameOutput& out) override {
    // Tracking loss under trace.on_invalid = widen: a larger buffer (widened_spec).
    const MappingSpec& s = widened_spec(resolve(ctx, out), ctx.widen, widened_);
    const GBuffer& gb = *ctx.gbuffer;
    const int W = gb.width, H = gb.height;
    const int w = reduced_size(W, s.sigma), h = reduced_size(H, s.sigma);
    const RectMap map = RectMap::make(W, H, w, h, ctx.gaze_px, s.fx_pixels(W), s.fy_pixels(H));

    // Rectangular mapping of the G-buffer into the TG-buffer, shading into the RS-buffer.
    // The TG-buffer is an index into the shared G-buffer, shaded through it (gather_gbuffer).
    const size_t n_used = gather_gbuffer(
        gb, w, h, [&](double u, double v) { return map.inverse(u, v); }, rs_index_, used_);
    shade_buffer(ctx, GBufferRef(gb, rs_index_.data(), w, h), rs_col_, &used_, out);

    // Rendering to the screen: inverse rectangular mapping as a per-pixel gather (eqs. 4-5).
    out.image.resize(W, H, 3);
    std::vector<double> ux(static_cast<size_t>(W)),
        vy(static_cast<size_t>(H));  // separable: one forward map per column/row
    for (int x = 0; x < W; ++x) ux[size_t(x)] = map.ax.forward(x + 0.5);
    for (int y = 0; y < H; ++y) vy[size_t(y)] = map.ay.forward(y + 0.5);
    parallel_rows(H, [&](int y) {
      for (int x = 0; x < W; ++x) {
        glm::vec3 c = bilinear(rs_col_, ux[size_t(x)], vy[size_t(y)], false);
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
  MappingSpec widened_;             // the spec of a frame under tracking loss (widened_spec)
  std::vector<uint32_t> rs_index_;  // TG-buffer: G-buffer sample per slot
  Image rs_col_;
  std::vector<uint8_t> used_;
};

}  // namespace

std::unique_ptr<FoveationMethod> create_rmfr(Params& p) {
  return std::make_unique<RmfrMethod>(MappingSpec::from_params("rmfr", p));
}

const std::vector<ParamInfo>& rmfr_params() {
  static const std::vector<ParamInfo> t = {
      {"sigma", "number", "2.6", "[1, inf)", "Ye et al. 2022 §3.2, §6.1",
       "W / w = H / h of the RS-buffer"},
      {"fx", "number", "0.38", "(0, inf)", "Ye et al. 2022 eq. 4, Fig. 7",
       "f_x as a fraction of W"},
      {"fy", "number", "0.38", "(0, inf)", "Ye et al. 2022 eq. 4, Fig. 7",
       "f_y as a fraction of H"},
      {"fx_px", "number", "none", "(0, inf)", "Ye et al. 2022 eq. 4",
       "f_x in pixels (instead of fx)"},
      {"fy_px", "number", "none", "(0, inf)", "Ye et al. 2022 eq. 4",
       "f_y in pixels (instead of fy)"},
      {"target_shaded_fraction", "number", "none", "(0, 1]", "Ye et al. 2022 §5.1",
       "iso-budget: solve sigma"},
  };
  return t;
}

}  // namespace fovsim
