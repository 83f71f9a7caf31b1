// `kfr`: Kernel Foveated Rendering (Meng 2018, ch. 2).
// Pass 1: every LP-buffer pixel (u, v) of the (W/sigma) x (H/sigma) buffer takes the nearest
// G-buffer sample at its inverse-mapped screen point (Alg. 2, eqs. 2.10-2.13 inverted), only
// samples landing on the screen are shaded (KFR leaves LP corners unused); a 3x3 Gaussian is
// applied to the peripheral (right) part of the LP-buffer (§2.2.3). Pass 2: each screen pixel
// maps forward (eq. 2.10) and reads the LP-buffer bilinearly, then the eq. 2.14 Gaussian
// post filter with size eta(r / e^L) runs (§2.3.2), then TAA with Halton jitter of the LP-buffer's
// samples (taa.h; rows taa*, on by default; the pass runs in render_with_lighting).
// Both filters are sizes in display pixels, applied at render.scale times that size
// (docs/fidelity.md "Scale invariance of the methods"); a filter narrower than a simulated
// pixel keeps its variance and flags kfr_filter_below_pixel.
//
// Parameters: the declaration kfr_params() at the end of this file (name, type, default,
// range, seed section, meaning); docs/methods.md and configs/README.md are generated from it.
#include <algorithm>
#include <cmath>

#include "sim/core/param_table.h"
#include "sim/foveation/mapping_method.h"
#include "sim/foveation/methods.h"

namespace fovsim {
namespace {

// Fills unused LP pixels from the used ones so bilinear taps next to the screen border read
// shaded colours: along each row (one direction from the fovea) the used pixels form one run
// (the ray meets the convex screen in one segment), extend it both ways; empty rows copy the
// nearest non-empty row (angle wraps).
void extend_unused(Image& img, const std::vector<uint8_t>& used) {
  const int w = img.width, h = img.height;
  std::vector<uint8_t> row_ok(size_t(h), 0);
  parallel_rows(h, [&](int v) {
    const uint8_t* u = &used[size_t(v) * size_t(w)];
    int first = -1, last = -1;
    for (int x = 0; x < w; ++x)
      if (u[x]) {
        if (first < 0) first = x;
        last = x;
      }
    if (first < 0) return;
    row_ok[size_t(v)] = 1;
    for (int x = 0; x < w; ++x) {
      if (u[x]) continue;
      const int src = x < first ? first : (x > last ? last : -1);
      if (src < 0) {  // interior gap (rounding at a corner): nearest used to the left
        int s = x - 1;
        while (s > first && !u[s]) --s;
        std::copy_n(img.at(s, v), 3, img.at(x, v));
      } else {
        std::copy_n(img.at(src, v), 3, img.at(x, v));
      }
    }
  });
  bool any = false;
  for (uint8_t b : row_ok) any |= (b != 0);
  if (!any) return;
  for (int v = 0; v < h; ++v) {
    if (row_ok[size_t(v)]) continue;
    for (int d = 1; d <= h; ++d) {
      int a = ((v - d) % h + h) % h, b = (v + d) % h;
      int src = row_ok[size_t(a)] ? a : (row_ok[size_t(b)] ? b : -1);
      if (src >= 0) {
        std::copy_n(img.row(src), size_t(w) * 3, img.row(v));
        break;
      }
    }
  }
}

// kfr's parameters and sampling geometry (density, samples, iso-budget free parameter, widening);
// the keys are the table params_table() at the end of this file.
struct KfrGeometry final : GeometryOf<KfrGeometry> {
  static constexpr const char* kMethod = method_id::kfr;
  // Defaults: params_table() (read_mapping_spec sets them).
  double sigma = 0;              // W / w (= H / h), Meng 2018 eq. 2.8
  KernelFn kernel;               // kernel K and alpha
  bool internal_aa = false;      // §2.2.3 3x3 Gaussian on the peripheral part of the LP-buffer
  double internal_aa_start = 0;  // fraction of the LP-buffer width where "the right part" starts
  bool post_aa = false;          // §2.3.2 eq. 2.14 Gaussian post filter

  static const ParamTable<MappingSpec>& params_table();
  double density(const MappingView& v, double x, double y) const override;
  double expected_samples(const MappingView& v) const override;
  bool shades_whole_buffer() const override { return true; }
  double buffer_reduction() const override { return sigma; }
  // The LP-buffer shades (W / sigma) x (H / sigma) samples (eq. 2.8): sigma is the budget knob.
  BudgetKnob budget_knob() const override { return coarser_buffer_knob("sigma", sigma); }
  FreeParam free_param() const override { return {"sigma", 1.0, 1e4, nullptr}; }
  double& free_ref() override { return sigma; }
  // Under tracking loss the LP-buffer grows by k per axis: sigma' = max(1, sigma / k) (Meng 2018
  // eq. 2.8: every sampling rate of the map scales with 1 / sigma, so a region sampled at
  // least at a given rate grows).
  void widen(double k) override { sigma = widened_sigma(sigma, k); }
  void widen_keys(double k, Json& p) const override { p["sigma"] = widened_sigma(sigma, k); }
};

class KfrMethod final : public MappingMethod<KfrGeometry> {
 public:
  using MappingMethod::MappingMethod;

