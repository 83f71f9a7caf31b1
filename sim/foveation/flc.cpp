// `flc`: Foveated Light Culling (seed 001, Yang et al. 2021). Per frame: RSM per light -> VPLs
// (§3), importance map (§4.1, eqs. 3-9), quasi-MH sample selection (§4.2, Alg. 1), VPL
// contributions with BLSO visibility (§5, eqs. 10-14), stochastic culling to `vpl_budget`,
// indirect shading with the kept VPLs (optionally log-polar + interleaved, §6), added to the
// shared direct-light reference. Ground truth (the seed's TBDS role) = direct + indirect from
// ALL VPLs; it is returned in FrameOutput::reference.
//
// Parameters: the declaration flc_params() at the end of this file (name, type, default,
// range, seed section, meaning); docs/methods.md and configs/README.md are generated from it.
#include "sim/foveation/flc.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <memory>
#include <mutex>
#include <sstream>

#include "sim/core/hash.h"
#include "sim/core/rng.h"
#include "sim/foveation/flc_contribution.h"
#include "sim/foveation/flc_importance.h"
#include "sim/foveation/flc_sampling.h"
#include "sim/foveation/flc_shading.h"
#include "sim/foveation/methods.h"
#include "sim/render/rsm.h"
#include "sim/render/vpl.h"

namespace fovsim {
namespace {

struct FlcSettings {
  int vpl_budget = 1024, rsm_size = 64, samples = 256, chain_length = 16;
  FlcImportanceParams imp;
  double history_blend = 0.5, w_fovea = 1.0, w_periphery = 1.0, epsilon = 0.02;
  FlcVisibility visibility = FlcVisibility::Blso;
  BlsoParams blso;
  double culling_floor = 0.02, min_dist = 0.01;
  bool shading_visibility = false, log_polar = false;
  double lp_sigma = 2.0;
  int interleave = 1;
  uint64_t seed = 1;
};

// Ground-truth indirect images shared by every FLC instance (a sweep over budgets renders the
// same frame many times). Keyed by everything the image depends on; a few entries only.
class GroundTruthCache {
 public:
  std::shared_ptr<const Image> get(const std::string& key) {
    std::lock_guard<std::mutex> lk(mu_);
    for (auto& e : entries_)
      if (e.first == key) return e.second;
    return nullptr;
  }
  void clear() {
    std::lock_guard<std::mutex> lk(mu_);
    entries_.clear();
  }
  void put(const std::string& key, std::shared_ptr<const Image> img) {
    std::lock_guard<std::mutex> lk(mu_);
    for (auto& e : entries_)
      if (e.first == key) return;
    entries_.emplace_back(key, std::move(img));
    while (entries_.size() > 2) entries_.pop_front();
  }

 private:
  std::mutex mu_;
  std::deque<std::pair<std::string, std::shared_ptr<const Image>>> entries_;
};
GroundTruthCache& gt_cache() {
  static GroundTruthCache c;
  return c;
}

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

class FlcMethod final : public FoveationMethod {
 public:
  explicit FlcMethod(const FlcSettings& s) : s_(s) {}
  std::string name() const override { return "flc"; }
  uint32_t required_channels() const override { return kShadingChannels; }
  bool temporal() const override { return true; }
  void reset() override { history_ = Image(); }
  std::vector<std::pair<std::string, double>> param_columns() const override {
    return {{"vpl_budget", s_.vpl_budget},
            {"rsm_size", s_.rsm_size},
            {"blso", s_.visibility == FlcVisibility::Blso ? 1.0 : 0.0},
            {"visibility_code", double(int(s_.visibility))},
            {"samples", s_.samples},
            {"chain_length", s_.chain_length},
            {"log_polar", s_.log_polar ? 1.0 : 0.0},
            {"lp_sigma", s_.log_polar ? s_.lp_sigma : 1.0},
            {"interleave", s_.interleave}};
  }

