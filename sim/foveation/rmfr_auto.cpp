// `rmfr_auto`: RMFR (Ye et al. 2022 §3.2) with f_x and f_y chosen per frame from the image, the
// automatic estimation of f_x* and f_y* that Ye et al. 2022 leaves as future work (§7).
// Ye et al. 2022 §4.4.1 reports that scenes dominated by flat (near-horizontal) lines tolerate
// compression along X (small f_x*, large f_y*) and steep lines the reverse. We measure that
// orientation in the periphery of the previous frame's output (what an engine has before
// rendering the next frame): E_x = sum |dI/dx|^2 (energy of steep edges), E_y = sum |dI/dy|^2
// (flat edges), and split a budget f_x + f_y = f_sum in proportion:
//   f_x = f_sum E_x / (E_x + E_y),  f_y = f_sum E_y / (E_x + E_y),  clamped to [f_min, f_max],
// smoothed over frames (weight `adapt` for the newest estimate) and quantised to 0.02 so the
// RS-buffer mapping is rebuilt rarely. Equal energies give RMFR's default 0.38 / 0.38. The
// first frame (and after reset) uses f_sum / 2 each. Rendering, counters and cost are RMFR's.
//
// Parameters: the declaration rmfr_auto_params() at the end of this file (docs are generated).
#include <algorithm>
#include <cmath>
#include <map>

#include "sim/core/math.h"
#include "sim/core/param_table.h"
#include "sim/foveation/mapping_method.h"
#include "sim/foveation/mapping_spec.h"
#include "sim/foveation/methods.h"

namespace fovsim {
namespace {

// Defaults: auto_table() (ParamTable::read sets every key).
struct AutoParams {
  double sigma = 0, f_sum = 0, f_min = 0, f_max = 0, adapt = 0, periphery_deg = 0;
  TaaSettings taa;  // RMFR's (Ye et al. 2022 Table 3); its inner RMFRs jitter with it
};

class RmfrAutoMethod final : public FoveationMethod {
 public:
  explicit RmfrAutoMethod(const AutoParams& p) : p_(p) { reset(); }
  std::string name() const override { return method_id::rmfr_auto; }
  uint32_t required_channels() const override { return kShadingChannels; }
  bool temporal() const override { return true; }
  TaaSettings taa() const override { return p_.taa; }
  void reset() override {
    fx_ = fy_ = 0.5 * p_.f_sum;
    has_prev_ = false;
    select();
  }
  // sigma, the f_x, f_y in use (not keys), f_sum.
  std::vector<std::pair<std::string, double>> param_columns() const override {
    return {{"sigma", p_.sigma}, {"fx", qx_}, {"fy", qy_}, {"f_sum", p_.f_sum}};
  }
  const MappingSpec* mapping_spec() const override {
    return current_ ? current_->mapping_spec() : nullptr;
  }
  // Its cost is RMFR's at its sigma (the f_x, f_y chosen per frame do not change the
  // RS-buffer's samples): the mapping methods' counters, sigma as the budget knob, and under
  // tracking loss sigma' = max(1, sigma / k) as RMFR widens.
  void analytic_counters(const AnalyticFrame& f, Counters& c) const override {
    mapping_analytic_counters(f, c);
  }
  BudgetKnob budget_knob(const AnalyticWorkload&) const override {
    return coarser_buffer_knob("sigma", p_.sigma);
  }
  void widen_cost_keys(double k, Json& p) const override {
    p["sigma"] = widened_sigma(p_.sigma, k);
  }

  void render(const FrameContext& ctx, FrameOutput& out) override {
    if (has_prev_) estimate(ctx);
    select();
    current_->render(ctx, out);
    prev_ = out.image_is_reference ? *ctx.reference : out.image;  // reuses prev_'s storage
    has_prev_ = true;
  }

 private:
  // The RMFR for the current (clamped, quantised) f_x, f_y; before any frame: f_sum / 2 each,
  // which is also the geometry density and predict evaluate.
  void select() {
    qx_ = std::round(std::clamp(fx_, p_.f_min, p_.f_max) * 50.0) / 50.0;
    qy_ = std::round(std::clamp(fy_, p_.f_min, p_.f_max) * 50.0) / 50.0;
    current_ = &inner(qx_, qy_);
  }

