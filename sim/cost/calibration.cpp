// Calibration of GPU profiles against the seeds' tables (see calibration.h).
#include "sim/cost/calibration.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "sim/core/error.h"
#include "sim/cost/analytic.h"
#include "sim/cost/nnls.h"
#include "sim/cost/passes.h"

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

bool is_baseline_method(const std::string& m) { return m == "full"; }

}  // namespace

std::string fitted_param(const Workload& w) { return w.vpl_flops >= 0 ? "vpl_flops" : "shading_flops"; }

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
      e.spec.source = s.string("source", "");
      d.specs[it.key()] = e;
    }
    p.finish();
  }
  std::vector<std::string> files;
  for (auto& e : std::filesystem::directory_iterator(models_dir + "/calibration"))
    if (e.path().extension() == ".json" && e.path().filename() != "gpu_specs.json") files.push_back(e.path().string());
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
      if (!d.workloads.count(ce.workload)) e.fail("workload", "unknown workload '" + ce.workload + "'");
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
      ce.published_ms = e.number("ms", Range::at_least(0));
      ce.fit = e.string("use", "fit", {"fit", "check"}) == "fit";
      e.ignore("comment");
      ce.id = t.id + ":" + ce.workload + ":" + ce.config + ":" + ce.row;
      (void)k++;
      t.entries.push_back(ce);
    }
    p.ignore("withheld");
    p.finish();
    d.tables.push_back(t);
  }
  return d;
}

Workload entry_workload(const CostFit& fit, const CalData& data, const CalEntry& e) {
  auto it = fit.workloads.find(e.workload);
  const Workload& base = it != fit.workloads.end() ? it->second : data.workloads.at(e.workload);
  return apply_overrides(base, e.workload_overrides, e.id + ": workload_overrides");
}