  void render(const FrameContext& ctx, FrameOutput& out) override {
    const GBuffer& g = *ctx.gbuffer;
    const Renderer& r = *ctx.renderer;
    const Scene& scene = *ctx.scene;
    const int W = g.width, H = g.height;
    Counters& c = out.counters;
    const uint64_t fseed = splitmix64(s_.seed ^ splitmix64(uint64_t(ctx.frame) + 0x51ull));
    times_ = FlcStageTimes();
    auto t0 = Clock::now();

    // S-1, S-2: RSMs and VPLs.
    const AABB bounds = scene_bounds(r);
    const float diag = bounds.empty() ? 1.f : std::max(1e-6f, glm::length(bounds.hi - bounds.lo));
    std::vector<RSM> rsms;
    std::vector<VPL> vpls;
    for (size_t li = 0; li < scene.lights.size(); ++li) {
      rsms.emplace_back();
      render_rsm(r, int(li), s_.rsm_size, bounds, rsms.back(), &c);
      vpls_from_rsm(rsms.back(), vpls);
    }
    c.set("vpls_total", double(vpls.size()));
    auto t1 = Clock::now();
    times_.rsm = ms_between(t0, t1);
    VplShading sh;
    sh.min_dist = float(s_.min_dist) * diag;
    sh.visibility = s_.shading_visibility;
    sh.ray_offset = 1e-4f * diag;

    // Ground truth: direct + indirect from all VPLs (TBDS role, §7).
    std::ostringstream key;
    key.precision(17);
    const Camera& cam = *ctx.camera;
    key << &scene << '|' << &r << '|' << r.time() << '|' << W << 'x' << H << '|' << cam.position.x
        << ',' << cam.position.y << ',' << cam.position.z << '|' << cam.orientation.w << ','
        << cam.orientation.x << ',' << cam.orientation.y << ',' << cam.orientation.z << '|'
        << cam.tan_half_h << ',' << cam.tan_half_v << '|' << s_.rsm_size << '|' << s_.min_dist
        << '|' << s_.shading_visibility << '|' << scene.name << '|' << scene.triangle_count() << '|'
        << vpls.size();
    // Light content too, so a different scene that reuses an address never hits a stale entry.
    for (const RSM& m : rsms)
      key << '|' << m.ls.position.x << ',' << m.ls.position.y << ',' << m.ls.position.z << ','
          << m.ls.direction.x << ',' << m.ls.direction.y << ',' << m.ls.direction.z << ','
          << m.ls.radiance.x << ',' << m.ls.radiance.y << ',' << m.ls.radiance.z;
    std::shared_ptr<const Image> gt_ind = gt_cache().get(key.str());
    if (!gt_ind) {
      auto img = std::make_shared<Image>();
      Counters gc;
      shade_indirect(g, make_soa(vpls), sh, *img, &r, nullptr, &gc);
      gt_ind = img;
      gt_cache().put(key.str(), gt_ind);
    }
    t0 = Clock::now();
    times_.ground_truth = ms_between(t1, t0);

    // §4.1: importance map from the display-encoded direct frame and the indirect history.
    ToneMap tm;
    tm.exposure = scene.exposure;
    Image color;
    tm.apply(*ctx.reference, color);
    const double tan_diag =
        std::sqrt(cam.tan_half_h * cam.tan_half_h + cam.tan_half_v * cam.tan_half_v);
    FlcImportanceMaps maps;
    const bool hist_ok = history_.width == W && history_.height == H;
    flc_importance_map(g, color, hist_ok ? &history_ : nullptr, ctx.gaze_px, tan_diag,
                       ctx.eccentricity, s_.imp, maps, ctx.want_debug);

    t1 = Clock::now();
    times_.importance = ms_between(t0, t1);
    // §4.2, Alg. 1: N_s chains of length M over shuffled Halton points.
    const std::vector<glm::vec2> halton =
        shuffled_halton(size_t(s_.samples) * size_t(s_.chain_length), fseed);
    const std::vector<ImportanceSample> samples =
        flc_select_samples(maps.importance, halton, s_.samples, s_.chain_length);
    c.set("importance_samples", double(samples.size()));
    c.set("halton_proposals", double(halton.size()));
    const double half_diag = 0.5 * std::sqrt(double(W) * W + double(H) * H);
    const double fovea_px = s_.imp.fovea_frac * half_diag;
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
    ContributionSettings cs;
    cs.visibility = s_.visibility;
    cs.blso = s_.blso;
    cs.eps2 = float(s_.epsilon * diag) * float(s_.epsilon * diag);
    cs.scene_scale = diag;
    cs.ray_offset = 1e-4f * diag;
    cs.seed = fseed;
    const std::vector<double> contrib = flc_contributions(vpls, rsms, pts, cs, &r, &c);
    t1 = Clock::now();
    times_.contribution = ms_between(t0, t1);
    const CullResult kept = flc_cull(contrib, s_.vpl_budget, s_.culling_floor, fseed ^ 0xc011ull);
    c.set("vpls_kept", double(kept.kept.size()));

    t0 = Clock::now();
    times_.culling = ms_between(t1, t0);
    // S-7: shading with the kept VPLs.
    const int n = s_.interleave;
    const std::vector<VplSoA> groups = flc_interleave_groups(vpls, kept.kept, kept.weight, n);
    Image indirect, lp_dbg;
    if (s_.log_polar)
      flc_shade_logpolar(g, ctx.gaze_px, s_.lp_sigma, groups, n, sh, &r, indirect, &c,
                         ctx.want_debug ? &lp_dbg : nullptr);
    else
      flc_shade_cartesian(g, groups, n, sh, &r, indirect, &c);

    t1 = Clock::now();
    times_.shading = ms_between(t0, t1);
    const Image& direct = *ctx.reference;
    out.image.resize(W, H, 3);
    Image gt(W, H, 3);
    const size_t N = size_t(W) * size_t(H) * 3;
    for (size_t i = 0; i < N; ++i) {
      out.image.data[i] = direct.data[i] + indirect.data[i];
      gt.data[i] = direct.data[i] + gt_ind->data[i];
    }

    // Own tau (Table 1) on display-encoded images, fovea = the eq. 5 region.
    Image od, gd;
    tm.apply(out.image, od);
    tm.apply(gt, gd);
    const double rf = rmse_region(od, gd, ctx.gaze_px, fovea_px, true);
    const double rp = rmse_region(od, gd, ctx.gaze_px, fovea_px, false);
    c.set("flc_rmse_fovea", rf);
    c.set("flc_rmse_periphery", rp);
    c.set("flc_tau", (rp + 1e-6) / (rf + 1e-6));  // regularised: 1 when both are 0

    // eq. 8 history: accumulated tone-mapped luma of the indirect light.
    Image ind_d;
    tm.apply(indirect, ind_d);
    if (!hist_ok) history_ = Image(W, H, 1);
    const float a = hist_ok ? float(s_.history_blend) : 1.f;
    for (size_t i = 0; i < g.size(); ++i) {
      const float* p = &ind_d.data[i * 3];
      history_.data[i] = (1.f - a) * history_.data[i] + a * luma(p[0], p[1], p[2]);
    }

    const double px = double(W) * double(H);
    c.set("gbuffer_samples", px);
    c.set("fullres_pixels", px);
    c.set("direct_shaded_samples", px);
    c.set("lights", double(scene.lights.size()));
    out.reference = std::move(gt);
    times_.compose = ms_between(t1, Clock::now());
    if (ctx.want_debug) {
      out.debug.emplace_back("importance", std::move(maps.importance));
      out.debug.emplace_back("acuity", std::move(maps.acuity));
      out.debug.emplace_back("silhouette", std::move(maps.silhouette));
      out.debug.emplace_back("brightness", std::move(maps.brightness));
      out.debug.emplace_back("indirect", std::move(ind_d));
      if (!lp_dbg.empty()) {
        Image lpd;
        tm.apply(lp_dbg, lpd);
        out.debug.emplace_back("lp_buffer", std::move(lpd));
      }
    }
  }