  // Peripheral gradient energies of the previous output (luma, every second pixel).
  void estimate(const FrameContext& ctx) {
    const Image& im = prev_;
    if (im.width < 3 || im.height < 3 || !ctx.eccentricity) return;
    double ex = 0, ey = 0;
    auto lum = [&](int x, int y) {
      const float* c = im.at(x, y);
      return double(luma(c[0], c[1], c[2]));
    };
    for (int y = 1; y + 1 < im.height; y += 2)
      for (int x = 1; x + 1 < im.width; x += 2) {
        if ((*ctx.eccentricity)[size_t(y) * size_t(im.width) + size_t(x)] < p_.periphery_deg)
          continue;
        const double gx = lum(x + 1, y) - lum(x - 1, y), gy = lum(x, y + 1) - lum(x, y - 1);
        ex += gx * gx;
        ey += gy * gy;
      }
    if (!(ex + ey > 0)) return;
    const double nx = p_.f_sum * ex / (ex + ey), ny = p_.f_sum * ey / (ex + ey);
    fx_ = p_.adapt * nx + (1 - p_.adapt) * fx_;
    fy_ = p_.adapt * ny + (1 - p_.adapt) * fy_;
  }

  // One RMFR per quantised (f_x, f_y), kept (bounded by the 0.02 grid on [f_min, f_max]^2).
  FoveationMethod& inner(double fx, double fy) {
    const auto key = std::make_pair(int(std::lround(fx * 50)), int(std::lround(fy * 50)));
    auto it = cache_.find(key);
    if (it == cache_.end()) {
      // With its TAA keys: the inner RMFR jitters its RS-buffer as the TAA asks (the pass itself
      // runs once, on this method's output).
      Json j = p_.taa.keys();
      if (p_.taa.enabled) j["taa_jitter"] = p_.taa.jitter;
      j["sigma"] = p_.sigma;
      j["fx"] = fx;
      j["fy"] = fy;
      Params p(j, method_id::rmfr_auto, "");
      it = cache_.emplace(key, create_rmfr(p)).first;
    }
    return *it->second;
  }

  AutoParams p_;
  double fx_ = 0.38, fy_ = 0.38, qx_ = 0.38, qy_ = 0.38;
  bool has_prev_ = false;
  Image prev_;
  std::map<std::pair<int, int>, std::unique_ptr<FoveationMethod>> cache_;
  FoveationMethod* current_ = nullptr;
};

// The declaration of every key (parsing, defaults, ranges, docs, columns).
const ParamTable<AutoParams>& auto_table() {
  static const ParamTable<AutoParams> t = [] {
    ParamTable<AutoParams> t;
    t.number("sigma", 2.6, Range::at_least(1), &AutoParams::sigma)
        .doc("Ye et al. 2022 §3.2, §4.4.2", "W / w = H / h of the RS-buffer")
        .column()
        .number("f_sum", 0.76, Range::above(0, 2), &AutoParams::f_sum)
        .doc("ours (2 x RMFR's 0.38)", "f_x + f_y (fractions of W, H) split by edge orientation")
        .column()
        .number("f_min", 0.1, Range::closed(0.01, 1), &AutoParams::f_min)
        .doc("Ye et al. 2022 Fig. 9 range", "lower clamp of f_x, f_y (at least RMFR's 0.01)")
        .number("f_max", 0.8, Range::above(0, 2), &AutoParams::f_max)
        .doc("Ye et al. 2022 Fig. 9 range", "upper clamp of f_x, f_y")
        .number("adapt", 0.5, Range::above(0, 1), &AutoParams::adapt)
        .doc("ours", "weight of the newest estimate (temporal smoothing)")
        .number("periphery_deg", 10.0, Range::closed(0, 180), &AutoParams::periphery_deg)
        .doc("ours", "edges counted beyond this eccentricity (deg)")
        .validate([](const AutoParams& a, Params& p) {
          if (a.f_max < a.f_min) p.fail("f_max", "must be >= f_min");
        });
    add_taa_rows(
        t, [](auto& s) -> auto& { return s.taa; },
        TaaDefaults{true, 0.1, "box3", true, "Ye et al. 2022 Table 3", true});
    return t;
  }();
  return t;
}

}  // namespace

std::unique_ptr<FoveationMethod> create_rmfr_auto(Params& p) {
  return std::make_unique<RmfrAutoMethod>(auto_table().read(p));
}

const std::vector<ParamInfo>& rmfr_auto_params() {
  return auto_table().info();
}

const MethodCost& rmfr_auto_cost() {
  return mapping_method_cost();
}

}  // namespace fovsim
