// Cost-model commands (issue 7): `fovsim calibrate`, `fovsim predict`, `fovsim budget`,
// `fovsim validate-cost`. Documented in docs/cost_model.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "sim/app/commands.h"
#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/cost/analytic.h"
#include "sim/cost/budget.h"
#include "sim/cost/calibration.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/cost_report.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/passes.h"
#include "sim/cost/validate.h"
#include "sim/cost/workload.h"
#include "sim/experiment/config.h"
#include "sim/experiment/plots.h"
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
    for (auto& n : Workload::available(models))
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
  return analytic_frame(g, m.name, m.params, w, d, "--method " + m.text);
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
  CalibrateOptions o;
  o.models = models_or_default(a.models);
  o.tables = parse_id_list(a.tables, "--tables");
  o.model = a.model == "linear" ? CostModelKind::Linear : CostModelKind::Roofline;
  o.write = !a.dry_run;
  const CalibrationRun run = run_calibration(o);
  if (!a.quiet) {
    std::vector<std::vector<std::string>> rows = {{"table", "gpu", "workload", "config", "row",
                                                   "use", "published_ms", "model_ms", "rel_err"}};
    for (auto& r : run.rows)
      rows.push_back({r.entry.table, r.entry.gpu, r.entry.workload, r.entry.config, r.entry.row,
                      r.entry.fit ? "fit" : "check", fmt("%.3f", r.entry.published_ms),
                      fmt("%.3f", r.model_ms), fmt("%+.1f%%", 100 * r.rel_err)});
    print_table(rows);
    std::cout << "\nfitted rows: " << run.fitted_n
              << ", mean |relative error|: " << fmt("%.1f%%", 100 * run.fitted_mean_abs_err)
              << "\n";
    std::cout << "\nworkload shading costs (effective FP32 operations per shaded sample and light "
                 "/ VPL):\n";
    for (auto& wl : run.fit.fitted_workloads) {
      const Workload& w = run.fit.workloads.at(wl);
      std::string p = fitted_param(w);
      std::cout << "  " << wl << "." << p << " = "
                << fmt("%.1f", p == "vpl_flops" ? w.vpl_flops : w.shading_flops) << "\n";
    }
    std::cout << "\nshared work per counter unit (theta; coefficient = theta / spec rate of its "
                 "resource):\n";
    for (auto& [k, v] : run.fit.theta) std::cout << "  " << k << " = " << fmt("%.6g", v) << "\n";
    for (auto& f : run.written) std::cout << "wrote " << f << "\n";
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
      for (auto& p : fc.passes) {
        j["est_ms_" + p.pass] = p.ms;
        if (fc.interval_level > 0) {
          j["est_ms_" + p.pass + "_lo"] = p.lo_ms;
          j["est_ms_" + p.pass + "_hi"] = p.hi_ms;
        }
      }
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
  std::vector<std::vector<std::string>> rows = {
      {"gpu", "method", "total_ms", "interval_ms", "budget_ms", "fits", "headroom_ms", "headroom",
       "x_shading", "x_geometry", "x_raster", "x_memory", "x_fixed", "x_all"}};
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  WhatIf wi;
  wi.shading = a.s_shading, wi.geometry = a.s_geometry, wi.raster = a.s_raster;
  wi.memory = a.s_memory, wi.fixed = a.s_fixed;
  auto factor_text = [](double f) { return std::isfinite(f) ? fmt("%.2f", f) : "inf"; };
  auto factor_json = [](double f) { return std::isfinite(f) ? Json(f) : Json("inf"); };
  for (auto& gname : a.t.gpus) {
    GpuProfile g = apply_what_if(GpuProfile::load(gname, models), wi);
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
      if (iv) {
        j["est_ms_total_lo"] = fc.total_lo_ms, j["est_ms_total_hi"] = fc.total_hi_ms;
        j["interval_level"] = fc.interval_level;
      }
      for (auto& pc : fc.passes) {
        j["est_ms_" + pc.pass] = pc.ms;
        if (iv)
          j["est_ms_" + pc.pass + "_lo"] = pc.lo_ms, j["est_ms_" + pc.pass + "_hi"] = pc.hi_ms;
      }
      const BudgetFactors bf = budget_factors(fc, budget);
      for (auto& rn : budget_resources()) {
        r.push_back(factor_text(bf.x.at(rn)));
        j["factor_" + rn] = factor_json(bf.x.at(rn));
      }
      r.push_back(factor_text(bf.x_all));
      j["factor_all"] = factor_json(bf.x_all);
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
  const ValidationOutputs v = run_validation(models_or_default(a.models));
  write_validation(v, a.out);
  std::cout << v.report_txt << "\nwrote " << a.out
            << "/{report.txt,validate_cost.csv,cross_predictions.csv}\n";
  if (!a.no_plot) {
    // One way of launching viz scripts (sim/experiment/plots.h): a missing matplotlib skips.
    const PlotOutcome po = run_plot_script(
        "plot_cost.py", {a.out + "/validate_cost.csv", a.out + "/validate_cost.png"}, false);
    if (po.status == PlotOutcome::Status::Made)
      std::cout << "wrote " << a.out << "/validate_cost.png\n";
    else if (!po.message.empty())
      std::cerr << "fovsim: " << po.message << "\n";
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
        ->check(finite_in(1.0, 10000.0));
    c->add_option("--budget-ms", a->budget_ms, "Frame budget in ms (overrides --hz)")
        ->check(finite_above(0.0, 1e6));
    c->add_option("--scale-shading", a->s_shading, "What-if: multiply shading (FP32) throughput")
        ->check(finite_in(1e-6, 1e6));
    c->add_option("--scale-geometry", a->s_geometry,
                  "What-if: multiply geometry (triangle) throughput")
        ->check(finite_in(1e-6, 1e6));
    c->add_option("--scale-raster", a->s_raster, "What-if: multiply raster (fill) throughput")
        ->check(finite_in(1e-6, 1e6));
    c->add_option("--scale-memory", a->s_memory, "What-if: multiply memory bandwidth")
        ->check(finite_in(1e-6, 1e6));
    c->add_option("--scale-fixed", a->s_fixed,
                  "What-if: divide fixed per-pass overheads by this factor")
        ->check(finite_in(1e-6, 1e6));
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
