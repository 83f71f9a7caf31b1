// Calibration of GPU profiles against the seeds' tables (see calibration.h).
#include "sim/cost/calibration.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "sim/core/error.h"
#include "sim/cost/analytic.h"
#include "sim/cost/nnls.h"
#include "sim/cost/passes.h"
#include "sim/foveation/factory.h"

namespace fovsim {

namespace {

Display parse_display(Params& p, const std::string& key, const std::string& models_dir) {
  const Json& j = p.raw(key);
  if (j.is_string()) return Display::load(j.get<std::string>(), models_dir);
  Params d(j, p.file(), p.path_of(key));
  return Display::from_params(d);
}

Workload apply_overrides(const Workload& w, const Json& ov, const std::string& where) {
  if (!ov.is_object() || ov.empty()) return w;
  Json j = w.to_json();
  j.merge_patch(ov);
  Params p(j, "", where);
  Workload r = Workload::from_params(p);
  p.finish();
  return r;
}

// A table's baseline rows are those of the full-resolution pipeline (CostPasses::full_resolution
// in the method's declaration).
bool is_baseline_method(const std::string& m) {
  const MethodEntry* e = find_method(m);
  return e && e->cost().passes.full_resolution;
}

}  // namespace

std::string fitted_param(const Workload& w) {
  return w.vpl_flops >= 0 ? "vpl_flops" : "shading_flops";
}

// Long because: it reads models/calibration (gpu_specs.json, then each table's configs, entries
// and withheld figures) with a located error for every reference between them (a table's GPU,
// an entry's config, workload and passes); it reads top to bottom like the files' schema
// (docs/cost_model.md).
CalData load_calibration(const std::string& models_dir) {
  CalData d;
  d.models_dir = models_dir;
  {
    std::string f = models_dir + "/calibration/gpu_specs.json";
    Params p = Params::from_file(f);
    p.ignore("comment");
    Params g = p.child("gpus");
    for (auto it = g.json().begin(); it != g.json().end(); ++it) {
      Params s = g.child(it.key());
      GpuSpecEntry e;
      e.description = s.string("description", "");
      auto pos = Range::above(0);
      e.spec.fp32_gflops = s.number("fp32_gflops", pos);
      e.spec.mem_gbps = s.number("mem_gbps", pos);
      e.spec.fill_gpix = s.number("fill_gpix", pos);
      e.spec.tri_gtris = s.number("tri_gtris", pos);
      e.spec.boost_mhz = s.number("boost_mhz", 0, Range::at_least(0));
      e.spec.l2_mb = s.number("l2_mb", 0, Range::at_least(0));
      e.widen = s.number("extrapolation_widen", 1.0, Range::closed(1, 10));
      e.architecture = s.string("architecture", "");
      e.spec.source = s.string("source", "");
      d.specs[it.key()] = e;
    }
    p.finish();
  }
  std::vector<std::string> files;
  for (auto& e : std::filesystem::directory_iterator(models_dir + "/calibration"))
    if (e.path().extension() == ".json" && e.path().filename() != "gpu_specs.json")
      files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  for (auto& f : files) {
    Params p = Params::from_file(f);
    CalTable t;
    t.file = f;
    t.json = p.json();
    t.id = p.string("id");
    t.source = p.string("source");
    t.gpu = p.string("gpu");
    if (!d.specs.count(t.gpu)) p.fail("gpu", "unknown GPU '" + t.gpu + "' (not in gpu_specs.json)");
    Display disp = parse_display(p, "display", models_dir);
    std::vector<std::string> wls;
    if (p.has("workload")) wls.push_back(p.string("workload"));
    if (p.has("workloads"))
      for (auto& v : p.raw("workloads")) wls.push_back(v.get<std::string>());
    for (auto& w : wls)
      if (!d.workloads.count(w)) d.workloads[w] = Workload::load(w, models_dir);
    Params cfgs = p.child("configs");
    std::map<std::string, Json> cfg_json;
    for (auto it = cfgs.json().begin(); it != cfgs.json().end(); ++it) {
      Params c = cfgs.child(it.key());
      std::string m = c.string("method", cost_methods());
      if (c.has("params")) c.raw("params");
      c.ignore("comment");
      if (c.has("workload_overrides")) c.raw("workload_overrides");
      c.finish();
      cfg_json[it.key()] = it.value();
    }
    int k = 0;
    for (Params e : p.children("entries")) {
      CalEntry ce;
      ce.table = t.id;
      ce.gpu = t.gpu;
      ce.display = disp;
      ce.row = e.string("row");
      ce.config = e.string("config");
      if (!cfg_json.count(ce.config)) e.fail("config", "unknown config '" + ce.config + "'");
      const Json& cj = cfg_json[ce.config];
      ce.method = cj.at("method").get<std::string>();
      if (cj.contains("params")) ce.params = cj.at("params");
      if (cj.contains("workload_overrides")) ce.workload_overrides = cj.at("workload_overrides");
      ce.baseline = is_baseline_method(ce.method);
      ce.workload = e.string("workload", wls.empty() ? "" : wls.front());
      if (!d.workloads.count(ce.workload))
        e.fail("workload", "unknown workload '" + ce.workload + "'");
      const Json& ps = e.raw("passes");
      if (ps.is_array()) {
        for (auto& v : ps) {
          std::string pn = v.get<std::string>();
          if (!is_known_pass(pn)) e.fail("passes", "unknown pass '" + pn + "'");
          ce.passes.push_back(pn);
        }
      } else if (!(ps.is_string() && ps.get<std::string>() == "all")) {
        e.fail("passes", "must be an array of pass names or \"all\"");
      }
      // "all" but these: a published total that leaves out work the model charges (KFR
      // thesis Table 4.1 "Total" lists the passes; "Total GPU Time" adds the frame's rest).
      if (e.has("except")) {
        if (!ce.passes.empty()) e.fail("except", "only with \"passes\": \"all\"");
        for (auto& v : e.raw("except")) {
          std::string pn = v.is_string() ? v.get<std::string>() : std::string();
          if (!is_known_pass(pn)) e.fail("except", "unknown pass '" + pn + "'");
          ce.except.push_back(pn);
        }
      }
      ce.published_ms = e.number("ms", Range::at_least(0));
      ce.fit = e.string("use", "fit", {"fit", "check"}) == "fit";
      e.ignore("comment");
      ce.id = t.id + ":" + ce.workload + ":" + ce.config + ":" + ce.row;
      (void)k++;
      t.entries.push_back(ce);
    }
    // Withheld figures (predicted only); `workloads` (optional) names scenes of the figure that
    // no table row uses (e.g. KFR's ray-marching scene), default: the table's workloads.
    if (p.has("withheld"))
      for (Params w : p.children("withheld")) {
        w.string("id");
        w.ignore("what");
        if (w.has("display")) w.raw("display");
        if (w.has("params")) w.raw("params");
        w.raw("configs");
        if (w.has("workloads"))
          for (auto& v : w.raw("workloads")) {
            const std::string wl = v.get<std::string>();
            if (!d.workloads.count(wl)) d.workloads[wl] = Workload::load(wl, models_dir);
          }
        w.finish();
      }
    p.finish();
    d.tables.push_back(t);
  }
  return d;
}

// A published row's method keys with its TAA as the paper's pipeline had it: the workload's
// pipeline.taa (Table 3 of Ye et al. 2022 and Table 2 of Franke et al. 2021 list a TAA pass,
// Meng 2018 Table 4.1 does not), not the method's default (docs/methods.md "Temporal
// anti-aliasing"), so the fit explains the published passes and no others.
static Json paper_params(const CalEntry& e, const Workload& w) {
  Json p = e.params.is_null() ? Json::object() : e.params;
  const MethodEntry* m = find_method(e.method);
  if (!m || !p.is_object() || p.contains("taa")) return p;
  for (const ParamInfo& i : m->params())
    if (std::string(i.name) == "taa") p["taa"] = w.pipeline.taa;
  return p;
}

Workload entry_workload(const CostFit& fit, const CalData& data, const CalEntry& e) {
  auto it = fit.workloads.find(e.workload);
  const Workload& base = it != fit.workloads.end() ? it->second : data.workloads.at(e.workload);
  return apply_overrides(base, e.workload_overrides, e.id + ": workload_overrides");
}

double entry_ms(const GpuProfile& g, const Workload& w, const CalEntry& e, FrameCost* out) {
  CostInputs in;
  Counters c = analytic_counters(e.method, paper_params(e, w), w, e.display, e.id, false,
                                 &in.passes.emplace());
  in.method = e.method;
  in.counters = &c;
  in.display = e.display;
  in.workload = &w;
  FrameCost fc = estimate_frame(g, in);
  double ms = 0;
  if (e.passes.empty()) {
    ms = fc.total_ms;
    for (auto& p : e.except) ms -= fc.pass_ms(p);
  } else {
    for (auto& p : e.passes) {
      bool found = false;
      for (auto& pc : fc.passes) found |= pc.pass == p;
      if (!found) throw Error(e.id, "pass '" + p + "' does not exist for this workload and method");
      ms += fc.pass_ms(p);
    }
  }
  if (out) *out = fc;
  return ms;
}

GpuProfile profile_from_fit(const CostFit& fit, const std::string& gpu, const CalData& data) {
  const GpuSpecEntry& se = data.specs.at(gpu);
  GpuProfile g;
  g.model = fit.model;
  g.name = gpu;
  g.description = se.description;
  g.spec = se.spec;
  for (const std::string& pass : known_passes()) {
    PassCoef pc;
    auto oh = fit.theta.find(pass + ".overhead_ms");
    pc.overhead_ms = oh == fit.theta.end() ? 0 : oh->second;
    // A pass no fitted row measured: its nominal work at the pooled efficiency (prior_theta);
    // the frame's rest (present, UI) has no nominal work and stays 0.
    const bool unseen = fit.unseen(pass);
    if (unseen) pc.overhead_ms = pass == "frame" ? 0.0 : fit.prior_overhead_ms;
    // Every term the model knows for this pass.
    for (const std::string& term : term_names()) {
      const std::optional<Resource> r = find_term_resource(pass, term);
      if (!r) continue;
      double rate = se.spec.rate_per_ms(*r);
      if (pass == "lighting") {  // unit work: the workload carries the (fitted) flops
        pc.terms[term] = 1.0 / rate;
        continue;
      }
      if (unseen) {
        pc.terms[term] = prior_theta(fit, pass, term) / rate;
        continue;
      }
      auto t = fit.theta.find(pass + "." + term);
      // Roofline: a resource that never bottlenecked a calibration row runs at peak (floor).
      double floor = fit.model == CostModelKind::Roofline ? theta_floor(pass, term) : 0.0;
      pc.terms[term] = (t == fit.theta.end() ? floor : std::max(floor, t->second)) / rate;
    }
    g.passes[pass] = pc;
  }
  return g;
}

double predict_entry(const CostFit& fit, const CalData& data, const CalEntry& e) {
  return entry_ms(profile_from_fit(fit, e.gpu, data), entry_workload(fit, data, e), e);
}

namespace {

// One design-matrix row: columns by name, constant part (fixed coefficients), target.
struct Row {
  std::map<std::string, double> x;
  std::map<std::string, double> floor;  // lower bound of theta per column (roofline)
  double fixed = 0, y = 0;
};

Row design_row(const CostFit& fit, const CalData& data, const CalEntry& e) {
  Workload w = entry_workload(fit, data, e);
  const std::string fp = fitted_param(w);
  const bool fitted_wl = fit.fitted_workloads.count(e.workload) > 0;
  Workload wu = w;  // unit shading cost for the fitted parameter: its column is the cost
  if (fitted_wl) (fp == "vpl_flops" ? wu.vpl_flops : wu.shading_flops) = 1.0;
  if (fitted_wl) wu.tri_cost = 1.0;  // its G-buffer triangle work is the column "geo:<workload>"
  auto col = [&](const std::string& pass, const std::string& term) {
    return fitted_wl && pass == "gbuffer" && term == "tris" ? "geo:" + e.workload
                                                            : pass + "." + term;
  };
  const GpuSpec& spec = data.specs.at(e.gpu).spec;
  CostInputs in;
  Counters c = analytic_counters(e.method, paper_params(e, w), w, e.display, e.id, false,
                                 &in.passes.emplace());
  in.method = e.method;
  in.counters = &c;
  in.display = e.display;
  in.workload = &wu;
  Row r;
  r.y = e.published_ms;
  for (const PassWork& pw : assemble_passes(in, wu)) {
    if (!e.passes.empty() && std::find(e.passes.begin(), e.passes.end(), pw.pass) == e.passes.end())
      continue;
    if (std::find(e.except.begin(), e.except.end(), pw.pass) != e.except.end()) continue;
    r.x[pw.pass + ".overhead_ms"] += 1.0;
    // Roofline: only the bottleneck resource's terms of each dispatch (with the current theta)
    // enter the row.
    bool use_all = fit.model != CostModelKind::Roofline || pw.pass == "lighting";
    std::map<int, Resource> active;  // per dispatch (Term::stage)
    if (!use_all) {
      std::map<int, std::map<Resource, double>> t_res;
      for (const Term& t : pw.terms) {
        auto it = fit.theta.find(col(pw.pass, t.name));
        double th0 = it == fit.theta.end() ? 0.0 : it->second;
        if (it == fit.theta.end() && col(pw.pass, t.name).rfind("geo:", 0) == 0) {
          auto m = fit.theta.find("gbuffer.tris");  // a scene without Render rows: the mean
          th0 = m == fit.theta.end() ? 0.0 : m->second * w.tri_cost;
        }
        double th = std::max(theta_floor(pw.pass, t.name), th0);
        t_res[t.stage][t.res] += th * t.value *
                                 working_set_factor(pw.pass, t.name, spec, e.display) /
                                 spec.rate_per_ms(t.res);
      }
      for (auto& [stage, per_res] : t_res) {
        double worst = -1;
        for (auto& [res, v] : per_res)
          if (v > worst) worst = v, active[stage] = res;
      }
    }
    for (const Term& t : pw.terms) {
      if (!use_all && t.res != active[t.stage]) continue;
      double v = t.value / spec.rate_per_ms(t.res);
      if (fit.model == CostModelKind::Roofline)
        v *= working_set_factor(pw.pass, t.name, spec, e.display);
      if (pw.pass == "lighting") {
        std::string fterm = fp == "vpl_flops" ? "vpl_flops" : "shade_flops";
        if (t.name == fterm && fitted_wl)
          r.x["wl:" + e.workload] += v;
        else
          r.fixed += v;  // coefficient 1: cost already in work units
      } else {
        r.x[col(pw.pass, t.name)] += v;
        r.floor[col(pw.pass, t.name)] =
            fit.model == CostModelKind::Roofline ? theta_floor(pw.pass, t.name) : 0;
      }
    }
  }
  return r;
}

std::vector<double> solve(const std::vector<Row>& rows, const std::vector<std::string>& cols,
                          const std::map<std::string, double>& ridge) {
  const int n = int(cols.size()), m = int(rows.size());
  std::vector<double> scale(n, 0.0);
  for (int j = 0; j < n; ++j) {
    double s = 0;
    for (auto& r : rows) {
      auto it = r.x.find(cols[j]);
      if (it != r.x.end()) s += std::pow(it->second / r.y, 2);
    }
    scale[j] = std::sqrt(s);
  }
  std::vector<double> A(size_t(m + n) * n, 0.0), b(m + n, 0.0);
  for (int i = 0; i < m; ++i) {
    const Row& r = rows[i];
    for (int j = 0; j < n; ++j) {
      auto it = r.x.find(cols[j]);
      if (it != r.x.end() && scale[j] > 0) A[size_t(i) * n + j] = it->second / r.y / scale[j];
    }
    double fl = 0;  // theta = floor + z, z >= 0
    for (auto& [k, f] : r.floor) fl += f * r.x.at(k);
    b[i] = (r.y - r.fixed - fl) / r.y;  // relative error
  }
  for (int j = 0; j < n; ++j) A[size_t(m + j) * n + j] = std::sqrt(ridge.at(cols[j]));
  std::vector<double> z = nnls(A, m + n, n, b);
  std::vector<double> th(n, 0.0);
  for (int j = 0; j < n; ++j) {
    double fl = 0;
    for (auto& r : rows) {
      auto it = r.floor.find(cols[j]);
      if (it != r.floor.end()) fl = it->second;
    }
    th[j] = fl + (scale[j] > 0 ? z[j] / scale[j] : 0.0);
  }
  return th;
}

}  // namespace

namespace {

// One least-squares solve with the rows' current design (roofline: current bottlenecks).
// Per-scene G-buffer triangle work theta("geo:<workload>"): the profile keeps their geometric
// mean as gbuffer.tris (the cost of an average scene's triangle), each workload its ratio to
// it as tri_cost.
void finish_tri_costs(CostFit& fit) {
  double sl = 0;
  int n = 0;
  for (auto& [k, v] : fit.theta)
    if (k.rfind("geo:", 0) == 0 && v > 0) sl += std::log(v), ++n;
  if (n == 0) return;
  const double mean = std::exp(sl / n);
  fit.theta["gbuffer.tris"] = mean;
  for (auto& [k, v] : fit.theta)
    if (k.rfind("geo:", 0) == 0) fit.workloads[k.substr(4)].tri_cost = std::max(v, 1e-6) / mean;
}

// `design` chooses the bottlenecks (its theta); the solution is written to `fit`.
void solve_once(CostFit& fit, const CostFit& design, const CalData& data,
                const std::vector<const CalEntry*>& used, const FitOptions& opt) {
  std::vector<Row> rows;
  std::set<std::string> colset;
  for (auto* e : used) {
    rows.push_back(design_row(design, data, *e));
    for (auto& kv : rows.back().x) colset.insert(kv.first);
  }
  fit.rows = int(rows.size());
  std::vector<std::string> cols(colset.begin(), colset.end());
  std::map<std::string, double> ridge;
  for (auto& c : cols)
    ridge[c] = c.find(".overhead_ms") != std::string::npos
                   ? opt.ridge_overhead
                   : (c.rfind("wl:", 0) == 0 ? 0.0 : opt.ridge);
  std::vector<double> th = solve(rows, cols, ridge);
  for (size_t j = 0; j < cols.size(); ++j) {
    if (cols[j].rfind("wl:", 0) == 0) {
      Workload& w = fit.workloads[cols[j].substr(3)];
      (fitted_param(w) == "vpl_flops" ? w.vpl_flops : w.shading_flops) = th[j];
    } else {
      fit.theta[cols[j]] = th[j];
    }
  }
  finish_tri_costs(fit);
}

// Sum of squared relative errors of the fitted rows (the fit's objective, without ridge).
double fit_loss(const CostFit& fit, const CalData& data, const std::vector<const CalEntry*>& used) {
  double l = 0;
  for (auto* e : used) {
    double m = predict_entry(fit, data, *e);
    l += std::pow((m - e->published_ms) / e->published_ms, 2);
  }
  return l;
}

}  // namespace

double theta_floor(const std::string& pass, const std::string& term) {
  (void)pass;
  for (const char* t :
       {"tris", "frags", "gbuffer_bytes", "shadow_tris", "shadow_texels", "texels", "sprites"})
    if (term == t) return 1.0;
  return 0.0;
}

double nominal_work(const std::string& pass, const std::string& term, std::string* like,
                    std::string* why) {
  struct Nominal {
    const char *pass, *term;
    double work;
    const char *like, *why;
  };
  // Bytes per unit (memory terms) or FP32 operations per unit (shading terms) at 100%
  // efficiency, from each pass's algorithm as its paper states it. Not fitted.
  static const Nominal table[] = {
      {"reproject", "sprites", 1, "depth.tris",
       "Franke et al. 2021 §4: each pixel of the previous frame is a pixel-sized point sprite "
       "rasterised again, one primitive through the same vertex and setup stages as a depth-pass "
       "triangle"},
      {"reproject", "pixels", 44, "",
       "Franke et al. 2021 §4: a sprite's colour (RGBA8, 4 B) and world position (XYZW 32-bit, "
       "16 B) read, and written with its depth (24 B) where it wins the depth test"},
      {"reproject", "fill_pixels", 61, "",
       "Franke et al. 2021 §5: push-pull hole filling builds and reads the mip chain of colour, "
       "depth and confidence (4/3 x 40 B = 53 B), then the confidence per pixel (8 B)"},
      {"ssao", "pixels", 42, "",
       "Franke et al. 2021 §8.4: SSAO at half resolution, 32 samples per pixel: 32 x 4 B depth + "
       "8 B normal + 1 B written per half-resolution pixel = 137 B / 4 = 34 B per pixel, plus a "
       "full-resolution upsample/blur (8 B)"},
      {"tonemap", "pixels", 12, "", "read RGBA16F (8 B), write RGBA8 (4 B)"},
      {"taa", "pixels", 36, "",
       "current colour 8 B, history 8 B, motion 4 B read; output and history 8 B each written "
       "(the 3x3 clamp neighbourhood from cache)"},
      {"post_aa", "taps", 8, "",
       "Yang et al. 2021 §6: per pixel a 3x3 Gaussian (9 taps), TAA whose clamp window is eta x "
       "eta texels with eta = 3 + 2 floor((r/L - 0.10)/0.05) (eq. 15; mean eta^2 451 at "
       "1024x1024, gaze at the centre), history and motion (2 taps); one RGBA16F texel (8 B) per "
       "tap, uncached, as pass 2's taps"},
      {"pass2", "taps", 8, "", "one RGBA16F texel per filter tap, uncached"},
      {"importance", "pixels", 16, "",
       "Yang et al. 2021 eqs. 3-9: depth and normal read (8 B), importance written with its mip "
       "chain (8 B)"},
      {"importance", "samples", 50, "",
       "Yang et al. 2021 Alg. 1: one quasi-Metropolis-Hastings step (candidate, importance "
       "lookup, acceptance ratio)"},
      {"contribution", "flops", 1, "",
       "Yang et al. 2021 §5: the term counts the stated FP32 work: 80 per VPL-sample pair (eq. 14: "
       "distance, normalisation, two cosines, the summand with its division, the eq. 11 mix, the "
       "local frames of the two BLSO estimates) and 120 per BLSO lookup (eqs. 12-13: a random "
       "position in the cone around d, its light-space projection 4x4 + divide, the depth "
       "compare, sqrt and exp of eq. 12, the mean of eq. 13; 2 N' lookups per pair, eq. 11), "
       "transcendentals counted as 4 (their 1/4 issue rate)"},
      {"light_culling", "vpls", 100, "",
       "Yang et al. 2021 §5: one random draw, a comparison and the compaction of a VPL"},
      {"rsm", "tris", 1, "shadow.shadow_tris",
       "a reflective shadow map is a shadow map rendered from the light (Dachsbacher and "
       "Stamminger 2005): the same work per triangle"},
      {"rsm", "texels", 3, "shadow.shadow_texels",
       "Dachsbacher and Stamminger 2005: an RSM texel stores depth, normal and flux: three "
       "render targets per shadow-map texel"},
  };
  for (const Nominal& n : table)
    if (pass == n.pass && term == n.term) {
      if (like) *like = n.like;
      if (why) *why = n.why;
      return n.work;
    }
  if (like) like->clear();
  if (why) why->clear();
  return 0.0;
}

double prior_theta(const CostFit& fit, const std::string& pass, const std::string& term) {
  std::string like;
  const double w = nominal_work(pass, term, &like);
  const double fl = theta_floor(pass, term);
  if (!like.empty()) {
    const auto dot = like.find('.');
    const std::string lp = like.substr(0, dot), lt = like.substr(dot + 1);
    if (fit.unseen(lp)) return std::max(fl, w * prior_theta(fit, lp, lt));
    auto it = fit.theta.find(like);
    const double lf = fit.model == CostModelKind::Roofline ? theta_floor(lp, lt) : 0.0;
    return std::max(fl, w * (it == fit.theta.end() ? lf : std::max(lf, it->second)));
  }
  if (!(w > 0)) return fl;
  auto e = fit.efficiency.find(term_resource(pass, term, ""));
  const double eff = e == fit.efficiency.end() || !(e->second > 0) ? 1.0 : e->second;
  return std::max(fl, w / eff);
}

namespace {

// Pooled efficiencies and the prior overhead of the passes a fit never measured.
void finish_priors(CostFit& fit) {
  std::map<Resource, std::pair<double, int>> acc;
  std::vector<double> oh;
  for (const std::string& pass : known_passes()) {
    if (fit.unseen(pass)) continue;
    std::set<Resource> res;
    // Not the "taps" terms: their nominal bytes count every filter tap as an uncached texel,
    // which neighbouring windows share through the caches (pass 2 and FLC's post-AA fit at
    // 1.2-4x the peak DRAM bandwidth by that count, which DRAM cannot do), so they do not
    // measure how close a pass gets to the bandwidth; the streaming terms' bytes do.
    for (const char* term : {"pixels", "fill_pixels", "samples", "flops", "vpls", "holes"}) {
      std::string like;
      const double w = nominal_work(pass, term, &like);
      if (!like.empty() || !(w > 0)) continue;
      auto it = fit.theta.find(pass + "." + term);
      if (it == fit.theta.end() || !(it->second > 0)) continue;  // never measured or never bound
      auto& a = acc[term_resource(pass, term, "")];
      a.first += std::log(w / it->second), ++a.second;
    }
    // Overheads of the single-resource screen and shading passes (no geometry work).
    bool single = false;
    for (const char* term : {"pixels", "taps", "flops", "vpls"})
      if (find_term_resource(pass, term)) single = pass != "skybox" && pass != "importance";
    auto o = fit.theta.find(pass + ".overhead_ms");
    if (single && o != fit.theta.end()) oh.push_back(o->second);
  }
  fit.efficiency.clear();
  for (auto& [r, a] : acc) fit.efficiency[r] = std::exp(a.first / a.second);
  fit.prior_overhead_ms = 0;
  if (!oh.empty()) {
    std::sort(oh.begin(), oh.end());
    const size_t m = oh.size() / 2;
    fit.prior_overhead_ms = oh.size() % 2 ? oh[m] : 0.5 * (oh[m - 1] + oh[m]);
  }
}

}  // namespace

std::string theta_unit(const std::string& key) {
  if (key.rfind("geo:", 0) == 0) return "[triangle-rate units per submitted triangle, this scene]";
  const auto dot = key.find('.');
  if (dot == std::string::npos) return "";
  const std::string pass = key.substr(0, dot), term = key.substr(dot + 1);
  if (term == "overhead_ms") return "[ms per pass]";
  if (const auto r = find_term_resource(pass, term)) {
    switch (*r) {
      case Resource::Geometry:
        return "[triangles at peak rate per counted triangle]";
      case Resource::Raster:
        return "[pixels at peak fill rate per counted fragment/texel/pixel]";
      case Resource::Memory:
        return "[bytes per counted unit]";
      case Resource::Shading:
        return "[FP32 operations per counted unit]";
      case Resource::Fixed:
        return "[ms]";
    }
  }
  return "";
}

CostFit fit_cost_model(const CalData& data, const FitOptions& opt) {
  CostFit fit;
  fit.workloads = data.workloads;
  std::vector<const CalEntry*> used;
  // Scenes outside the fit start from the mean triangle cost (no leak from their files' fits).
  for (auto& [name, w] : fit.workloads) w.tri_cost = 1.0;
  for (auto& t : data.tables) {
    if (!opt.tables.empty() && !opt.tables.count(t.id)) continue;
    for (auto& e : t.entries)
      if (e.fit && e.published_ms > 0) used.push_back(&e);
  }
  for (auto* e : used) fit.fitted_workloads.insert(e->workload);
  for (auto* e : used)
    for (auto& p : e->passes) fit.seen_passes.insert(p);
  fit.model = CostModelKind::Linear;
  solve_once(fit, CostFit(fit), data, used, opt);
  fit.iterations = 1;
  if (opt.model == CostModelKind::Linear) {
    finish_priors(fit);
    return fit;
  }
  // Roofline: the max makes the fit piecewise linear. Active-set iteration: pick each pass's
  // bottleneck with the current theta, solve the linear problem on those terms only, repeat
  // until the fitted loss stops improving. Two deterministic starts: every multi-resource
  // term at its floor (peak rates decide the bottleneck) and the linear fit; the lower loss wins.
  CostFit best;
  double best_loss = HUGE_VAL;
  for (int start = 0; start < 2; ++start) {
    CostFit f = fit;
    f.model = CostModelKind::Roofline;
    if (start == 0)
      for (auto& [k, v] : f.theta) {
        auto dot = k.find('.');
        double fl = theta_floor(k.substr(0, dot), k.substr(dot + 1));
        if (fl > 0) v = fl;
      }
    double prev = HUGE_VAL;
    for (int it = 1; it <= 12; ++it) {
      CostFit next = f;
      next.theta.clear();  // terms that are never a bottleneck fall back to their floor
      solve_once(next, f, data, used, opt);
      next.iterations = it;
      double l = fit_loss(next, data, used);
      if (l < best_loss) best_loss = l, best = next;
      if (!(l < prev - 1e-9)) break;
      prev = l;
      f = next;
    }
  }
  finish_priors(best);
  return best;
}

namespace {

// Roofline: the G-buffer pass costs overhead + max(triangle time, fragment time, byte time),
// so the scene's triangle work enters a row only where triangles are the bottleneck. A linear
// refit on the current bottlenecks cannot raise it past another resource; instead the
// relative-error loss of the workload's G-buffer rows is minimised over log(theta) by golden
// section (each row's model is convex and non-decreasing in theta).
void refit_tri_cost_roofline(CostFit& fit, const CalData& data, const std::string& workload,
                             const std::vector<const CalEntry*>& rows, const std::string& col) {
  std::vector<const CalEntry*> geo;
  for (auto* e : rows)
    if (e->workload == workload && e->published_ms > 0 &&
        std::find(e->passes.begin(), e->passes.end(), "gbuffer") != e->passes.end())
      geo.push_back(e);
  auto it = fit.theta.find("gbuffer.tris");
  if (geo.empty() || it == fit.theta.end() || !(it->second > 0)) return;
  const double mean = it->second;
  auto set = [&](double th) {
    fit.theta[col] = th;
    fit.workloads[workload].tri_cost = th / mean;
  };
  auto loss = [&](double u) {
    set(std::exp(u));
    double l = 0;
    for (auto* e : geo)
      l += std::pow((predict_entry(fit, data, *e) - e->published_ms) / e->published_ms, 2);
    return l;
  };
  const double fl = std::max(1e-9, theta_floor("gbuffer", "tris"));
  // A coarse scan brackets the minimum (the loss is flat where triangles do not bind), then
  // golden section refines it.
  const double lo = std::log(fl), hi = std::log(std::max(fl, mean) * 1e4);
  const int kScan = 48;
  int best = 0;
  double best_l = HUGE_VAL;
  for (int i = 0; i <= kScan; ++i) {
    const double l = loss(lo + (hi - lo) * i / kScan);
    if (l < best_l) best_l = l, best = i;
  }
  double a = lo + (hi - lo) * std::max(0, best - 1) / kScan;
  double b = lo + (hi - lo) * std::min(kScan, best + 1) / kScan;
  const double g = (std::sqrt(5.0) - 1) / 2;
  double x1 = b - g * (b - a), x2 = a + g * (b - a), f1 = loss(x1), f2 = loss(x2);
  for (int i = 0; i < 80 && b - a > 1e-6; ++i) {
    if (f1 <= f2) {
      b = x2, x2 = x1, f2 = f1, x1 = b - g * (b - a), f1 = loss(x1);
    } else {
      a = x1, x1 = x2, f1 = f2, x2 = a + g * (b - a), f2 = loss(x2);
    }
  }
  set(std::exp(0.5 * (a + b)));
}

}  // namespace

void refit_workload(CostFit& fit, const CalData& data, const std::string& workload,
                    const std::vector<const CalEntry*>& rows) {
  fit.fitted_workloads.insert(workload);
  {
    auto it = fit.theta.find("gbuffer.tris");
    fit.theta["geo:" + workload] =
        it == fit.theta.end() ? 1.0 : it->second * fit.workloads[workload].tri_cost;
  }
  // One-dimensional least squares (relative error) for the workload's shading cost and its
  // G-buffer triangle work, each from the rows that contain it, the other theta fixed.
  for (int pass = 0; pass < 2; ++pass)
    for (std::string c : {"wl:" + workload, "geo:" + workload}) {
      double num = 0, den = 0;
      for (auto* e : rows) {
        if (e->workload != workload || !(e->published_ms > 0)) continue;
        Row r = design_row(fit, data, *e);
        double rest = r.fixed, xw = 0;
        for (auto& kv : r.x) {
          if (kv.first == c) {
            xw += kv.second;
            continue;
          }
          auto it = fit.theta.find(kv.first);
          double th = it != fit.theta.end() ? it->second : 0.0;
          if (kv.first == "wl:" + workload) {
            const Workload& w = fit.workloads[workload];
            th = fitted_param(w) == "vpl_flops" ? w.vpl_flops : w.shading_flops;
          }
          rest += th * kv.second;
        }
        double a = xw / r.y, b = (r.y - rest) / r.y;
        num += a * b;
        den += a * a;
      }
      if (c[0] == 'w') {
        if (!(den > 0)) continue;
        Workload& w = fit.workloads[workload];
        (fitted_param(w) == "vpl_flops" ? w.vpl_flops : w.shading_flops) = std::max(0.0, num / den);
      } else if (fit.model != CostModelKind::Roofline) {
        if (!(den > 0)) continue;
        fit.theta[c] = std::max(0.0, num / den);
        auto it = fit.theta.find("gbuffer.tris");
        if (it != fit.theta.end() && it->second > 0)
          fit.workloads[workload].tri_cost = fit.theta[c] / it->second;
      } else {
        refit_tri_cost_roofline(fit, data, workload, rows, c);
      }
    }
}

}  // namespace fovsim
