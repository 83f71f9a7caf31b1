// Cost-model commands: `fovsim calibrate`, `fovsim predict`, `fovsim budget`,
// `fovsim validate-cost`. Documented in docs/cost_model.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "sim/app/commands.h"
#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/text.h"
#include "sim/cost/analytic.h"
#include "sim/cost/budget.h"
#include "sim/cost/calibration.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/cost_report.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/passes.h"
#include "sim/cost/tracking_cost.h"
#include "sim/cost/validate.h"
#include "sim/cost/workload.h"
#include "sim/experiment/config.h"
#include "sim/experiment/config_cost.h"
#include "sim/experiment/info.h"
#include "sim/experiment/plots.h"
#include "sim/experiment/recost.h"
#include "sim/foveation/factory.h"

namespace fovsim::app {

namespace {

std::string models_or_default(const std::string& m) {
  return m.empty() ? default_models_dir() : m;
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
  std::string models, display = kDefaultDisplay,
                      workload;  // workload: required without --results
  std::vector<std::string> gpus;
  int width = 0, height = 0, eyes = 0;
  std::vector<std::string> methods;
  std::string config;  // --config: the run config's scene, workload, display and methods
};

void add_target_options(CLI::App* c, Target& t, const std::string& default_methods) {
  c->add_option("--gpu", t.gpus,
                "GPU profile name(s) or path(s) (models/gpus/NAME.json); repeat or comma-separate "
                "(required, except with --config: the config's gpus)")
      ->delimiter(',');
  c->add_option("--workload", t.workload,
                "Workload descriptor name or path (models/workloads/NAME.json); required: the "
                "scene's triangles, "
                "lights and shading cost decide every method's cost");
  c->add_option("--display", t.display, "Display name or path (models/displays/NAME.json)")
      ->capture_default_str();
  add_number(c, "--width", t.width, "Override the per-eye width", {CostArgRanges::pixels(), "px"});
  add_number(c, "--height", t.height, "Override the per-eye height",
             {CostArgRanges::pixels(), "px"});
  add_number(c, "--eyes", t.eyes, "Override the number of eyes rendered",
             {CostArgRanges::eyes(), "eyes"});
  c->add_option(
      "-m,--method", t.methods,
      "Method and parameters, e.g. full, kfr:sigma=1.8, rmfr:sigma=2.6, twfr:redraw_fraction=0.06, "
      "fvrs, flc:vpl_budget=1024; repeatable (default: " +
          default_methods + ")");
  c->add_option("--models", t.models,
                "Models directory (default: $FOVSIM_MODELS, ./models, or the source tree's)");
  c->add_option("--config", t.config,
                "A run config (configs/*.json): its scene's triangles, lights and indirect light, "
                "its workload, display and methods, as `fovsim run` charges them (replaces "
                "--workload; --display/--width/--height/--eyes/-m override)");
}

// A workload must be named (generic knows no scene): Workload::load_for_costing.
Workload target_workload(const Target& t, const std::string& models) {
  return Workload::load_for_costing(t.workload, models, "--workload",
                                    "or --config CONFIG for a run config's scene");
}

// What predict/budget cost: --config's scene, or --workload with the display flags.
struct Resolved {
  Workload workload;
  Display display;
  bool indirect = false;
  std::vector<MethodSpec> methods;
  std::vector<std::string> gpus;
};

Resolved resolve_target(const Target& t, const std::string& models,
                        const std::vector<std::string>& default_methods, bool display_given) {
  Resolved r;
  r.gpus = t.gpus;
  if (!t.config.empty()) {
    if (!t.workload.empty())
      throw Error("--workload", "give either --workload or --config (its scene), not both");
    const ConfigCostTarget c = config_cost_target(t.config, models);
    r.workload = c.workload;
    r.display = display_given ? Display::load(t.display, models) : c.display;
    r.indirect = c.features.indirect;
    for (auto& m : c.methods) {
      if (!is_cost_method(m.method))
        throw Error(t.config, "no cost model for method \"" + m.method + "\"");
      r.methods.push_back({m.label, m.method, m.params});
    }
    if (r.gpus.empty()) r.gpus = c.gpus;
  } else {
    r.workload = target_workload(t, models);
    r.display = Display::load(t.display, models);
  }
  if (t.width) r.display.width = t.width;
  if (t.height) r.display.height = t.height;
  if (t.eyes) r.display.eyes = t.eyes;
  if (!t.methods.empty() || r.methods.empty()) {
    r.methods.clear();
    for (auto& m : t.methods.empty() ? default_methods : t.methods)
      r.methods.push_back(parse_method(m));
  }
  if (r.gpus.empty())
    throw Error("--gpu", "required (a GPU profile name, e.g. " + std::string(kDefaultGpu) + ")");
  return r;
}

FrameCost cost_for(const GpuProfile& g, const MethodSpec& m, const Resolved& r) {
  return analytic_frame(g, m.name, m.params, r.workload, r.display, "--method " + m.text,
                        r.indirect);
}

// Footnote for spec-transfer profiles.
void print_uncalibrated_note(const std::vector<GpuProfile>& gs) {
  for (auto& g : gs)
    if (!g.calibrated)
      std::cout << "* " << escape_control(g.name, 80)
                << ": calibrated = no, a spec-sheet transfer (no calibration table used this GPU); "
                   "its interval is widened x"
                << fmt("%.2f", g.interval.widen) << " in log space"
                << (g.architecture.empty() ? std::string() : "; " + g.architecture) << "\n";
}

// Every cell escaped (escape_control): a GPU, workload or method name from a file never
// carries an ESC sequence or a line break into the terminal.
void print_table(std::vector<std::vector<std::string>> rows) {
  if (rows.empty()) return;
  for (auto& r : rows)
    for (auto& cell : r) cell = escape_control(cell, 80);
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
  std::string models, tables, model = "roofline", out = "results/calibrate";
  bool dry_run = false, quiet = false;
};

int do_calibrate(const CalibrateArgs& a) {
  CalibrateOptions o;
  o.models = models_or_default(a.models);
  o.tables = parse_id_list(a.tables, "--tables");
  o.model = a.model == "linear" ? CostModelKind::Linear : CostModelKind::Roofline;
  o.write = !a.dry_run;
  o.out = a.out;
  const CalibrationRun run = run_calibration(o);
  if (!a.quiet) {
    std::vector<std::vector<std::string>> rows = {{"table", "gpu", "workload", "config", "row",
                                                   "use", "published [ms]", "model [ms]",
                                                   "rel_err [%]"}};
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
    std::cout << "\nshared work per counter unit (theta; coefficient in ms per unit = theta / "
                 "spec rate of its resource):\n";
    for (auto& [k, v] : run.fit.theta)
      std::cout << "  " << k << " = " << fmt("%.6g", v) << " " << theta_unit(k) << "\n";
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
  double tracking_loss = -1;  // < 0: not given
  std::string on_invalid = "hold";
  double widen_k = 1.75;
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
    j["label"] = x.label;
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
    std::cout << "results " << a.results << " re-costed for display " << escape_control(d.name, 80)
              << " " << d.width << "x" << d.height << " x" << d.eyes << " eye(s), workload "
              << res.workload << "; mean ms per frame ('-': pass does not exist)\n";
    print_table(rows);
  }
  return 0;
}

int do_predict(const PredictArgs& a) {
  if (!a.results.empty()) return do_predict_results(a);
  const std::string models = models_or_default(a.t.models);
  const Resolved res = resolve_target(a.t, models, {"full"}, a.display_given);
  const Workload& w = res.workload;
  const Display& d = res.display;
  const std::vector<MethodSpec>& methods = res.methods;
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  std::vector<std::vector<std::string>> rows;
  std::vector<GpuProfile> used;
  std::vector<std::string> header = {"gpu", "calibrated", "method"};
  for (auto& p : known_passes()) header.push_back(p);
  header.push_back("total_ms");
  header.push_back("interval_ms");
  header.push_back("speedup");
  // Tracking loss (docs/tracking.md "What each policy costs"): lost frames costed as the policy
  // renders them, and the expected frame time with that loss fraction.
  const bool loss = a.tracking_loss >= 0;
  OnInvalid policy = OnInvalid::Hold;
  parse_on_invalid(a.on_invalid, policy);
  if (loss) {
    header.push_back("lost_ms");
    header.push_back("with_loss_ms");
  }
  rows.push_back(header);
  for (auto& gname : res.gpus) {
    GpuProfile g = GpuProfile::load(gname, models);
    used.push_back(g);
    double full_total = cost_for(g, parse_method("full"), res).total_ms;
    for (auto& m : methods) {
      FrameCost fc = cost_for(g, m, res);
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
      if (!a.t.config.empty()) j["label"] = m.text, j["indirect"] = res.indirect;
      if (!fc.missing_counters.empty()) j["missing_counters"] = fc.missing_counters;
      out.push_back(j);
      std::vector<std::string> r = {g.name, g.calibrated ? "yes" : "no*", m.text};
      for (auto& p : known_passes()) {
        bool exists = false;
        for (auto& pc : fc.passes) exists |= pc.pass == p;
        r.push_back(exists ? fmt("%.3f", fc.pass_ms(p)) : "-");
      }
      r.push_back(fmt("%.3f", fc.total_ms));
      r.push_back(fc.interval_level > 0 ? fmt("%.2f-", fc.total_lo_ms) + fmt("%.2f", fc.total_hi_ms)
                                        : "-");
      r.push_back(fmt("%.2fx", fc.total_ms > 0 ? full_total / fc.total_ms : 0.0));
      if (loss) {
        MethodSpec lm = m;
        lm.name = lost_frame_method(m.name, policy);
        if (lm.name == "full" && m.name != "full") lm.params = Json::object();
        bool modelled = true;
        if (policy == OnInvalid::Widen)
          lm.params = widened_method_params(lm.name, lm.params, a.widen_k, &modelled, &res.display);
        const double lost = modelled ? cost_for(g, lm, res).total_ms : double(NAN);
        const double expect = expected_ms_with_loss(fc.total_ms, lost, a.tracking_loss);
        j["tracking_loss"] = {{"fraction", a.tracking_loss},
                              {"on_invalid", a.on_invalid},
                              {"widen_k", policy == OnInvalid::Widen ? Json(a.widen_k) : Json()},
                              {"lost_ms", modelled ? Json(lost) : Json()},
                              {"est_ms_total_with_loss", modelled ? Json(expect) : Json()}};
        out.back() = j;
        r.push_back(modelled ? fmt("%.3f", lost) : "-");
        r.push_back(modelled ? fmt("%.3f", expect) : "-");
      }
      rows.push_back(r);
    }
  }
  if (a.json) {
    std::cout << out.dump(2) << "\n";
  } else {
    std::cout << "workload " << escape_control(w.name, 80) << ", display "
              << escape_control(d.name, 80) << " " << d.width << "x" << d.height << " x" << d.eyes
              << " eye(s); ms per frame ('-': pass does not exist); interval_ms: the profile's "
              << "prediction interval on the total (docs/cost_model.md)"
              << (a.t.config.empty() ? std::string()
                                     : std::string("; scene of ") + a.t.config +
                                           (res.indirect ? " (indirect light)" : ""))
              << "\n";
    print_table(rows);
    if (loss)
      std::cout << "tracking loss: " << fmt("%.3g", a.tracking_loss) << " of the frames under "
                << "trace.on_invalid = " << a.on_invalid
                << (policy == OnInvalid::Widen ? " (k = " + fmt("%.3g", a.widen_k) + ")" : "")
                << "; lost_ms: a lost frame as the policy renders it, with_loss_ms = (1 - f) "
                   "total_ms + f lost_ms ('-': twfr's widened cost is not analytic; run it)\n";
    print_uncalibrated_note(used);
  }
  return 0;
}

// ---------------------------------------------------------------- budget
struct BudgetArgs {
  Target t;
  double hz = 90, budget_ms = 0, target_p = kDefaultFitLevel;
  double s_shading = 1, s_geometry = 1, s_raster = 1, s_memory = 1, s_fixed = 1;
  bool json = false, display_given = false, workload_given = false;
  std::string results;  // budget of a finished run's measured counters
};

std::string pct(double p) {
  return fmt("%.0f%%", 100 * p);
}

// `fovsim budget --results RUN`: the run's (or each sweep cell's) re-costed frame time against
// the budget: verdict, headroom and the probability of fitting (logic: recost_results).
int do_budget_results(const BudgetArgs& a, double budget) {
  if (a.t.gpus.empty()) throw Error("--gpu", "required with --results");
  RecostOptions o;
  o.results = a.results;
  o.models = models_or_default(a.t.models);
  o.gpus = a.t.gpus;
  if (a.display_given) o.display = a.t.display;
  o.width = a.t.width, o.height = a.t.height, o.eyes = a.t.eyes;
  if (a.workload_given) o.workload = a.t.workload;
  const RecostResult res = recost_results(o);
  std::map<std::string, GpuProfile> gs;
  std::vector<GpuProfile> used;
  for (auto& n : a.t.gpus) {
    gs.emplace(n, GpuProfile::load(n, o.models));
    used.push_back(gs.at(n));
  }
  std::vector<std::vector<std::string>> rows = {{"gpu", "calibrated", "config_id", "total_ms",
                                                 "interval_ms", "budget_ms", "fits", "p_fit",
                                                 "headroom_ms"}};
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const RecostRow& x : res.rows) {
    const GpuProfile* g = nullptr;
    for (auto& [n, p] : gs)
      if (p.name == x.gpu) g = &p;
    const BudgetDecision bd =
        decide_budget(g ? g->interval : PredictionInterval{}, x.total_ms, budget, a.target_p);
    const double pf = bd.p_fit;
    const char* verdict = bd.verdict;
    rows.push_back({x.gpu, g && !g->calibrated ? "no*" : "yes", x.config_id,
                    fmt("%.3f", x.total_ms),
                    x.level > 0 ? fmt("%.2f-", x.lo_ms) + fmt("%.2f", x.hi_ms) : "-",
                    fmt("%.2f", budget), verdict, pct(pf), fmt("%+.3f", budget - x.total_ms)});
    out.push_back({{"gpu", x.gpu},
                   {"config_id", x.config_id},
                   {"method", x.method},
                   {"est_ms_total", x.total_ms},
                   {"budget_ms", budget},
                   {"verdict", verdict},
                   {"p_fit", pf},
                   {"fits", bd.fits},
                   {"fit_level", a.target_p},
                   {"headroom_ms", budget - x.total_ms}});
  }
  if (a.json) {
    std::cout << out.dump(2) << "\n";
  } else {
    std::cout << "results " << a.results << " re-costed for display " << res.display.name << " "
              << res.display.width << "x" << res.display.height << " x" << res.display.eyes
              << " eye(s), workload " << res.workload << "; budget " << fmt("%.2f", budget)
              << " ms; p_fit: probability that the frame fits (held-out total errors); fits: "
                 "p_fit >= "
              << pct(a.target_p) << ", does not fit: p_fit <= " << pct(1 - a.target_p)
              << ", else uncertain (--p)\n";
    print_table(rows);
    print_uncalibrated_note(used);
  }
  return 0;
}

int do_budget(const BudgetArgs& a) {
  const double budget = a.budget_ms > 0 ? a.budget_ms : 1000.0 / a.hz;
  if (!a.results.empty()) return do_budget_results(a, budget);
  const std::string models = models_or_default(a.t.models);
  const Resolved res = resolve_target(a.t, models, budget_default_methods(), a.display_given);
  const Workload& w = res.workload;
  const Display& d = res.display;
  std::vector<std::vector<std::string>> rows = {
      {"gpu", "calibrated", "method", "total_ms", "interval_ms", "budget_ms", "fits", "p_fit",
       "change_for_" + pct(a.target_p), "headroom_ms", "x_shading", "x_geometry", "x_raster",
       "x_memory", "x_fixed", "x_all"}};
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  WhatIf wi;
  wi.shading = a.s_shading, wi.geometry = a.s_geometry, wi.raster = a.s_raster;
  wi.memory = a.s_memory, wi.fixed = a.s_fixed;
  auto factor_text = [](double f) { return std::isfinite(f) ? fmt("%.2f", f) : "inf"; };
  auto factor_json = [](double f) { return std::isfinite(f) ? Json(f) : Json("inf"); };
  std::vector<GpuProfile> used;
  for (auto& gname : res.gpus) {
    GpuProfile g = apply_what_if(GpuProfile::load(gname, models), wi);
    used.push_back(g);
    for (const MethodSpec& m : res.methods) {
      FrameCost fc = cost_for(g, m, res);
      const double T = fc.total_ms;
      const bool iv = fc.interval_level > 0;
      const BudgetDecision bd = decide_budget(g.interval, T, budget, a.target_p);
      const char* verdict = bd.verdict;
      const double pf = bd.p_fit;
      BudgetQuery q;
      q.gpu = &g, q.method = m.name, q.params = m.params, q.workload = &w, q.display = d;
      q.indirect = res.indirect, q.where = "--method " + m.text;
      const std::vector<BudgetChange> changes = fitting_changes(q, budget, a.target_p);
      const std::string change = changes.empty() ? "none found" : changes.front().text;
      std::vector<std::string> r = {
          g.name,
          g.calibrated ? "yes" : "no*",
          m.text,
          fmt("%.3f", T),
          iv ? fmt("%.2f-", fc.total_lo_ms) + fmt("%.2f", fc.total_hi_ms) : "-",
          fmt("%.2f", budget),
          verdict,
          pct(pf),
          change,
          fmt("%+.3f", budget - T)};
      nlohmann::ordered_json j = {{"gpu", g.name},
                                  {"calibrated", g.calibrated},
                                  {"method", m.text},
                                  {"est_ms_total", T},
                                  {"budget_ms", budget},
                                  {"fits", bd.fits},
                                  {"fit_level", a.target_p},
                                  {"verdict", verdict},
                                  {"p_fit", pf},
                                  {"headroom_ms", budget - T}};
      nlohmann::ordered_json cj = nlohmann::ordered_json::array();
      for (auto& c : changes)
        cj.push_back({{"kind", c.kind},
                      {"change", c.text},
                      {"value", c.value},
                      {"est_ms_total", c.total_ms},
                      {"p_fit", c.probability}});
      j["changes_for_p"] = a.target_p;
      j["changes"] = cj;
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
    std::cout << "budget " << fmt("%.2f", budget) << " ms; workload " << escape_control(w.name, 80)
              << ", display " << d.width << "x" << d.height << " x" << d.eyes
              << " eye(s); what-if throughput x shading " << a.s_shading << ", geometry "
              << a.s_geometry << ", raster " << a.s_raster << ", memory " << a.s_memory
              << ", fixed " << a.s_fixed << "\n"
              << "p_fit: probability that the frame fits (held-out frame-total errors, "
                 "docs/cost_model.md); fits: p_fit >= "
              << pct(a.target_p) << ", does not fit: p_fit <= " << pct(1 - a.target_p)
              << ", else uncertain (--p); change_for_" << pct(a.target_p)
              << ": the cheapest change reaching that probability (the "
              << "method's parameter, then resolution, then GPU throughput)\n"
              << "x_<resource>: throughput factor that resource alone needs to fit (<1: slack; "
                 "inf: cannot fit alone); x_all: uniform factor on everything but fixed "
                 "overheads\n";
    print_table(rows);
    print_uncalibrated_note(used);
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
                           "tables (models/calibration) and write profiles to --out");
    c->add_option("--models", a->models,
                  "Models directory (default: $FOVSIM_MODELS, ./models, or the source tree's)");
    c->add_option("--tables", a->tables,
                  "Comma-separated calibration table ids to fit (default: all)");
    c->add_flag("--dry-run", a->dry_run,
                "Print the fit and residuals without writing profiles or workloads");
    c->add_option("--out", a->out,
                  "Directory for OUT/gpus/*.json and OUT/workloads/*.json (`--out models` "
                  "replaces the committed profiles)")
        ->capture_default_str();
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
    add_number(c, "--tracking-loss", a->tracking_loss,
               "Fraction of frames with tracking lost: adds lost_ms and with_loss_ms "
               "(docs/tracking.md)",
               {Range::closed(0, 1), "fraction"});
    c->add_option("--on-invalid", a->on_invalid,
                  "Policy on lost frames with --tracking-loss (docs/tracking.md)")
        ->check(CLI::IsMember(on_invalid_choices()))
        ->capture_default_str();
    add_number(c, "--widen-k", a->widen_k,
               "With --on-invalid widen: mean foveal growth factor k over the lost frames "
               "(default 1.75 = 1 + 10/s x 75 ms, the middle of a 150 ms blink)",
               {Range::closed(1, 1000), "factor"})
        ->capture_default_str();
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
    add_target_options(c, a->t, join_names(budget_default_methods()) + " (every method)");
    add_number(c, "--hz", a->hz,
               "Refresh rate whose frame time is the budget (e.g. 72, 90, 120, 144)",
               {CostArgRanges::hz(), "Hz"})
        ->capture_default_str();
    add_number(c, "--budget-ms", a->budget_ms, "Frame budget (overrides --hz)",
               {CostArgRanges::budget_ms(), "ms"});
    add_number(c, "--scale-shading", a->s_shading, "What-if: multiply shading (FP32) throughput",
               {CostArgRanges::scale(), "factor"});
    add_number(c, "--scale-geometry", a->s_geometry,
               "What-if: multiply geometry (triangle) throughput",
               {CostArgRanges::scale(), "factor"});
    add_number(c, "--scale-raster", a->s_raster, "What-if: multiply raster (fill) throughput",
               {CostArgRanges::scale(), "factor"});
    add_number(c, "--scale-memory", a->s_memory, "What-if: multiply memory bandwidth",
               {CostArgRanges::scale(), "factor"});
    add_number(c, "--scale-fixed", a->s_fixed,
               "What-if: divide fixed per-pass overheads by this factor",
               {CostArgRanges::scale(), "factor"});
    c->add_flag("--json", a->json, "Print JSON");
    add_number(c, "--p", a->target_p,
               "Level of every budget decision: a configuration fits when its probability of "
               "fitting (p_fit) reaches it, does not fit at or below 1 - it, and the cheapest "
               "change must reach it (default 0.8)",
               {fit_level_range(), "probability"});
    c->add_option("--results", a->results,
                  "A results directory of `fovsim run` (or a sweep folder: every cell): the "
                  "verdict, probability and headroom of its measured counters re-costed for --gpu");
    c->callback([a, &action, c]() {
      a->display_given = c->get_option("--display")->count() > 0;
      a->workload_given = c->get_option("--workload")->count() > 0;
      action = [a]() { return do_budget(*a); };
    });
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
