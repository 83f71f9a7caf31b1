// `flc` lighting strategy (lighting_flc.h): Yang et al., "Foveated light culling", §4-§5.
#include "sim/foveation/lighting_flc.h"

#include <chrono>
#include <cmath>

#include "sim/core/hash.h"
#include "sim/core/param_table.h"
#include "sim/core/rng.h"
#include "sim/foveation/flc_sampling.h"
#include "sim/foveation/method.h"
#include "sim/render/renderer.h"

namespace fovsim {
namespace {
using Clock = std::chrono::steady_clock;
double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}
}  // namespace

const ParamTable<FlcLightingSettings>& flc_lighting_table() {
  using S = FlcLightingSettings;
  static const auto t =
      ParamTable<S>()
          .integer("vpl_budget", 1024, Range::closed(0, 1e6), &S::vpl_budget)
          .doc("§7 Fig. 7", "VPLs kept for shading")
          .column()
          .integer("samples", 256, Range::closed(1, 1e6), &S::samples)
          .doc("Alg. 1", "N_s importance samples")
          .column()
          .integer("chain_length", 16, Range::closed(1, 4096), &S::chain_length)
          .doc("Alg. 1", "M proposals per chain")
          .column()
          .number(
              "omega_p", 0.2, Range::closed(0, 1), [](auto& s) -> auto& { return s.imp.omega_p; })
          .doc("eq. 3", "acuity floor")
          .number(
              "acuity_slope", 2.25, Range::closed(0, 1e3),
              [](auto& s) -> auto& { return s.imp.slope; })
          .doc("eq. 4", "acuity slope s (1/rad)")
          .number(
              "fovea_frac", 150.0 / (512.0 * std::sqrt(2.0)), Range::above(0, 10),
              [](auto& s) -> auto& { return s.imp.fovea_frac; })
          .doc("eq. 5", "foveal radius / half diagonal (150 px at 1024x1024)")
          .choice(
              "eccentricity", "seed",
              std::vector<std::pair<std::string, bool>>{{"seed", false}, {"exact", true}},
              [](auto& s) -> auto& { return s.imp.exact_eccentricity; })
          .doc("eq. 6", "eccentricity model")
          .number(
              "silhouette_value", 1.0, Range::closed(0, 1),
              [](auto& s) -> auto& { return s.imp.silhouette_value; })
          .doc("§4.1.2", "p_g on silhouettes")
          .number(
              "depth_threshold", 0.05, Range::above(0, 1e6),
              [](auto& s) -> auto& { return s.imp.depth_threshold; })
          .doc("§4.1.2", "relative depth jump")
          .number(
              "normal_threshold_deg", 30.0, Range::closed(0, 180),
              [](auto& s) -> auto& { return s.imp.normal_threshold_deg; })
          .doc("§4.1.2", "normal angle")
          .number(
              "color_threshold", 48.0, Range::closed(0, 1e6),
              [](auto& s) -> auto& { return s.imp.color_threshold; })
          .doc("eq. 7", "colour difference")
          .number(
              "delta", 20.0, Range::closed(0, 1e6), [](auto& s) -> auto& { return s.imp.delta; })
          .doc("eq. 8", "indirect brightness factor")
          .number("history_blend", 0.5, Range::above(0, 1), &S::history_blend)
          .doc("eq. 8", "weight of the newest frame in b(p)")
          .number("w_fovea", 1.0, Range::closed(0, 1e6), &S::w_fovea)
          .doc("eq. 1", "fovea sample weight")
          .number("w_periphery", 1.0, Range::closed(0, 1e6), &S::w_periphery)
          .doc("eq. 1", "periphery sample weight")
          .number("epsilon", 0.02, Range::above(0, 1), &S::epsilon)
          .doc("eq. 10", "sqrt(eps) / scene diagonal")
          .choice(
              "visibility", "blso",
              std::vector<std::pair<std::string, FlcVisibility>>{{"none", FlcVisibility::None},
                                                                 {"blso", FlcVisibility::Blso},
                                                                 {"exact", FlcVisibility::Exact}},
              &S::visibility)
          .doc("eq. 11", "visibility in eq. 14")
          .number(
              "blso_lambda", 0.5, Range::closed(0, 1),
              [](auto& s) -> auto& { return s.blso.lambda; })
          .doc("eq. 11", "mix coefficient")
          .number(
              "blso_k", 34.0, Range::above(0, 1e6), [](auto& s) -> auto& { return s.blso.k; })
          .doc("eq. 12", "attenuation factor")
          .number(
              "blso_xi", 0.01, Range::above(0, 1), [](auto& s) -> auto& { return s.blso.xi; })
          .doc("eq. 12", "threshold / scene diagonal")
          .number(
              "blso_radius", 0.1, Range::above(0, 10),
              [](auto& s) -> auto& { return s.blso.radius; })
          .doc("§5", "local radius / scene diagonal")
          .number(
              "blso_cone_deg", 30.0, Range::above(0, 90),
              [](auto& s) -> auto& { return s.blso.cone_deg; })
          .doc("§5", "local cone half-angle")
          .integer(
              "blso_samples", 4, Range::closed(1, 256),
              [](auto& s) -> auto& { return s.blso.samples; })
          .doc("eq. 13", "N' per side")
          .number("culling_floor", 0.02, Range::closed(0, 1), &S::culling_floor)
          .doc("§5", "uniform share of culling probabilities")
          .integer("seed", 1, Range::closed(0, 2e9), &S::seed)
          .doc("", "random seed");
  return t;
}