  void render(const FrameContext& ctx, FrameOutput& out) override {
    // Tracking loss under trace.on_invalid = widen: a larger buffer (KfrGeometry::widen).
    const KfrGeometry& s = frame_geometry(ctx, out);
    const GBuffer& gb = *ctx.gbuffer;
    const int W = gb.width, H = gb.height;
    const int w = reduced_size(W, s.sigma), h = reduced_size(H, s.sigma);
    const LogPolarMap map = LogPolarMap::make(W, H, w, h, ctx.gaze_px, s.kernel);

    // Pass 1: forward kernel log-polar transformation of the G-buffer (§2.2.1-2.2.2): the
    // LP-buffer is an index into the shared G-buffer, shaded through it (same values as a copy).
    // TAA (§2.3.2): Halton sub-pixel jitter of the LP-buffer's samples (zero without TAA).
    const glm::dvec2 jit = taa_jitter(s.taa, ctx.frame);
    const size_t n_used = lp_gather(gb, map, lp_index_, used_, jit);
    shade_buffer(ctx, GBufferRef(gb, lp_index_.data(), w, h), lp_col_, &used_, out);
    extend_unused(lp_col_, used_);
    double taps = 0;
    // Scale invariance: the filters below are defined at the display's resolution (Meng 2018
    // §2.2.3 in native LP pixels, eq. 2.14 in display pixels) and applied at render.scale s,
    // i.e. with s^2 times their variance in simulated pixels (mapping.h kernel_with_variance).
    const double scale = ctx.render_scale;
    bool below_pixel = false;  // a filter narrower than a simulated pixel (its variance kept)
    // §2.2.3 internal anti-aliasing: 3x3 Gaussian on the right (peripheral) part.
    if (s.internal_aa) {
      taps += gaussian3x3_from(lp_col_, int(std::floor(s.internal_aa_start * w)), true, &tmp_lp_,
                               scale);
      below_pixel = below_pixel || scale < 1;  // 0.5 s^2 < 0.5 px^2: a sub-pixel 3-tap kernel
    }

    // Pass 2: inverse transformation by sampling the LP-buffer at each pixel's forward map
    // (Alg. 2 as a gather), bilinear, angle wrapping.
    lp_reconstruct(lp_col_, map, W, H, out.image, jit);
    taps += 4.0 * W * H;

    // §2.3.2 post anti-aliasing, eq. 2.14: eta = 3 + 2 ceil((r / e^L - 0.10) / 0.05);
    // eta < 3 (r / e^L <= 0.05) leaves the pixel unfiltered; r <= e^L caps eta at 39.
    if (s.post_aa) {
      eta_.resize(size_t(W) * size_t(H));
      const double eL = std::exp(map.L);
      // eta(x) on a row is a function of |dx| alone, monotone (every step -- subtraction,
      // square, sqrt, division, ceil -- is monotone in floating point), so each side of the
      // gaze splits into runs of equal eta: found by galloping/binary search with the exact
      // per-pixel formula, then filled.
      int split =
          int(std::clamp(std::ceil(map.gx - 0.5), 0.0, double(W)));  // first x: x + 0.5 >= gx
      while (split > 0 && split - 1 + 0.5 >= map.gx) --split;
      while (split < W && !(split + 0.5 >= map.gx)) ++split;
      parallel_rows(H, [&](int y) {
        const double dy = y + 0.5 - map.gy, dy2 = dy * dy;
        auto eta_at = [&](int x) {
          const double dx = x + 0.5 - map.gx;
          const double q = std::min(std::sqrt(dx * dx + dy2) / eL, 1.0);
          const double e = 3.0 + 2.0 * std::ceil((q - 0.10) / 0.05 - 1e-9);
          return uint8_t(e < 3 ? 1 : std::min(e, 39.0));
        };
        uint8_t* er = &eta_[size_t(y) * size_t(W)];
        int x = 0;
        while (x < W) {
          const int end = x < split ? split : W;  // monotone segment [x, end)
          const uint8_t e = eta_at(x);
          int lo = x, step = 1;  // eta(lo) == e; find the last such index before end
          while (lo + step < end && eta_at(lo + step) == e) {
            lo += step;
            step *= 2;
          }
          int hi = std::min(lo + step, end);  // eta(hi) != e or hi == end
          while (hi - lo > 1) {
            const int mid = lo + (hi - lo) / 2;
            if (eta_at(mid) == e)
              lo = mid;
            else
              hi = mid;
          }
          std::fill(er + x, er + lo + 1, e);
          x = lo + 1;
        }
      });
      taps += variable_gaussian(out.image, eta_, 39, &tmp_full_, scale);
      if (scale < 1) {
        // Codes whose scaled kernel is narrower than a pixel (variance <= 0.5 px^2, the 3-tap
        // form of kernel_with_variance), and whether one of them is in use.
        bool sub[40] = {};
        for (int n = 3; n <= 39; n += 2)
          sub[n] = scale * scale * kernel_variance(post_aa_kernel_native(n)) <= 0.5;
        below_pixel = below_pixel || std::any_of(eta_.begin(), eta_.end(),
                                                 [&](uint8_t e) { return e >= 3 && sub[e]; });
      }
    }
    if (below_pixel) out.flags.push_back("kfr_filter_below_pixel");

    set_counters(out, double(n_used), double(n_used), double(w) * h, double(n_used), double(W) * H,
                 taps);
    if (ctx.want_debug) {
      out.debug.emplace_back("lp_buffer", lp_col_);
      Image m(w, h, 1);
      for (size_t i = 0; i < used_.size(); ++i) m.data[i] = used_[i];
      out.debug.emplace_back("lp_used", std::move(m));
      debug_density(ctx, s, out);
    }
  }

