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
#include "sim/experiment/cost_queries.h"
#include "sim/experiment/info.h"
#include "sim/experiment/plots.h"
#include "sim/experiment/recost.h"
#include "sim/foveation/factory.h"

namespace fovsim::app {

namespace {

std::string models_or_default(const std::string& m) {
  return m.empty() ? default_models_dir() : m;
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

// The CLI's flags as the library's cost target (sim/experiment/cost_queries.h).
CostTarget cost_target(const Target& t, bool display_given) {
  CostTarget c;
  c.models = models_or_default(t.models);
  c.display = display_given || t.config.empty() ? t.display : "";
  c.workload = t.workload;
  c.config = t.config;
  c.gpus = t.gpus;
  c.methods = t.methods;
  c.width = t.width, c.height = t.height, c.eyes = t.eyes;
  return c;
}

double num_of(const nlohmann::ordered_json& j, const std::string& k) {
  return j.contains(k) && j[k].is_number() ? j[k].get<double>() : double(NAN);
}

std::string factor_text(const nlohmann::ordered_json& f) {
  return f.is_number() ? fmt("%.2f", f.get<double>()) : "inf";
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
  PredictLoss loss;
  loss.fraction = a.tracking_loss;
  loss.on_invalid = a.on_invalid;
  loss.widen_k = a.widen_k;
  const CostRows cr = predict_rows(cost_target(a.t, a.display_given), loss);
  const ResolvedCostTarget& res = cr.target;
  const bool with_loss = a.tracking_loss >= 0;
  if (a.json) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (auto& j : cr.rows) out.push_back(j);
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> header = {"gpu", "calibrated", "method"};
  for (auto& p : known_passes()) header.push_back(p);
  for (const char* h : {"total_ms", "interval_ms", "speedup"}) header.push_back(h);
  if (with_loss) header.push_back("lost_ms"), header.push_back("with_loss_ms");
  rows.push_back(header);
  size_t i = 0;
  for (auto& g : cr.gpus)
    for (auto& m : res.methods) {
      const nlohmann::ordered_json& j = cr.rows[i++];
      std::vector<std::string> r = {g.name, g.calibrated ? "yes" : "no*", m.text};
      for (auto& p : known_passes()) {
        const double ms = num_of(j, "est_ms_" + p);
        r.push_back(std::isnan(ms) ? "-" : fmt("%.3f", ms));
      }
      r.push_back(fmt("%.3f", num_of(j, "est_ms_total")));
      r.push_back(j.contains("est_ms_total_lo") ? fmt("%.2f-", num_of(j, "est_ms_total_lo")) +
                                                      fmt("%.2f", num_of(j, "est_ms_total_hi"))
                                                : "-");
      r.push_back(fmt("%.2fx", num_of(j, "speedup_vs_full")));
      if (with_loss) {
        const auto& tl = j["tracking_loss"];
        r.push_back(tl["lost_ms"].is_number() ? fmt("%.3f", tl["lost_ms"].get<double>()) : "-");
        r.push_back(tl["est_ms_total_with_loss"].is_number()
                        ? fmt("%.3f", tl["est_ms_total_with_loss"].get<double>())
                        : "-");
      }
      rows.push_back(r);
    }
  const Display& d = res.display;
  std::cout << "workload " << escape_control(res.workload.name, 80) << ", display "
            << escape_control(d.name, 80) << " " << d.width << "x" << d.height << " x" << d.eyes
            << " eye(s); ms per frame ('-': pass does not exist); interval_ms: the profile's "
            << "prediction interval on the total (docs/cost_model.md)"
            << (a.t.config.empty() ? std::string()
                                   : std::string("; scene of ") + a.t.config +
                                         (res.indirect ? " (indirect light)" : ""))
            << "\n";
  print_table(rows);
  if (with_loss)
    std::cout << "tracking loss: " << fmt("%.3g", a.tracking_loss) << " of the frames under "
              << "trace.on_invalid = " << a.on_invalid
              << (a.on_invalid == "widen" ? " (k = " + fmt("%.3g", a.widen_k) + ")" : "")
              << "; lost_ms: a lost frame as the policy renders it, with_loss_ms = (1 - f) "
                 "total_ms + f lost_ms ('-': twfr's widened cost is not analytic; run it)\n";
  print_uncalibrated_note(cr.gpus);
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
  WhatIf wi;
  wi.shading = a.s_shading, wi.geometry = a.s_geometry, wi.raster = a.s_raster;
  wi.memory = a.s_memory, wi.fixed = a.s_fixed;
  const CostRows cr = budget_rows(cost_target(a.t, a.display_given), budget, a.target_p, wi);
  if (a.json) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (auto& j : cr.rows) out.push_back(j);
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::vector<std::vector<std::string>> rows = {
      {"gpu", "calibrated", "method", "total_ms", "interval_ms", "budget_ms", "fits", "p_fit",
       "change_for_" + pct(a.target_p), "headroom_ms", "x_shading", "x_geometry", "x_raster",
       "x_memory", "x_fixed", "x_all"}};
  for (auto& j : cr.rows) {
    const bool calibrated = j["calibrated"].get<bool>();
    std::vector<std::string> r = {
        j["gpu"].get<std::string>(),
        calibrated ? "yes" : "no*",
        j["method"].get<std::string>(),
        fmt("%.3f", num_of(j, "est_ms_total")),
        j.contains("est_ms_total_lo")
            ? fmt("%.2f-", num_of(j, "est_ms_total_lo")) + fmt("%.2f", num_of(j, "est_ms_total_hi"))
            : "-",
        fmt("%.2f", budget),
        j["verdict"].get<std::string>(),
        pct(num_of(j, "p_fit")),
        j["changes"].empty() ? "none found" : j["changes"][0]["change"].get<std::string>(),
        fmt("%+.3f", num_of(j, "headroom_ms"))};
    for (auto& rn : budget_resources()) r.push_back(factor_text(j["factor_" + rn]));
    r.push_back(factor_text(j["factor_all"]));
    rows.push_back(r);
  }
  const Display& d = cr.target.display;
  std::cout << "budget " << fmt("%.2f", budget) << " ms; workload "
            << escape_control(cr.target.workload.name, 80) << ", display " << d.width << "x"
            << d.height << " x" << d.eyes << " eye(s); what-if throughput x shading " << a.s_shading
            << ", geometry " << a.s_geometry << ", raster " << a.s_raster << ", memory "
            << a.s_memory << ", fixed " << a.s_fixed << "\n"
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
  print_uncalibrated_note(cr.gpus);
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