FlcLightingSettings FlcLightingSettings::from_params(Params& p) {
  return flc_lighting_table().read(p);
}

const std::vector<ParamInfo>& flc_lighting_params() {
  return flc_lighting_table().info();
}

std::vector<std::pair<std::string, double>> FlcLighting::param_columns() const {
  return {{"vpl_budget", s_.vpl_budget},
          {"blso", s_.visibility == FlcVisibility::Blso ? 1.0 : 0.0},
          {"visibility_code", double(int(s_.visibility))},
          {"samples", s_.samples},
          {"chain_length", s_.chain_length}};
}

void FlcLighting::begin_frame(const FrameContext& ctx, Counters& c) {
  const FrameVpls& fv = *ctx.vpls;
  const GBuffer& g = *ctx.gbuffer;
  const int W = g.width, H = g.height;
  const Camera& cam = *ctx.camera;
  const uint64_t fseed = splitmix64(s_.seed ^ splitmix64(uint64_t(ctx.frame) + 0x51ull));
  c.set(Counter::vpls_total, double(fv.vpls.size()));
  auto t0 = Clock::now();

  // §4.1: importance map from the display-encoded direct frame and the indirect history.
  ToneMap tm;
  tm.exposure = ctx.scene->exposure;
  tm.apply(*ctx.direct, color_);
  const double tan_diag =
      std::sqrt(cam.tan_half_h * cam.tan_half_h + cam.tan_half_v * cam.tan_half_v);
  const bool hist_ok = history_.width == W && history_.height == H;
  keep_debug_ = ctx.want_debug;
  // Tracking loss under trace.on_invalid = widen (docs/tracking.md): the foveal region of
  // eq. 5 grows by k = ctx.widen (fovea_frac' = k fovea_frac), so the acuity importance, and
  // with it the shading points and the VPL budget they select, covers a k times larger radius.
  // With exact_eccentricity the eccentricity map is already divided by k.
  FlcImportanceParams imp = s_.imp;
  const bool widen = ctx.widen > 1;
  if (widen && !(imp.exact_eccentricity && ctx.eccentricity)) imp.fovea_frac *= ctx.widen;
  flc_importance_map(g, color_, hist_ok ? &history_ : nullptr, ctx.gaze_px, tan_diag,
                     ctx.eccentricity, imp, maps_, ctx.want_debug);
  auto t1 = Clock::now();
  times_.importance = ms_between(t0, t1);

  // §4.2, Alg. 1: N_s chains of length M over shuffled Halton points.
  const std::vector<glm::vec2> halton =
      shuffled_halton(size_t(s_.samples) * size_t(s_.chain_length), fseed);
  const std::vector<ImportanceSample> samples =
      flc_select_samples(maps_.importance, halton, s_.samples, s_.chain_length);
  c.set(Counter::importance_samples, double(samples.size()));
  c.set(Counter::halton_proposals, double(halton.size()));
  const double half_diag = 0.5 * std::sqrt(double(W) * W + double(H) * H);
  const double fovea_px = s_.imp.fovea_frac * half_diag * (widen ? ctx.widen : 1.0);  // eq. 1
  std::vector<FlcShadingPoint> pts;
  pts.reserve(samples.size());
  for (const ImportanceSample& sm : samples) {
    FlcShadingPoint p;
    if (!g.hit(sm.pixel) || !(sm.weight > 0.f)) {
      pts.push_back(p);  // weight 0: contributes nothing (kept for a fixed N_s)
      continue;
    }
    p.p = g.position[sm.pixel];
    p.n = g.normal[sm.pixel];
    const double dx = (sm.pixel % uint32_t(W)) + 0.5 - ctx.gaze_px.x,
                 dy = (sm.pixel / uint32_t(W)) + 0.5 - ctx.gaze_px.y;
    const double wr =
        (dx * dx + dy * dy <= fovea_px * fovea_px) ? s_.w_fovea : s_.w_periphery;  // eq. 1
    p.weight = float(sm.weight * wr);
    pts.push_back(p);
  }
  t0 = Clock::now();
  times_.sampling = ms_between(t1, t0);

  // §5: contributions (eq. 14) and stochastic culling.
  const float diag = fv.scene_diag;
  ContributionSettings cs;
  cs.visibility = s_.visibility;
  cs.blso = s_.blso;
  cs.eps2 = float(s_.epsilon * diag) * float(s_.epsilon * diag);
  cs.scene_scale = diag;
  cs.ray_offset = 1e-4f * diag;
  cs.seed = fseed;
  const std::vector<double> contrib =
      flc_contributions(fv.vpls, fv.rsms, pts, cs, ctx.renderer, &c);
  t1 = Clock::now();
  times_.contribution = ms_between(t0, t1);
  kept_ = flc_cull(contrib, s_.vpl_budget, s_.culling_floor, fseed ^ 0xc011ull);
  c.set(Counter::vpls_kept, double(kept_.kept.size()));
  selected_ = make_soa(fv.vpls, kept_.kept, kept_.weight);
  times_.culling = ms_between(t1, Clock::now());
}

