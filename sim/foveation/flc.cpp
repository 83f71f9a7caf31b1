// `flc`: Foveated Light Culling (Yang et al. 2021) as a method = full-resolution sampling of
// the direct light + the `flc` lighting strategy (lighting_flc.h: importance map §4.1,
// quasi-MH sample selection §4.2, eq. 14 contributions with BLSO visibility §5, stochastic
// culling to `vpl_budget`) + the paper's own indirect shading with the kept VPLs (optionally
// in log-polar space with interleaved sampling, §6). The RSMs, the VPLs and the ground truth
// (direct + indirect from ALL VPLs, the paper's TBDS) are the frame's shared data: the scene
// says how VPLs are made (scene.vpl), and this method is measured against the same reference
// as every other row. The same culling composes with any sampling method through
// {"lighting": {"method": "flc"}}.
//
// Parameters: the declaration flc_params() at the end of this file (name, type, default,
// range, seed section, meaning); docs/methods.md and configs/README.md are generated from it.
#include "sim/foveation/flc.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "sim/core/param_table.h"
#include "sim/foveation/flc_shading.h"
#include "sim/foveation/lighting_flc.h"
#include "sim/foveation/methods.h"

namespace fovsim {
namespace {

using Clock = std::chrono::steady_clock;
double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

double rmse_region(const Image& a, const Image& b, const glm::dvec2& gaze, double radius,
                   bool inside) {
  double acc = 0;
  size_t n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const double dx = x + 0.5 - gaze.x, dy = y + 0.5 - gaze.y;
      if ((dx * dx + dy * dy <= radius * radius) != inside) continue;
      const float* p = a.at(x, y);
      const float* q = b.at(x, y);
      for (int c = 0; c < 3; ++c) acc += double(p[c] - q[c]) * double(p[c] - q[c]);
      n += 3;
    }
  return n ? std::sqrt(acc / double(n)) : 0.0;
}

struct FlcShadeSettings {
  bool log_polar = false;
  double lp_sigma = 2.0;
  int interleave = 1;
  TaaSettings taa;  // §6: TAA whose history clamp is eq. 15's eta x eta window
};

class FlcMethod final : public FoveationMethod {
 public:
  FlcMethod(const FlcLightingSettings& ls, const FlcShadeSettings& s) : s_(s) {
    auto l = std::make_unique<FlcLighting>(ls);
    flc_ = l.get();
    lighting_ = std::move(l);
  }
  std::string name() const override { return method_id::flc; }
  uint32_t required_channels() const override { return kShadingChannels; }
  bool own_lighting() const override { return true; }
  TaaSettings taa() const override { return s_.taa; }
  std::vector<std::pair<std::string, double>> param_columns() const override {
    return {{"log_polar", s_.log_polar ? 1.0 : 0.0},
            {"lp_sigma", s_.log_polar ? s_.lp_sigma : 1.0},
            {"interleave", s_.interleave}};
  }

  // Direct light at every pixel, one VPL per RSM texel (§3), its strategy's selection passes
  // and the kept VPLs at the shaded samples of the log-polar transform, interleaved (§6).
  void analytic_counters(const AnalyticFrame& f, Counters& c) const override {
    const AnalyticWorkload& w = *f.workload;
    const double P = f.pixels;
    double lights = std::max(1.0, w.lights);
    double total = w.rsm_res * w.rsm_res * lights;  // one VPL per RSM texel (Yang et al. 2021 §3)
    // The budget given on the command line (validated by FLC's parser), else the workload's.
    const double budget =
        f.given->contains("vpl_budget") ? f.column("vpl_budget", w.vpl_budget) : w.vpl_budget;
    double kept = std::min(total, budget);
    double ns = w.importance_samples;
    double s = P * w.lpt_fraction;
    c.set(Counter::shaded_samples, s);
    c.set(Counter::gbuffer_samples, P);
    c.set(Counter::rsm_texels, total);
    c.set(Counter::vpls_total, total);
    c.set(Counter::vpls_kept, kept);
    // The strategy's selection counters: eq. 14 for every VPL and sample, BLSO lookups.
    flc_->analytic_selection_counters(c, total, ns);
    c.set(Counter::shaded_sample_vpls, s * kept / w.interleave);  // interleaved sampling (§6)
  }
  // Fewer VPLs kept (§7, Fig. 7: the cost falls almost quadratically with them).
  BudgetKnob budget_knob(const AnalyticWorkload& w) const override {
    return halved_count_knob("vpl_budget", w.vpl_budget);
  }
  // Under tracking loss the log-polar buffer grows by k per axis: lp_sigma' = max(1, lp_sigma /
  // k), as render() widens it; its foveal region does not change the analytic cost (the VPL
  // budget is a count).
  void widen_cost_keys(double k, Json& p) const override {
    if (s_.log_polar) p["lp_sigma"] = std::max(1.0, s_.lp_sigma / k);
  }