  const FlcStageTimes& times() const { return times_; }

 private:
  FlcSettings s_;
  Image history_;  // eq. 8 b(p), 1 channel
  FlcStageTimes times_;
};

}  // namespace

const FlcStageTimes* flc_stage_times(const FoveationMethod& m) {
  const auto* f = dynamic_cast<const FlcMethod*>(&m);
  return f ? &f->times() : nullptr;
}
void flc_clear_ground_truth_cache() {
  gt_cache().clear();
}

std::unique_ptr<FoveationMethod> create_flc(Params& p) {
  FlcSettings s;
  s.vpl_budget = p.integer("vpl_budget", 1024, Range::closed(0, 1e6));
  s.rsm_size = p.integer("rsm_size", 64, Range::closed(1, 1024));
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
  s.min_dist = p.number("min_dist", 0.01, Range::above(0, 1));
  s.shading_visibility = p.boolean("shading_visibility", false);
  s.log_polar = p.boolean("log_polar", false);
  s.lp_sigma = p.number("lp_sigma", 2.0, Range::closed(1, 32));
  s.interleave = p.integer("interleave", 1, Range::closed(1, 2));
  s.seed = uint64_t(p.integer("seed", 1, Range::closed(0, 2e9)));
  return std::make_unique<FlcMethod>(s);
}

const std::vector<ParamInfo>& flc_params() {
  static const std::vector<ParamInfo> t = {
      {"vpl_budget", "int", "1024", "[0, 1e6]", "§7 Fig. 7", "VPLs kept for shading"},
      {"rsm_size", "int", "64", "[1, 1024]", "§7", "RSM texels per edge per light"},
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
      {"min_dist", "number", "0.01", "(0, 1]", "S-7", "distance clamp / scene diagonal"},
      {"shading_visibility", "bool", "false", "", "beyond seed", "shadow rays in VPL shading"},
      {"log_polar", "bool", "false", "", "§6", "log-polar shading"},
      {"lp_sigma", "number", "2", "[1, 32]", "§6", "log-polar buffer reduction"},
      {"interleave", "int", "1", "[1, 2]", "§6", "interleaved sampling n"},
      {"seed", "int", "1", "[0, 2e9]", "", "random seed"},
  };
  return t;
}

}  // namespace fovsim