 private:
  std::vector<uint32_t> lp_index_;  // LP-buffer: G-buffer sample per slot (reused across frames)
  Image lp_col_;
  std::vector<uint8_t> used_, eta_;
  Image tmp_lp_, tmp_full_;  // scratch of the two Gaussian passes (kept: no per-frame allocation)
};

double KfrGeometry::density(const MappingView& v, double x, double y) const {
  auto m = LogPolarMap::make(v.W, v.H, reduced_size(v.W, sigma), reduced_size(v.H, sigma),
                             v.gaze_px, kernel);
  return m.density(x, y);
}

// LP-buffer pixels whose inverse map lands on the screen (the ones pass 1 shades).
double KfrGeometry::expected_samples(const MappingView& v) const {
  const int w = reduced_size(v.W, sigma), h = reduced_size(v.H, sigma);
  auto m = LogPolarMap::make(v.W, v.H, w, h, v.gaze_px, kernel);
  return sum_rows(h, [&](int iv) {
    double n = 0;
    for (int iu = 0; iu < w; ++iu) {
      glm::dvec2 p = m.inverse(iu + 0.5, iv + 0.5);
      if (p.x >= 0 && p.y >= 0 && p.x < v.W && p.y < v.H) n += 1;
    }
    return n;
  });
}

const ParamTable<MappingSpec>& KfrGeometry::params_table() {
  using G = KfrGeometry;
  static const ParamTable<MappingSpec> t = [] {
    ParamTable<MappingSpec> t;
    t.number("sigma", 1.8, Range::at_least(1), field<G>(&G::sigma))
        .doc("Meng 2018 §2.1 eq. 2.8", "W / w = H / h of the LP-buffer")
        .column()
        .number(
            "alpha", 4.0, Range::closed(1e-3, 1e3),
            [](auto& s) -> auto& { return s.template as<G>().kernel.alpha; })
        .doc("Meng 2018 §2.1 eq. 2.9", "exponent of K(x) = x^alpha")
        .column()
        .choice(
            "kernel", "power",
            std::vector<std::pair<std::string, KernelKind>>{
                {"power", KernelKind::Power}, {"sine", KernelKind::Sine}, {"exp", KernelKind::Exp}},
            [](auto& s) -> auto& { return s.template as<G>().kernel.kind; })
        .doc("Meng 2018 §2.1", "K(x) = x^alpha, sin(x pi/2) or (e^x - 1)/(e - 1)")
        .column()
        .boolean("internal_aa", true, field<G>(&G::internal_aa))
        .doc("Meng 2018 §2.2.3", "3x3 Gaussian on the peripheral LP part")
        .number("internal_aa_start", 0.5, Range::closed(0, 1), field<G>(&G::internal_aa_start))
        .doc("Meng 2018 §2.2.3", "u/w where the filtered part starts")
        .boolean("post_aa", true, field<G>(&G::post_aa))
        .doc("Meng 2018 §2.3.2 eq. 2.14", "eccentricity-sized Gaussian post filter");
    // §2.3.2: "temporal anti-aliasing with Halton sampling" after the post filter.
    add_taa_rows(
        t, [](auto& s) -> auto& { return s.template as<G>().taa; },
        TaaDefaults{true, 0.1, "box3", true, "Meng 2018 §2.3.2", true});
    add_target_row(t, "sigma");
    return t;
  }();
  return t;
}

}  // namespace

std::unique_ptr<FoveationMethod> create_kfr(Params& p) {
  return std::make_unique<KfrMethod>(read_mapping_spec<KfrGeometry>(p));
}

const std::vector<ParamInfo>& kfr_params() {
  return KfrGeometry::params_table().info();
}

const MethodCost& kfr_cost() {
  return mapping_method_cost();
}

}  // namespace fovsim
