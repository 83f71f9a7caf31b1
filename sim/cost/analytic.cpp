// Analytic counters for each method (see the parameter table in analytic.h).
#include "sim/cost/analytic.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "sim/core/error.h"
#include "sim/cost/passes.h"
#include "sim/foveation/density.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/lighting.h"
#include "sim/foveation/mapping_spec.h"

namespace fovsim {

double fvrs_shaded_fraction(const Display& d, double gu, double gv, double r1, double r2) {
  if (d.width <= 0 || d.height <= 0) return 0;
  Camera cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
  glm::dvec3 g = gaze_dir_from_screen(d, gu, gv);
  const int nx = std::min(d.width, 256), ny = std::min(d.height, 256);
  double sum = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      double px = (i + 0.5) * d.width / nx, py = (j + 0.5) * d.height / ny;
      double e = cam.eccentricity_deg(px, py, g);
      sum += e < r1 ? 1.0 : (e < r2 ? 0.25 : 1.0 / 16.0);
    }
  return sum / (double(nx) * ny);
}

namespace {
// Keys that only `predict`/`budget`/calibration understand (assumptions replacing a rendered
// measurement), per cost family (method_list.h); every other key is the method's own.
std::vector<std::string> analytic_keys(CostFamily f) {
  switch (f) {
    case CostFamily::Mapping:  // shaded_fraction / gaze: baselines only (see below)
      return {"shaded_fraction", "gaze_u", "gaze_v", "filter_taps_per_pixel"};
    case CostFamily::Fvrs:
      return {"shaded_fraction", "gaze_u", "gaze_v"};
    case CostFamily::Twfr:
      return {"redraw_fraction", "prims_fraction"};
    default:
      return {};
  }
}

double column(const std::vector<std::pair<std::string, double>>& cols, const std::string& k,
              double def) {
  for (auto& [n, v] : cols)
    if (n == k) return v;
  return def;
}

// The method's columns, with an iso-budget target's free parameter as solved (`resolved`), and
// its lighting strategy's (flc: vpl_budget).
std::vector<std::pair<std::string, double>> method_columns(
    const FoveationMethod& inst, const std::optional<MappingSpec>& resolved) {
  std::vector<std::pair<std::string, double>> cols = inst.param_columns();
  if (resolved && inst.mapping_spec()->target_shaded_fraction() > 0)
    for (auto& [k, v] : resolved->columns())
      for (auto& c : cols)
        if (c.first == k) c.second = v;
  if (inst.lighting())
    for (auto& c : inst.lighting()->param_columns()) cols.push_back(c);
  return cols;
}

}  // namespace

// The iso-budget as a run resolves it (analytic.h).
MappingSpec resolved_mapping_spec(const MappingSpec& s, const Display& d) {
  if (!(s.target_shaded_fraction() > 0) || d.width <= 0 || d.height <= 0) return s;
  const Camera cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
  MappingView v = MappingView::at(cam, glm::dvec2(d.width * 0.5, d.height * 0.5));
  const std::vector<float> ecc = eccentricity_map(cam, v.gaze_dir);
  v.ecc = &ecc;
  MappingSpec r;
  solve_iso_budget(s, v, s.target_shaded_fraction(), r);
  return r;
}