  void render(const FrameContext& ctx, FrameOutput& out) override {
    const GBuffer& g = *ctx.gbuffer;
    const int W = g.width, H = g.height;
    Counters& c = out.counters;
    const double px = double(W) * double(H);
    c.set(Counter::gbuffer_samples, px);
    c.set(Counter::fullres_pixels, px);
    c.set(Counter::direct_shaded_samples, px);
    c.set(Counter::lights, double(ctx.scene->lights.size()));
    times_ = FlcStageTimes();
    if (!ctx.vpls || ctx.lighting != flc_) {
      // The scene has no indirect light: FLC has nothing to cull; full-resolution direct light.
      out.image_is_reference = true;
      c.set(Counter::shaded_samples, px);
      out.flags.push_back("no_indirect_light");
      return;
    }
    const FlcLightingTimes& lt = flc_->times();
    times_.importance = lt.importance;
    times_.sampling = lt.sampling;
    times_.contribution = lt.contribution;
    times_.culling = lt.culling;
    auto t0 = Clock::now();
    // S-7 / §6: shading with the kept VPLs, interleaved groups, optionally in log-polar space.
    const int n = s_.interleave;
    const CullResult& kept = flc_->kept();
    const std::vector<VplSoA> groups =
        flc_interleave_groups(ctx.vpls->vpls, kept.kept, kept.weight, n);
    const VplShading& sh = ctx.vpls->shading;
    Image lp_dbg;
    if (s_.log_polar)
      // Tracking loss under trace.on_invalid = widen: the log-polar buffer grows by k per
      // axis, lp_sigma' = max(1, lp_sigma / k), as kfr's sigma (docs/tracking.md).
      flc_shade_logpolar(g, ctx.gaze_px,
                         ctx.widen > 1 ? std::max(1.0, s_.lp_sigma / ctx.widen) : s_.lp_sigma,
                         groups, n, sh, ctx.renderer, indirect_, &c,
                         ctx.want_debug ? &lp_dbg : nullptr, &scratch_);
    else
      flc_shade_cartesian(g, groups, n, sh, ctx.renderer, indirect_, &c, &scratch_);
    auto t1 = Clock::now();
    times_.shading = ms_between(t0, t1);
    const Image& direct = *ctx.direct;
    if (out.image.width != W || out.image.height != H || out.image.channels != 3)
      out.image.resize(W, H, 3);
    const size_t N = size_t(W) * size_t(H) * 3;
    for (size_t i = 0; i < N; ++i) out.image.data[i] = direct.data[i] + indirect_.data[i];

    // Own tau (Table 1) on display-encoded images against the shared reference, fovea = the
    // eq. 5 region.
    ToneMap tm;
    tm.exposure = ctx.scene->exposure;
    tm.apply(out.image, od_);
    tm.apply(*ctx.reference, gd_);
    const double half_diag = 0.5 * std::sqrt(double(W) * W + double(H) * H);
    const double fovea_px = flc_->settings().imp.fovea_frac * half_diag;
    const double rf = rmse_region(od_, gd_, ctx.gaze_px, fovea_px, true);
    const double rp = rmse_region(od_, gd_, ctx.gaze_px, fovea_px, false);
    c.set(Counter::flc_rmse_fovea, rf);
    c.set(Counter::flc_rmse_periphery, rp);
    c.set(Counter::flc_tau, (rp + 1e-6) / (rf + 1e-6));  // regularised: 1 when both are 0
    times_.compose = ms_between(t1, Clock::now());
    if (ctx.want_debug && !lp_dbg.empty()) {
      Image lpd;
      tm.apply(lp_dbg, lpd);
      out.debug.emplace_back("lp_buffer", std::move(lpd));
    }
  }

  const FlcStageTimes& times() const { return times_; }

 private:
  FlcShadeSettings s_;
  FlcLighting* flc_ = nullptr;  // owned by lighting_
  Image indirect_, od_, gd_;    // scratch, reused every frame
  FlcShadeScratch scratch_;
  FlcStageTimes times_;
};

}  // namespace

const FlcStageTimes* flc_stage_times(const FoveationMethod& m) {
  const auto* f = dynamic_cast<const FlcMethod*>(&m);
  return f ? &f->times() : nullptr;
}

namespace {
// The method's own keys (log-polar shading, §6); the strategy's keys come first
// (flc_lighting_table).
const ParamTable<FlcShadeSettings>& flc_shade_table() {
  using S = FlcShadeSettings;
  static const ParamTable<S> t = [] {
    ParamTable<S> t;
    t.boolean("log_polar", false, &S::log_polar)
        .doc("§6", "log-polar shading")
        .number("lp_sigma", 2.0, Range::closed(1, 32), &S::lp_sigma)
        .doc("§6", "log-polar buffer reduction")
        .integer("interleave", 1, Range::closed(1, 2), &S::interleave)
        .doc("§6", "interleaved sampling n");
    // §6: the post-antialiasing pass ends with TAA whose history clamp is the eta x eta window
    // of eq. 15 (no reduced buffer of direct light to jitter: no jitter row).
    add_taa_rows(
        t, [](auto& s) -> auto& { return s.taa; },
        TaaDefaults{true, 0.1, "eta", false, "§6 eq. 15", false});
    return t;
  }();
  return t;
}
}  // namespace

std::unique_ptr<FoveationMethod> create_flc(Params& p) {
  for (const char* moved : {"rsm_size", "min_dist", "shading_visibility"})
    if (p.has(moved))
      p.fail(moved, std::string("VPL generation is a scene setting now: use scene.vpl.") +
                        (std::string(moved) == "shading_visibility" ? "shadow_rays" : moved) +
                        " (models/scenes/README.md)");
  const FlcLightingSettings ls = FlcLightingSettings::from_params(p);
  return std::make_unique<FlcMethod>(ls, flc_shade_table().read(p));
}

// Direct light at every pixel plus its own VPLs, built and counted even on a scene without
// indirect light; the strategy's importance, contribution and culling passes come from its
// lighting strategy (declared_passes).
const MethodCost& flc_cost() {
  static const MethodCost m = [] {
    MethodCost d;
    d.passes.direct_at_every_pixel = d.passes.own_vpls = true;
    return d;
  }();
  return m;
}

const std::vector<ParamInfo>& flc_params() {
  static const std::vector<ParamInfo> t = [] {
    std::vector<ParamInfo> v = flc_lighting_params();
    for (const ParamInfo& i : flc_shade_table().info()) v.push_back(i);
    return v;
  }();
  return t;
}

}  // namespace fovsim