double entry_ms(const GpuProfile& g, const Workload& w, const CalEntry& e, FrameCost* out) {
  Counters c = analytic_counters(e.method, e.params, w, e.display, e.id);
  CostInputs in;
  in.method = e.method;
  in.counters = &c;
  in.display = e.display;
  in.workload = &w;
  FrameCost fc = estimate_frame(g, in);
  double ms = 0;
  if (e.passes.empty()) {
    ms = fc.total_ms;
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
  g.name = gpu;
  g.description = se.description;
  g.spec = se.spec;
  for (const std::string& pass : known_passes()) {
    PassCoef pc;
    auto oh = fit.theta.find(pass + ".overhead_ms");
    pc.overhead_ms = oh == fit.theta.end() ? 0 : oh->second;
    // Every term the model knows for this pass (term_resource validates the pair).
    for (const char* term : {"tris", "frags", "gbuffer_bytes", "shadow_tris", "shadow_texels", "texels", "pixels",
                             "holes", "samples", "evals", "vpls", "shade_flops", "vpl_flops", "taps"}) {
      Resource r;
      try {
        r = term_resource(pass, term, "");
      } catch (const Error&) {
        continue;
      }
      double rate = se.spec.rate_per_ms(r);
      if (pass == "lighting") {  // unit work: the workload carries the (fitted) flops
        pc.terms[term] = 1.0 / rate;
        continue;
      }
      auto t = fit.theta.find(pass + "." + term);
      pc.terms[term] = t == fit.theta.end() ? 0 : t->second / rate;
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
  double fixed = 0, y = 0;
};

Row design_row(const CostFit& fit, const CalData& data, const CalEntry& e) {
  Workload w = entry_workload(fit, data, e);
  const std::string fp = fitted_param(w);
  const bool fitted_wl = fit.fitted_workloads.count(e.workload) > 0;
  Workload wu = w;  // unit shading cost for the fitted parameter: its column is the cost
  if (fitted_wl) (fp == "vpl_flops" ? wu.vpl_flops : wu.shading_flops) = 1.0;
  const GpuSpec& spec = data.specs.at(e.gpu).spec;
  Counters c = analytic_counters(e.method, e.params, w, e.display, e.id);
  CostInputs in;
  in.method = e.method;
  in.counters = &c;
  in.display = e.display;
  in.workload = &wu;
  Row r;
  r.y = e.published_ms;
  for (const PassWork& pw : assemble_passes(in, wu)) {
    if (!e.passes.empty() && std::find(e.passes.begin(), e.passes.end(), pw.pass) == e.passes.end()) continue;
    r.x[pw.pass + ".overhead_ms"] += 1.0;
    for (const Term& t : pw.terms) {
      double v = t.value / spec.rate_per_ms(t.res);
      if (pw.pass == "lighting") {
        std::string fterm = fp == "vpl_flops" ? "vpl_flops" : "shade_flops";
        if (t.name == fterm && fitted_wl)
          r.x["wl:" + e.workload] += v;
        else
          r.fixed += v;  // coefficient 1: cost already in work units
      } else {
        r.x[pw.pass + "." + t.name] += v;
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
    b[i] = (r.y - r.fixed) / r.y;  // relative error
  }
  for (int j = 0; j < n; ++j) A[size_t(m + j) * n + j] = std::sqrt(ridge.at(cols[j]));
  std::vector<double> z = nnls(A, m + n, n, b);
  std::vector<double> th(n, 0.0);
  for (int j = 0; j < n; ++j) th[j] = scale[j] > 0 ? z[j] / scale[j] : 0.0;
  return th;
}

}  // namespace

CostFit fit_cost_model(const CalData& data, const FitOptions& opt) {
  CostFit fit;
  fit.workloads = data.workloads;
  std::vector<const CalEntry*> used;
  for (auto& t : data.tables) {
    if (!opt.tables.empty() && !opt.tables.count(t.id)) continue;
    for (auto& e : t.entries)
      if (e.fit && e.published_ms > 0) used.push_back(&e);
  }
  for (auto* e : used) fit.fitted_workloads.insert(e->workload);
  std::vector<Row> rows;
  std::set<std::string> colset;
  for (auto* e : used) {
    rows.push_back(design_row(fit, data, *e));
    for (auto& kv : rows.back().x) colset.insert(kv.first);
    for (auto& p : e->passes) fit.seen_passes.insert(p);
  }
  fit.rows = int(rows.size());
  std::vector<std::string> cols(colset.begin(), colset.end());
  std::map<std::string, double> ridge;
  for (auto& c : cols)
    ridge[c] = c.find(".overhead_ms") != std::string::npos ? opt.ridge_overhead : (c.rfind("wl:", 0) == 0 ? 0.0 : opt.ridge);
  std::vector<double> th = solve(rows, cols, ridge);
  for (size_t j = 0; j < cols.size(); ++j) {
    if (cols[j].rfind("wl:", 0) == 0) {
      Workload& w = fit.workloads[cols[j].substr(3)];
      (fitted_param(w) == "vpl_flops" ? w.vpl_flops : w.shading_flops) = th[j];
    } else {
      fit.theta[cols[j]] = th[j];
    }
  }
  return fit;
}

void refit_workload(CostFit& fit, const CalData& data, const std::string& workload,
                    const std::vector<const CalEntry*>& rows) {
  fit.fitted_workloads.insert(workload);
  double num = 0, den = 0;
  for (auto* e : rows) {
    if (e->workload != workload || !(e->published_ms > 0)) continue;
    Row r = design_row(fit, data, *e);
    double rest = r.fixed;
    double xw = 0;
    for (auto& kv : r.x) {
      if (kv.first == "wl:" + workload) {
        xw += kv.second;
        continue;
      }
      auto it = fit.theta.find(kv.first);
      if (it != fit.theta.end()) rest += it->second * kv.second;
    }
    double a = xw / r.y, b = (r.y - rest) / r.y;
    num += a * b;
    den += a * a;
  }
  if (den > 0) {
    Workload& w = fit.workloads[workload];
    (fitted_param(w) == "vpl_flops" ? w.vpl_flops : w.shading_flops) = std::max(0.0, num / den);
  }
}

}  // namespace fovsim