Counters analytic_counters(const std::string& method, const Json& params, const Workload& w,
                           const Display& d, const std::string& where, bool indirect,
                           CostPasses* passes) {
  if (!is_cost_method(method)) throw Error(where, "unknown method '" + method + "'");
  const Json all = params.is_null() ? Json::object() : params;
  if (!all.is_object()) throw Error(where, "method parameters must be an object");
  // Split: analytic-only keys here; the rest goes through the method's own parser (the one
  // `run` uses: same keys, defaults and ranges; unknown or mistyped keys are errors). An
  // analytic key the method does not use (kfr:shaded_fraction) stays unread and is reported
  // by p.finish() below.
  Json own = Json::object(), extra = Json::object();
  const std::vector<std::string> ak = analytic_keys(cost_family(method));
  for (auto it = all.begin(); it != all.end(); ++it)
    (std::find(ak.begin(), ak.end(), it.key()) != ak.end() ? extra : own)[it.key()] = it.value();
  Params mp(own, where, "");
  const std::unique_ptr<FoveationMethod> inst = make_method(method, mp);
  const CostPasses decl = declared_passes(*inst);  // family, strategy passes, shared work
  const CostFamily fam = decl.family;
  if (passes) *passes = decl;
  // An iso-budget target is solved before the columns are read (sigma, radius_scale, ...).
  const std::optional<MappingSpec> resolved =
      inst->mapping_spec()
          ? std::optional<MappingSpec>(resolved_mapping_spec(*inst->mapping_spec(), d))
          : std::nullopt;
  const std::vector<std::pair<std::string, double>> cols = method_columns(*inst, resolved);
  // kfr/rmfr-style buffers (a whole (W/sigma) x (H/sigma) buffer is shaded) vs baselines whose
  // shaded samples follow their layers / probability: the method's SamplingGeometry says.
  const bool whole_buffer = resolved && resolved->geometry().shades_whole_buffer();
  Params p(extra, where, "");
  const double P = double(std::max(0, d.width)) * double(std::max(0, d.height));
  Counters c;
  auto shaded_frac_param = [&](double def) {
    double f = p.number("shaded_fraction", w.shaded_fraction >= 0 ? w.shaded_fraction : -1,
                        Range::closed(-1, 1));
    return f >= 0 ? f : def;
  };
  // The baselines' shaded fraction from their real parameters at a gaze point (the same
  // geometry their render passes use, density.h), unless given.
  auto baseline_fraction = [&](double def_if_empty) {
    const double gu = p.number("gaze_u", 0.5, Range::closed(-1, 2)),
                 gv = p.number("gaze_v", 0.5, Range::closed(-1, 2));
    double f = shaded_frac_param(-1);
    if (f >= 0 || P <= 0) return f >= 0 ? f : def_if_empty;
    const MappingSpec* spec = resolved ? &*resolved : nullptr;
    if (!spec) return def_if_empty;
    Camera cam = Camera::from_pose(d, glm::dvec3(0), glm::dquat(1, 0, 0, 0));
    MappingView v = MappingView::at(cam, {gu * d.width, gv * d.height});
    if (fam == CostFamily::Fvrs)
      return fvrs_shaded_fraction(d, gu, gv, column(cols, "r1", 10), column(cols, "r2", 20));
    return expected_shaded_samples(*spec, v) / P;
  };
  if (fam == CostFamily::Full) {
    c.set(Counter::shaded_samples, P);
    c.set(Counter::gbuffer_samples, P);
  } else if (fam == CostFamily::Mapping) {
    // KFR/RMFR: the w x h = (W/sigma) x (H/sigma) buffer is fully shaded (Meng 2018 §2.2,
    // Ye et al. 2022 §3.2); the baselines shade what their layers / sample pattern need.
    const double sigma = column(cols, "sigma", 1.0);
    const double buf = P / (sigma * sigma);
    const double s = whole_buffer ? buf : baseline_fraction(1.0) * P;
    c.set(Counter::shaded_samples, s);
    c.set(Counter::gbuffer_samples, s);
    c.set(Counter::buffer_pixels_allocated, whole_buffer ? buf : s);
    c.set(Counter::buffer_pixels_used, s);
    c.set(Counter::fullres_pixels, P);
    // Total taps of pass 2 (bilinear inverse map: 4 per full-resolution pixel).
    c.set(Counter::filter_taps, P * p.number("filter_taps_per_pixel", 4, Range::at_least(0)));
  } else if (fam == CostFamily::Fvrs) {
    c.set(Counter::shaded_samples, baseline_fraction(1.0) * P);
    c.set(Counter::gbuffer_samples, P);
  } else if (fam == CostFamily::Twfr) {
    double rf = p.number("redraw_fraction", w.twfr_redraw_fraction, Range::closed(0, 1));
    double pf = p.number("prims_fraction", w.twfr_prims_fraction, Range::closed(0, 1));
    double T = std::max(0.0, w.triangles) * w.submitted_fraction;
    c.set(Counter::shaded_samples, rf * P);
    c.set(Counter::gbuffer_samples, rf * P);
    c.set(Counter::pixels_redrawn, rf * P);
    c.set(Counter::reprojected_pixels, P);
    c.set(Counter::prims_submitted, pf * T);
    c.set(Counter::prims_culled, (1 - pf) * T);
  } else if (fam == CostFamily::Flc) {
    double lights = std::max(1.0, w.lights);
    double total = w.rsm_res * w.rsm_res * lights;  // one VPL per RSM texel (Yang et al. 2021 §3)
    // The budget given on the command line (validated by FLC's parser), else the workload's.
    const double budget =
        own.contains("vpl_budget") ? column(cols, "vpl_budget", w.vpl_budget) : w.vpl_budget;
    double kept = std::min(total, budget);
    double ns = w.importance_samples;
    double s = P * w.lpt_fraction;
    c.set(Counter::shaded_samples, s);
    c.set(Counter::gbuffer_samples, P);
    c.set(Counter::rsm_texels, total);
    c.set(Counter::vpls_total, total);
    c.set(Counter::vpls_kept, kept);
    // The strategy's selection counters: eq. 14 for every VPL and sample, BLSO lookups.
    if (const LightingStrategy* L = inst->lighting()) L->analytic_selection_counters(c, total, ns);
    c.set(Counter::shaded_sample_vpls, s * kept / w.interleave);  // interleaved sampling (§6)
  }
  if (indirect && decl.frame_rsm && fam != CostFamily::Flc) {
    // One lighting model per scene: the method's samples also get the indirect light of its
    // strategy (lighting.h). all_vpls (the default) shades every VPL; flc / fir keep at most
    // their budget and pay for importance sampling and per-VPL culling.
    const double total = w.rsm_res * w.rsm_res * std::max(1.0, w.lights);  // FLC paper §3
    const LightingStrategy* L = inst->lighting();
    double kept = total;
    c.set(Counter::rsm_texels, total);
    c.set(Counter::vpls_total, total);
    if (L && (decl.importance || decl.culling)) {
      kept = std::min(total, column(cols, "vpl_budget", w.vpl_budget));
      // The strategy's own selection passes (flc: importance + eq. 14 contributions; fir: one
      // importance per VPL), declared by the strategy.
      L->analytic_selection_counters(c, total, w.importance_samples);
    }
    c.set(Counter::vpls_kept, kept);
    c.set(Counter::shaded_sample_vpls, c.get(Counter::shaded_samples) * kept);
  }
  p.finish();
  return c;
}

FrameCost analytic_frame(const GpuProfile& gpu, const std::string& method, const Json& params,
                         const Workload& w, const Display& d, const std::string& where,
                         bool indirect) {
  CostInputs in;
  const Counters c = analytic_counters(method, params, w, d, where, indirect, &in.passes.emplace());
  in.features.indirect = indirect;
  in.method = method;
  in.counters = &c;
  in.display = d;
  in.workload = &w;
  return estimate_frame(gpu, in);
}

}  // namespace fovsim
