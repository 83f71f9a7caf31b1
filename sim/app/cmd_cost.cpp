// Cost-model commands (issue 7): `fovsim calibrate`, `fovsim predict`, `fovsim budget`,
// `fovsim validate-cost`. Documented in docs/cost_model.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "sim/app/commands.h"
#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/cost/analytic.h"
#include "sim/cost/calibration.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/passes.h"
#include "sim/cost/validate.h"
#include "sim/cost/workload.h"
#include "sim/experiment/config.h"
#include "sim/experiment/recost.h"
#include "sim/foveation/factory.h"

namespace fovsim::app {

namespace {

std::string models_or_default(const std::string& m) {
  return m.empty() ? default_models_dir() : m;
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

std::string pad(const std::string& s, size_t w) {
  return s.size() >= w ? s : s + std::string(w - s.size(), ' ');
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char ch : s) {
    if (ch == sep) {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += ch;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

struct MethodSpec {
  std::string text, name;
  Json params = Json::object();
};

// "kfr:sigma=1.8,alpha=4": the one method syntax (parse_method_arg); keys are validated by
// the method's own parser inside analytic_counters.
MethodSpec parse_method(const std::string& s) {
  MethodArg a = parse_method_arg(s, "--method");
  if (!is_cost_method(a.name))
    throw Error("--method " + s, "no cost model for method \"" + a.name + "\"");
  MethodSpec m;
  m.text = a.text;
  m.name = a.name;
  m.params = a.params;
  return m;
}

struct Target {  // display + workload + GPUs shared by predict and budget
  std::string models, display = "htc_vive_pro_eye",
                      workload;  // workload: required without --results
  std::vector<std::string> gpus;
  int width = 0, height = 0, eyes = 0;
  std::vector<std::string> methods;
};

void add_target_options(CLI::App* c, Target& t, const std::string& default_methods) {
  c->add_option("--gpu", t.gpus,
                "GPU profile name(s) or path(s) (models/gpus/NAME.json); repeat or comma-separate")
      ->required()
      ->delimiter(',');
  c->add_option("--workload", t.workload,
                "Workload descriptor name or path (models/workloads/NAME.json); required: the "
                "scene's triangles, "
                "lights and shading cost decide every method's cost");
  c->add_option("--display", t.display, "Display name or path (models/displays/NAME.json)")
      ->capture_default_str();
  c->add_option("--width", t.width, "Override the per-eye width in pixels")
      ->check(CLI::Range(1, 1 << 20));
  c->add_option("--height", t.height, "Override the per-eye height in pixels")
      ->check(CLI::Range(1, 1 << 20));
  c->add_option("--eyes", t.eyes, "Override the number of eyes rendered (1 or 2)")
      ->check(CLI::Range(1, 2));
  c->add_option(
      "-m,--method", t.methods,
      "Method and parameters, e.g. full, kfr:sigma=1.8, rmfr:sigma=2.6, twfr:redraw_fraction=0.06, "
      "fvrs, flc:vpl_budget=1024; repeatable (default: " +
          default_methods + ")");
  c->add_option("--models", t.models,
                "Models directory (default: $FOVSIM_MODELS, ./models, or the source tree's)");
}

// Without a scene the generic workload knows no lights, so every method's shading cost (and
// KFR's speedup) would be meaningless (issue 14 item 5): a workload must be named.
Workload target_workload(const Target& t, const std::string& models) {
  if (t.workload.empty()) {
    std::string av;
    std::error_code ec;
    std::vector<std::string> names;
    for (auto& e : std::filesystem::directory_iterator(models + "/workloads", ec))
      if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
    std::sort(names.begin(), names.end());
    for (auto& n : names)
      if (n != "generic") av += (av.empty() ? "" : ", ") + n;
    throw Error("--workload",
                "required (the scene's triangles, lights and shading cost decide every estimate; "
                "available: " +
                    av + ")");
  }
  return Workload::load(t.workload, models);
}

Display target_display(const Target& t, const std::string& models) {
  Display d = Display::load(t.display, models);
  if (t.width) d.width = t.width;
  if (t.height) d.height = t.height;
  if (t.eyes) d.eyes = t.eyes;
  return d;
}

FrameCost cost_for(const GpuProfile& g, const MethodSpec& m, const Workload& w, const Display& d) {
  Counters c = analytic_counters(m.name, m.params, w, d, "--method " + m.text);
  CostInputs in;
  in.method = m.name;
  in.counters = &c;
  in.display = d;
  in.workload = &w;
  return estimate_frame(g, in);
}

void print_table(const std::vector<std::vector<std::string>>& rows) {
  if (rows.empty()) return;
  std::vector<size_t> wd(rows[0].size(), 0);
  for (auto& r : rows)
    for (size_t i = 0; i < r.size() && i < wd.size(); ++i) wd[i] = std::max(wd[i], r[i].size());
  for (auto& r : rows) {
    std::string line;
    for (size_t i = 0; i < r.size(); ++i) {
      std::string cell = r[i];
      if (i == 0)
        cell += std::string(wd[i] - r[i].size(), ' ');
      else
        cell = std::string(wd[i] - r[i].size(), ' ') + cell;
      line += (i ? "  " : "") + cell;
    }
    std::cout << line << "\n";
  }
}

// ---------------------------------------------------------------- calibrate
struct CalibrateArgs {
  std::string models, tables, model = "roofline";
  bool dry_run = false, quiet = false;
};

int do_calibrate(const CalibrateArgs& a) {
  const std::string models = models_or_default(a.models);
  CalData data = load_calibration(models);
  FitOptions opt;
  for (auto& t : split(a.tables, ',')) opt.tables.insert(t);
  opt.model = a.model == "linear" ? CostModelKind::Linear : CostModelKind::Roofline;
  CostFit fit = fit_cost_model(data, opt);
  std::vector<std::vector<std::string>> rows = {
      {"table", "gpu", "workload", "config", "row", "use", "published_ms", "model_ms", "rel_err"}};
  std::map<std::string, std::vector<std::pair<const CalEntry*, double>>> by_gpu;
  double sum = 0;
  int n = 0;
  for (auto& t : data.tables)
    for (auto& e : t.entries) {
      double ms = predict_entry(fit, data, e);
      by_gpu[e.gpu].push_back({&e, ms});
      double re = e.published_ms > 0 ? (ms - e.published_ms) / e.published_ms : 0;
      if (e.fit) sum += std::fabs(re), ++n;
      rows.push_back({t.id, e.gpu, e.workload, e.config, e.row, e.fit ? "fit" : "check",
                      fmt("%.3f", e.published_ms), fmt("%.3f", ms), fmt("%+.1f%%", 100 * re)});
    }
  if (!a.quiet) {
    print_table(rows);
    std::cout << "\nfitted rows: " << n
              << ", mean |relative error|: " << fmt("%.1f%%", 100 * (n ? sum / n : 0)) << "\n";
    std::cout << "\nworkload shading costs (effective FP32 operations per shaded sample and light "
                 "/ VPL):\n";
    for (auto& wl : fit.fitted_workloads) {
      const Workload& w = fit.workloads.at(wl);
      std::string p = fitted_param(w);
      std::cout << "  " << wl << "." << p << " = "
                << fmt("%.1f", p == "vpl_flops" ? w.vpl_flops : w.shading_flops) << "\n";
    }
    std::cout << "\nshared work per counter unit (theta; coefficient = theta / spec rate of its "
                 "resource):\n";
    for (auto& [k, v] : fit.theta) std::cout << "  " << k << " = " << fmt("%.6g", v) << "\n";
  }
  if (a.dry_run) return 0;
  // Prediction interval from the leave-out experiments of this model (docs/cost_model.md).
  const PredictionInterval iv = interval_from_rows(validate_cost(data, fit, opt).rows, 0.8);
  for (auto& [gpu, se] : data.specs) {
    GpuProfile g = profile_from_fit(fit, gpu, data);
    nlohmann::ordered_json j;
    j["name"] = gpu;
    j["description"] = se.description;
    j["calibrated"] = by_gpu.count(gpu) > 0;
    j["model"] = model_name(fit.model);
    if (iv.level > 0)
      j["interval"] = {
          {"level", iv.level},
          {"lo_factor", iv.lo_factor},
          {"hi_factor", iv.hi_factor},
          {"n", iv.n},
          {"method",
           "empirical 10%/90% quantiles of published/model over the held-out per-pass rows of "
           "fovsim validate-cost's leave-one-seed/GPU/scene-out refits, applied to the total"}};
    j["spec"] = {{"fp32_gflops", se.spec.fp32_gflops},
                 {"mem_gbps", se.spec.mem_gbps},
                 {"fill_gpix", se.spec.fill_gpix},
                 {"tri_gtris", se.spec.tri_gtris},
                 {"boost_mhz", se.spec.boost_mhz},
                 {"l2_mb", se.spec.l2_mb},
                 {"source", se.spec.source}};
    nlohmann::ordered_json ps = nlohmann::ordered_json::object();
    for (auto& pass : known_passes()) {
      auto& pc = g.passes.at(pass);
      nlohmann::ordered_json tj = nlohmann::ordered_json::object();
      for (auto& [k, v] : pc.terms) tj[k] = v;
      ps[pass] = {{"overhead_ms", pc.overhead_ms}, {"terms", tj}};
    }
    j["passes"] = ps;
    nlohmann::ordered_json cal;
    cal["comment"] =
        std::string(
            "Written by `fovsim calibrate`: NNLS on relative error over the tables below; ") +
        (by_gpu.count(gpu)
             ? "residuals are this GPU's entries."
             : "no table used this GPU: coefficients transferred through spec-sheet ratios only.");
    nlohmann::ordered_json tabs = nlohmann::ordered_json::array();
    for (auto& t : data.tables)
      if (opt.tables.empty() || opt.tables.count(t.id)) tabs.push_back(t.id + ": " + t.source);
    cal["tables"] = tabs;
    nlohmann::ordered_json res = nlohmann::ordered_json::array();
    for (auto& [e, ms] : by_gpu[gpu])
      res.push_back(
          {{"id", e->id},
           {"fitted", e->fit},
           {"published_ms", e->published_ms},
           {"model_ms", ms},
           {"rel_err", e->published_ms > 0 ? (ms - e->published_ms) / e->published_ms : 0.0}});
    cal["residuals"] = res;
    j["calibration"] = cal;
    std::string file = models + "/gpus/" + gpu + ".json";
    write_file_atomic(file, j.dump(2) + "\n");
    if (!a.quiet) std::cout << "wrote " << file << "\n";
  }
  for (auto& wl : fit.fitted_workloads) {
    std::string file = models + "/workloads/" + wl + ".json";
    auto j = nlohmann::ordered_json::parse(read_file(file));
    const Workload& w = fit.workloads.at(wl);
    std::string p = fitted_param(w);
    j[p] = p == "vpl_flops" ? w.vpl_flops : w.shading_flops;
    j["tri_cost"] = w.tri_cost;
    j["fitted_by"] = "fovsim calibrate: " + p + ", tri_cost";
    write_file_atomic(file, j.dump(2) + "\n");
    if (!a.quiet) std::cout << "wrote " << file << " (" << p << ")\n";
  }
  return 0;
}

// ---------------------------------------------------------------- predict
struct PredictArgs {
  Target t;
  bool json = false;
  std::string results;  // re-cost a run's measured counters
  bool display_given = false, workload_given = false;
};

// `fovsim predict --results DIR` (logic: sim/experiment/recost.h): prints the re-costed means.
int do_predict_results(const PredictArgs& a) {
  RecostOptions o;
  o.results = a.results;
  o.models = models_or_default(a.t.models);
  o.gpus = a.t.gpus;
  if (a.display_given) o.display = a.t.display;
  o.width = a.t.width;
  o.height = a.t.height;
  o.eyes = a.t.eyes;
  if (a.workload_given) o.workload = a.t.workload;
  const RecostResult res = recost_results(o);
  const Display& d = res.display;
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> hdr = {"gpu", "config_id", "frames"};
  for (auto& p : known_passes()) hdr.push_back(p);
  for (const char* h : {"total_ms", "interval_ms", "budget_ms"}) hdr.push_back(h);
  rows.push_back(hdr);
  for (const RecostRow& x : res.rows) {
    nlohmann::ordered_json j;
    j["gpu"] = x.gpu;
    j["config_id"] = x.config_id;
    j["method"] = x.method;
    j["frames"] = x.frames;
    j["display"] = {{"name", d.name}, {"width", d.width}, {"height", d.height}, {"eyes", d.eyes}};
    j["est_ms_total"] = x.total_ms;
    if (x.level > 0) {
      j["est_ms_total_lo"] = x.lo_ms;
      j["est_ms_total_hi"] = x.hi_ms;
      j["interval_level"] = x.level;
    }
    std::vector<std::string> r = {x.gpu, x.config_id, fmt("%.0f", x.frames)};
    for (auto& p : known_passes()) {
      std::string cell = "-";
      for (auto& kv : x.pass_ms)
        if (kv.first == p) {
          j["est_ms_" + p] = kv.second;
          cell = fmt("%.3f", kv.second);
        }
      r.push_back(cell);
    }
    r.push_back(fmt("%.3f", x.total_ms));
    r.push_back(x.level > 0 ? fmt("%.2f-", x.lo_ms) + fmt("%.2f", x.hi_ms) : "-");
    r.push_back(fmt("%.2f", d.frame_budget_ms()));
    rows.push_back(r);
    out.push_back(j);
  }
  if (a.json) {
    std::cout << out.dump(2) << "\n";
  } else {
    std::cout << "results " << a.results << " re-costed for display " << d.name << " " << d.width
              << "x" << d.height << " x" << d.eyes << " eye(s), workload " << res.workload
              << "; mean ms per frame ('-': pass does not exist)\n";
    print_table(rows);
  }
  return 0;
}

int do_predict(const PredictArgs& a) {
  if (!a.results.empty()) return do_predict_results(a);
  const std::string models = models_or_default(a.t.models);
  Workload w = target_workload(a.t, models);
  Display d = target_display(a.t, models);
  std::vector<MethodSpec> methods;
  for (auto& m : a.t.methods.empty() ? std::vector<std::string>{"full"} : a.t.methods)
    methods.push_back(parse_method(m));
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> header = {"gpu", "method"};
  for (auto& p : known_passes()) header.push_back(p);
  header.push_back("total_ms");
  header.push_back("interval_ms");
  header.push_back("speedup");
  rows.push_back(header);
  for (auto& gname : a.t.gpus) {
    GpuProfile g = GpuProfile::load(gname, models);
    double full_total = cost_for(g, parse_method("full"), w, d).total_ms;
    for (auto& m : methods) {
      FrameCost fc = cost_for(g, m, w, d);
      nlohmann::ordered_json j;
      j["gpu"] = g.name;
      j["calibrated"] = g.calibrated;
      j["method"] = m.name;
      j["params"] = m.params;
      j["workload"] = w.name;
      j["display"] = {{"name", d.name}, {"width", d.width}, {"height", d.height}, {"eyes", d.eyes}};
      j["est_ms_total"] = fc.total_ms;
      if (fc.interval_level > 0) {
        j["est_ms_total_lo"] = fc.total_lo_ms;
        j["est_ms_total_hi"] = fc.total_hi_ms;
        j["interval_level"] = fc.interval_level;
      }
      j["model"] = model_name(g.model);
      for (auto& p : fc.passes) j["est_ms_" + p.pass] = p.ms;
      j["speedup_vs_full"] = fc.total_ms > 0 ? full_total / fc.total_ms : 0.0;
      if (!fc.missing_counters.empty()) j["missing_counters"] = fc.missing_counters;
      out.push_back(j);
      std::vector<std::string> r = {g.name, m.text};
      for (auto& p : known_passes()) {
        bool exists = false;
        for (auto& pc : fc.passes) exists |= pc.pass == p;
        r.push_back(exists ? fmt("%.3f", fc.pass_ms(p)) : "-");
      }
      r.push_back(fmt("%.3f", fc.total_ms));
      r.push_back(fc.interval_level > 0 ? fmt("%.2f-", fc.total_lo_ms) + fmt("%.2f", fc.total_hi_ms)
                                        : "-");
      r.push_back(fmt("%.2fx", fc.total_ms > 0 ? full_total / fc.total_ms : 0.0));
      rows.push_back(r);
    }
  }
  if (a.json) {
    std::cout << out.dump(2) << "\n";
  } else {
    std::cout << "workload " << w.name << ", display " << d.name << " " << d.width << "x"
              << d.height << " x" << d.eyes
              << " eye(s); ms per frame ('-': pass does not exist); interval_ms: the profile's "
              << "prediction interval on the total (docs/cost_model.md)\n";
    print_table(rows);
  }
  return 0;
}

// ---------------------------------------------------------------- budget
struct BudgetArgs {
  Target t;
  double hz = 90, budget_ms = 0;
  double s_shading = 1, s_geometry = 1, s_raster = 1, s_memory = 1, s_fixed = 1;
  bool json = false;
};

int do_budget(const BudgetArgs& a) {
  const std::string models = models_or_default(a.t.models);
  Workload w = target_workload(a.t, models);
  Display d = target_display(a.t, models);
  const double budget = a.budget_ms > 0 ? a.budget_ms : 1000.0 / a.hz;
  std::vector<std::string> mlist = a.t.methods;
  if (mlist.empty())
    mlist = {"full", "kfr", "rmfr", "hyperbolic", "linear", "fvrs", "twfr"};  // run defaults
  const char* res_names[] = {"shading", "geometry", "raster", "memory", "fixed"};
  std::vector<std::vector<std::string>> rows = {
      {"gpu", "method", "total_ms", "interval_ms", "budget_ms", "fits", "headroom_ms", "headroom",
       "x_shading", "x_geometry", "x_raster", "x_memory", "x_fixed", "x_all"}};
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (auto& gname : a.t.gpus) {
    GpuProfile g = GpuProfile::load(gname, models)
                       .scaled(Resource::Shading, a.s_shading)
                       .scaled(Resource::Geometry, a.s_geometry)
                       .scaled(Resource::Raster, a.s_raster)
                       .scaled(Resource::Memory, a.s_memory)
                       .scaled(Resource::Fixed, a.s_fixed);
    for (auto& ms : mlist) {
      MethodSpec m = parse_method(ms);
      FrameCost fc = cost_for(g, m, w, d);
      const double T = fc.total_ms;
      const bool iv = fc.interval_level > 0;
      const char* verdict = budget_verdict(fc, budget);
      std::vector<std::string> r = {
          g.name,
          m.text,
          fmt("%.3f", T),
          iv ? fmt("%.2f-", fc.total_lo_ms) + fmt("%.2f", fc.total_hi_ms) : "-",
          fmt("%.2f", budget),
          verdict,
          fmt("%+.3f", budget - T),
          fmt("%+.0f%%", budget > 0 ? 100 * (budget - T) / budget : 0)};
      nlohmann::ordered_json j = {{"gpu", g.name},
                                  {"method", m.text},
                                  {"est_ms_total", T},
                                  {"budget_ms", budget},
                                  {"fits", T <= budget},
                                  {"verdict", verdict},
                                  {"headroom_ms", budget - T}};
      if (iv)
        j["est_ms_total_lo"] = fc.total_lo_ms, j["est_ms_total_hi"] = fc.total_hi_ms,
        j["interval_level"] = fc.interval_level;
      // Factor a resource's throughput needs (alone) so the frame fits: part / (budget - rest).
      for (const char* rn : res_names) {
        double part = fc.resource_ms.count(rn) ? fc.resource_ms.at(rn) : 0;
        double room = budget - (T - part);
        double f = part <= 0 ? (T <= budget ? 0 : INFINITY) : (room > 0 ? part / room : INFINITY);
        r.push_back(std::isfinite(f) ? fmt("%.2f", f) : "inf");
        j[std::string("factor_") + rn] = std::isfinite(f) ? Json(f) : Json("inf");
      }
      double fixed = fc.resource_ms.count("fixed") ? fc.resource_ms.at("fixed") : 0;
      double fa = (budget - fixed) > 0 ? (T - fixed) / (budget - fixed) : INFINITY;
      r.push_back(std::isfinite(fa) ? fmt("%.2f", fa) : "inf");
      j["factor_all"] = std::isfinite(fa) ? Json(fa) : Json("inf");
      rows.push_back(r);
      out.push_back(j);
    }
  }
  if (a.json) {
    std::cout << out.dump(2) << "\n";
  } else {
    std::cout << "budget " << fmt("%.2f", budget) << " ms; workload " << w.name << ", display "
              << d.width << "x" << d.height << " x" << d.eyes
              << " eye(s); what-if throughput x shading " << a.s_shading << ", geometry "
              << a.s_geometry << ", raster " << a.s_raster << ", memory " << a.s_memory
              << ", fixed " << a.s_fixed << "\n"
              << "x_<resource>: throughput factor that resource alone needs to fit (<1: slack; "
                 "inf: cannot fit alone); "
                 "x_all: uniform factor on everything but fixed overheads; fits: at the interval's "
                 "confidence "
                 "(uncertain: the interval straddles the budget)\n";
    print_table(rows);
  }
  return 0;
}

// ---------------------------------------------------------------- validate-cost
struct ValidateArgs {
  std::string models, out = "results/validate_cost";
  bool no_plot = false;
};

int do_validate(const ValidateArgs& a) {
  const std::string models = models_or_default(a.models);
  CalData data = load_calibration(models);
  FitOptions opt;  // the default model (roofline) is the detailed report below
  CostFit fit = fit_cost_model(data, opt);
  ValidationReport rep = validate_cost(data, fit, opt);
  std::vector<ModelSummary> sums;
  for (CostModelKind k : {CostModelKind::Roofline, CostModelKind::Linear}) {
    FitOptions o = opt;
    o.model = k;
    if (k == opt.model) {
      sums.push_back(summarize_model(rep, k, 0.8));
    } else {
      CostFit f = fit_cost_model(data, o);
      sums.push_back(summarize_model(validate_cost(data, f, o), k, 0.8));
    }
  }
  std::sort(sums.begin(), sums.end(), [](const ModelSummary& x, const ModelSummary& y) {
    return x.leaveout_mean < y.leaveout_mean;
  });
  std::ostringstream txt, csv;
  // model_lo_ms/model_hi_ms: the 80% interval; on cross-prediction rows the nested one (built
  // without the row's table), on the others the interval the profiles carry.
  const PredictionInterval iv_all = interval_from_rows(rep.rows, 0.8);
  std::map<std::string, PredictionInterval> iv_nested;
  for (auto& t : data.tables) iv_nested[t.id] = interval_from_rows(rep.rows, 0.8, t.id);
  csv << "experiment,id,table,gpu,workload,config,row,kind,published_ms,model_ms,rel_err,model_lo_"
         "ms,model_hi_ms\n";
  for (auto& r : rep.rows) {
    const PredictionInterval& iv =
        r.experiment.rfind("cross:", 0) == 0 ? iv_nested[r.table] : iv_all;
    csv << '"' << r.experiment << "\"," << '"' << r.id << "\"," << r.table << ',' << r.gpu << ','
        << r.workload << ',' << r.config << ",\"" << r.row << "\"," << r.kind << ','
        << r.published_ms << ',' << r.model_ms << ','
        << (r.published_ms > 0 ? std::to_string(r.rel_err()) : "") << ','
        << r.model_ms * iv.lo_factor << ',' << r.model_ms * iv.hi_factor << "\n";
  }
  txt << "fovsim validate-cost: predicted vs. published per-pass times (ms)\n\n";
  txt << "== models ranked by held-out (leave-one-seed = leave-one-GPU, leave-one-scene) mean |rel "
         "err|\n"
      << "   (no calibration table gives several resolutions: no leave-one-resolution-out "
         "experiment)\n";
  txt << pad("model", 10) << pad("fitted mean/worst", 20) << pad("held-out mean/worst", 22)
      << pad("80% interval (x model)", 24) << "nested coverage\n";
  for (auto& m : sums)
    txt << pad(model_name(m.model), 10)
        << pad(fmt("%.1f%%", 100 * m.fitted_mean) + fmt(" / %.1f%%", 100 * m.fitted_worst), 20)
        << pad(fmt("%.1f%%", 100 * m.leaveout_mean) + fmt(" / %.1f%%", 100 * m.leaveout_worst) +
                   " (" + std::to_string(m.leaveout_n) + ")",
               22)
        << pad(fmt("[%.2f, ", m.interval.lo_factor) + fmt("%.2f]", m.interval.hi_factor), 24)
        << fmt("%.0f%%", 100 * m.coverage) << " of " << m.coverage_n << "\n";
  txt << "nested coverage: each target table's held-out rows against the interval built from the "
         "other tables'\n\n";
  txt << "detailed report below: model " << model_name(opt.model) << "\n\n";
  txt << "== calibration entries (all tables fitted together; 'check' rows are totals, not "
         "fitted)\n";
  double se[2] = {0, 0};
  int ne[2] = {0, 0};
  for (auto& r : rep.rows) {
    if (r.experiment != "calibration") continue;
    int k = r.kind == "fitted" ? 0 : 1;
    se[k] += std::fabs(r.rel_err()), ne[k]++;
    txt << pad(r.id, 62) << " " << pad(r.kind, 9) << fmt(" %8.3f", r.published_ms)
        << fmt(" %8.3f", r.model_ms) << fmt(" %+7.1f%%", 100 * r.rel_err()) << "\n";
  }
  txt << "mean |rel err|: fitted " << fmt("%.1f%%", ne[0] ? 100 * se[0] / ne[0] : 0) << " ("
      << ne[0] << " rows), check " << fmt("%.1f%%", ne[1] ? 100 * se[1] / ne[1] : 0) << " ("
      << ne[1] << " rows)\n\n";
  txt << "== withheld figures (published values withheld from the seeds: predictions only)\n";
  std::map<std::string, std::vector<const ValidationRow*>> wh;
  for (auto& r : rep.rows)
    if (r.experiment == "withheld") wh[r.id + " " + r.workload].push_back(&r);
  for (auto& [k, v] : wh) {
    txt << pad(k, 52);
    for (auto* r : v) txt << " " << r->config << fmt(" %.2f ms", r->model_ms);
    if (v.size() == 2 && v[1]->model_ms > 0)
      txt << fmt("  speedup %.2fx", v[0]->model_ms / v[1]->model_ms);
    txt << "\n";
  }
  txt << "\n== cross-predictions (target's shading and triangle costs refit from its baseline "
         "lighting and G-buffer rows only)\n";
  std::ostringstream ccsv;
  ccsv << "name,fit_on,target,possible,n,mean_abs_rel_err,speedup_published,speedup_model\n";
  for (auto& c : rep.cross) {
    ccsv << '"' << c.name << "\",\"" << c.fit_on << "\"," << c.target << ',' << c.possible << ','
         << c.n << ',' << c.mean_abs_rel_err << ',' << c.speedup_published << ',' << c.speedup_model
         << "\n";
    txt << pad(c.name, 48);
    if (!c.possible) {
      txt << " not predictable (" << c.why << ")\n";
      continue;
    }
    txt << " rows " << c.n << ", mean |rel err| " << fmt("%.1f%%", 100 * c.mean_abs_rel_err);
    if (c.speedup_published > 0)
      txt << ", speedup published " << fmt("%.2fx", c.speedup_published) << " model "
          << fmt("%.2fx", c.speedup_model);
    if (!c.why.empty()) txt << " [rows skipped, " << c.why << "]";
    txt << "\n";
  }
  make_dirs(a.out);
  write_file_atomic(a.out + "/validate_cost.csv", csv.str());
  write_file_atomic(a.out + "/cross_predictions.csv", ccsv.str());
  write_file_atomic(a.out + "/report.txt", txt.str());
  std::cout << txt.str() << "\nwrote " << a.out
            << "/{report.txt,validate_cost.csv,cross_predictions.csv}\n";
  if (!a.no_plot) {
    std::string script = models + "/../viz/plot_cost.py";
    std::string cmd = "/usr/bin/python3 '" + script + "' '" + a.out + "/validate_cost.csv' '" +
                      a.out + "/validate_cost.png'";
    int rc = std::system(cmd.c_str());
    if (rc != 0)
      std::cerr << "fovsim: warning: plot failed (" << cmd << ")\n";
    else
      std::cout << "wrote " << a.out << "/validate_cost.png\n";
  }
  return 0;
}

}  // namespace

void register_cost(CLI::App& app, Action& action) {
  {
    auto a = std::make_shared<CalibrateArgs>();
    CLI::App* c =
        app.add_subcommand("calibrate",
                           "Fit GPU profiles and workload shading costs to the seeds' per-pass "
                           "tables (models/calibration) and write models/gpus/*.json");
    c->add_option("--models", a->models,
                  "Models directory (default: $FOVSIM_MODELS, ./models, or the source tree's)");
    c->add_option("--tables", a->tables,
                  "Comma-separated calibration table ids to fit (default: all)");
    c->add_flag("--dry-run", a->dry_run,
                "Print the fit and residuals without writing profiles or workloads");
    c->add_flag("-q,--quiet", a->quiet, "Do not print the residual table");
    c->add_option("--model", a->model,
                  "How a pass combines its resources: roofline (bottleneck) or linear (sum)")
        ->check(CLI::IsMember({"roofline", "linear"}))
        ->capture_default_str();
    c->callback([a, &action]() { action = [a]() { return do_calibrate(*a); }; });
  }
  {
    auto a = std::make_shared<PredictArgs>();
    CLI::App* c = app.add_subcommand(
        "predict",
        "Per-pass and total frame time of methods for a GPU, workload and display (analytic "
        "counters, no rendering), or of a finished run's measured counters (--results)");
    add_target_options(c, a->t, "full");
    c->add_flag("--json", a->json,
                "Print JSON with est_ms_total and est_ms_<pass> per GPU and method");
    c->add_option(
        "--results", a->results,
        "A results directory of `fovsim run`: re-cost its measured counters (frames.csv) for "
        "--gpu, and for "
        "--display/--width/--height/--eyes when given (default: the run's display); -m is ignored");
    c->callback([a, &action, c]() {
      a->display_given = c->get_option("--display")->count() > 0;
      a->workload_given = c->get_option("--workload")->count() > 0;
      action = [a]() { return do_predict(*a); };
    });
  }
  {
    auto a = std::make_shared<BudgetArgs>();
    CLI::App* c =
        app.add_subcommand("budget",
                           "Which configurations fit a refresh-rate budget, their headroom, and "
                           "the throughput factor each resource would need");
    add_target_options(c, a->t, "full, kfr, rmfr, hyperbolic, linear, fvrs, twfr (run defaults)");
    c->add_option("--hz", a->hz,
                  "Refresh rate whose frame time is the budget (e.g. 72, 90, 120, 144)")
        ->capture_default_str()
        ->check(CLI::Range(1.0, 10000.0));
    c->add_option("--budget-ms", a->budget_ms, "Frame budget in ms (overrides --hz)")
        ->check(CLI::Range(0.0, 1e6));
    c->add_option("--scale-shading", a->s_shading, "What-if: multiply shading (FP32) throughput")
        ->check(CLI::Range(1e-6, 1e6));
    c->add_option("--scale-geometry", a->s_geometry,
                  "What-if: multiply geometry (triangle) throughput")
        ->check(CLI::Range(1e-6, 1e6));
    c->add_option("--scale-raster", a->s_raster, "What-if: multiply raster (fill) throughput")
        ->check(CLI::Range(1e-6, 1e6));
    c->add_option("--scale-memory", a->s_memory, "What-if: multiply memory bandwidth")
        ->check(CLI::Range(1e-6, 1e6));
    c->add_option("--scale-fixed", a->s_fixed,
                  "What-if: divide fixed per-pass overheads by this factor")
        ->check(CLI::Range(1e-6, 1e6));
    c->add_flag("--json", a->json, "Print JSON");
    c->callback([a, &action]() { action = [a]() { return do_budget(*a); }; });
  }
  {
    auto a = std::make_shared<ValidateArgs>();
    CLI::App* c =
        app.add_subcommand("validate-cost",
                           "Report predicted vs. published times for every calibration entry, "
                           "withheld-figure predictions and cross-predictions (text, CSV, plot)");
    c->add_option("--models", a->models,
                  "Models directory (default: $FOVSIM_MODELS, ./models, or the source tree's)");
    c->add_option("-o,--out", a->out, "Output directory")->capture_default_str();
    c->add_flag("--no-plot", a->no_plot, "Do not run viz/plot_cost.py");
    c->callback([a, &action]() { action = [a]() { return do_validate(*a); }; });
  }
}

}  // namespace fovsim::app
