// `flc` lighting strategy (lighting_flc.h): Yang et al., "Foveated light culling", §4-§5.
#include "sim/foveation/lighting_flc.h"

#include <chrono>
#include <cmath>

#include "sim/core/hash.h"
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

FlcLightingSettings FlcLightingSettings::from_params(Params& p) {
  FlcLightingSettings s;
  s.vpl_budget = p.integer("vpl_budget", 1024, Range::closed(0, 1e6));
  s.samples = p.integer("samples", 256, Range::closed(1, 1e6));
  s.chain_length = p.integer("chain_length", 16, Range::closed(1, 4096));
  s.imp.omega_p = p.number("omega_p", 0.2, Range::closed(0, 1));
  s.imp.slope = p.number("acuity_slope", 2.25, Range::closed(0, 1e3));
  s.imp.fovea_frac = p.number("fovea_frac", 150.0 / (512.0 * std::sqrt(2.0)), Range::above(0, 10));
  s.imp.exact_eccentricity = p.string("eccentricity", "seed", {"seed", "exact"}) == "exact";
  s.imp.silhouette_value = p.number("silhouette_value", 1.0, Range::closed(0, 1));
  s.imp.depth_threshold = p.number("depth_threshold", 0.05, Range::above(0, 1e6));
  s.imp.normal_threshold_deg = p.number("normal_threshold_deg", 30.0, Range::closed(0, 180));
  s.imp.color_threshold = p.number("color_threshold", 48.0, Range::closed(0, 1e6));
  s.imp.delta = p.number("delta", 20.0, Range::closed(0, 1e6));
  s.history_blend = p.number("history_blend", 0.5, Range::above(0, 1));
  s.w_fovea = p.number("w_fovea", 1.0, Range::closed(0, 1e6));
  s.w_periphery = p.number("w_periphery", 1.0, Range::closed(0, 1e6));
  s.epsilon = p.number("epsilon", 0.02, Range::above(0, 1));
  const std::string vis = p.string("visibility", "blso", {"none", "blso", "exact"});
  s.visibility = vis == "none" ? FlcVisibility::None
                               : (vis == "exact" ? FlcVisibility::Exact : FlcVisibility::Blso);
  s.blso.lambda = p.number("blso_lambda", 0.5, Range::closed(0, 1));
  s.blso.k = p.number("blso_k", 34.0, Range::above(0, 1e6));
  s.blso.xi = p.number("blso_xi", 0.01, Range::above(0, 1));
  s.blso.radius = p.number("blso_radius", 0.1, Range::above(0, 10));
  s.blso.cone_deg = p.number("blso_cone_deg", 30.0, Range::above(0, 90));
  s.blso.samples = p.integer("blso_samples", 4, Range::closed(1, 256));
  s.culling_floor = p.number("culling_floor", 0.02, Range::closed(0, 1));
  s.seed = uint64_t(p.integer("seed", 1, Range::closed(0, 2e9)));
  return s;
}

const std::vector<ParamInfo>& flc_lighting_params() {
  static const std::vector<ParamInfo> t = {
      {"vpl_budget", "int", "1024", "[0, 1e6]", "§7 Fig. 7", "VPLs kept for shading"},
      {"samples", "int", "256", "[1, 1e6]", "Alg. 1", "N_s importance samples"},
      {"chain_length", "int", "16", "[1, 4096]", "Alg. 1", "M proposals per chain"},
      {"omega_p", "number", "0.2", "[0, 1]", "eq. 3", "acuity floor"},
      {"acuity_slope", "number", "2.25", "[0, 1e3]", "eq. 4", "acuity slope s (1/rad)"},
      {"fovea_frac", "number", "0.2072", "(0, 10]", "eq. 5", "foveal radius / half diagonal"},
      {"eccentricity", "string", "seed", "seed, exact", "eq. 6", "eccentricity model"},
      {"silhouette_value", "number", "1", "[0, 1]", "§4.1.2", "p_g on silhouettes"},
      {"depth_threshold", "number", "0.05", "(0, 1e6]", "§4.1.2", "relative depth jump"},
      {"normal_threshold_deg", "number", "30", "[0, 180]", "§4.1.2", "normal angle"},
      {"color_threshold", "number", "48", "[0, 1e6]", "eq. 7", "colour difference"},
      {"delta", "number", "20", "[0, 1e6]", "eq. 8", "indirect brightness factor"},
      {"history_blend", "number", "0.5", "(0, 1]", "eq. 8", "weight of the newest frame in b(p)"},
      {"w_fovea", "number", "1", "[0, 1e6]", "eq. 1", "fovea sample weight"},
      {"w_periphery", "number", "1", "[0, 1e6]", "eq. 1", "periphery sample weight"},
      {"epsilon", "number", "0.02", "(0, 1]", "eq. 10", "sqrt(eps) / scene diagonal"},
      {"visibility", "string", "blso", "none, blso, exact", "eq. 11", "visibility in eq. 14"},
      {"blso_lambda", "number", "0.5", "[0, 1]", "eq. 11", "mix coefficient"},
      {"blso_k", "number", "34", "(0, 1e6]", "eq. 12", "attenuation factor"},
      {"blso_xi", "number", "0.01", "(0, 1]", "eq. 12", "threshold / scene diagonal"},
      {"blso_radius", "number", "0.1", "(0, 10]", "§5", "local radius / scene diagonal"},
      {"blso_cone_deg", "number", "30", "(0, 90]", "§5", "local cone half-angle"},
      {"blso_samples", "int", "4", "[1, 256]", "eq. 13", "N' per side"},
      {"culling_floor", "number", "0.02", "[0, 1]", "§5", "uniform share of culling probabilities"},
      {"seed", "int", "1", "[0, 2e9]", "", "random seed"},
  };
  return t;
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
  c.set("vpls_total", double(fv.vpls.size()));
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
  c.set("importance_samples", double(samples.size()));
  c.set("halton_proposals", double(halton.size()));
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
  c.set("vpls_kept", double(kept_.kept.size()));
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