void FlcLighting::set_history(const FrameContext& ctx, const Image& indirect) {
  ToneMap tm;
  tm.exposure = ctx.scene->exposure;
  tm.apply(indirect, ind_d_);
  const bool hist_ok = history_.width == indirect.width && history_.height == indirect.height;
  if (!hist_ok) history_ = Image(indirect.width, indirect.height, 1);
  const float a = hist_ok ? float(s_.history_blend) : 1.f;
  for (size_t i = 0; i < history_.data.size(); ++i) {
    const float* p = &ind_d_.data[i * 3];
    history_.data[i] = (1.f - a) * history_.data[i] + a * luma(p[0], p[1], p[2]);
  }
}

void FlcLighting::end_frame(const FrameContext& ctx, const Image& linear) {
  // eq. 8 history: the method's own indirect light, i.e. its image minus the direct light
  // (clamped at 0: reconstruction filters can undershoot).
  const Image& d = *ctx.direct;
  if (ind_.width != d.width || ind_.height != d.height || ind_.channels != 3)
    ind_.resize(d.width, d.height, 3);
  for (size_t i = 0; i < ind_.data.size(); ++i)
    ind_.data[i] = std::max(0.f, linear.data[i] - d.data[i]);
  set_history(ctx, ind_);
}

void FlcLighting::debug_images(std::vector<std::pair<std::string, Image>>& out) {
  if (!keep_debug_) return;
  out.emplace_back("importance", maps_.importance);
  out.emplace_back("acuity", maps_.acuity);
  out.emplace_back("silhouette", maps_.silhouette);
  out.emplace_back("brightness", maps_.brightness);
  out.emplace_back("indirect", ind_d_);
}

std::unique_ptr<LightingStrategy> create_lighting_flc(Params& p) {
  return std::make_unique<FlcLighting>(FlcLightingSettings::from_params(p));
}
const std::vector<ParamInfo>& lighting_flc_params() {
  return flc_lighting_params();
}

}  // namespace fovsim
