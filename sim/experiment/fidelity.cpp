#include "sim/experiment/fidelity.h"

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/progress.h"
#include "sim/core/text.h"
#include "sim/experiment/fidelity_report.h"
#include "sim/experiment/runner.h"
#include "sim/experiment/sweep_runner.h"
#include "sim/experiment/sweep_spec.h"
#include "sim/metrics/registry.h"
#include "sim/render/renderer.h"

// The ladder itself: rungs parsed, each run (the top rung first), then the report
// (fidelity_report.cpp). The analytic rung is analytic_summary (config_cost.cpp, beside
// `predict --config`); the comparison statistics are in fidelity_stats.cpp.
namespace fovsim {

namespace fs = std::filesystem;

namespace {

// One rung from its token ("analytic" or overrides separated by ',').
FidelityRung parse_rung(const std::string& token, const std::string& flag) {
  FidelityRung r;
  r.name = trim(token);
  const std::string where = flag + " " + (r.name.empty() ? "\"\"" : r.name);
  if (r.name.empty())
    throw Error(where,
                "empty rung (rungs are separated by ';', e.g. analytic;scale=0.25;stride=2)");
  if (r.name == "analytic") {
    r.analytic = true;
    return r;
  }
  std::set<std::string> knobs;
  for (auto& part : split(r.name, ',')) {
    std::string p = trim(part);
    size_t eq = p.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 >= p.size())
      throw Error(where, "expected analytic, scale=X, stride=N, spp=N or key.path=value, got \"" +
                             p + "\"");
    std::string key = p.substr(0, eq), val = p.substr(eq + 1);
    // Each knob once per rung ("scale" and "render.scale" are one knob): a repeat would
    // silently keep only the last value.
    const std::string knob = key == "scale" ? "render.scale" : key == "spp" ? "render.spp" : key;
    if (!knobs.insert(knob).second)
      throw Error(where, "\"" + knob + "\" is given twice in one rung (each knob once)");
    auto number = [&](double lo, double hi, bool integer) {
      char* end = nullptr;
      double v = std::strtod(val.c_str(), &end);
      if (end == val.c_str() || *end != 0 || !std::isfinite(v) || v <= lo || v > hi ||
          (integer && v != std::floor(v)))
        throw Error(where, key + " must be " + (integer ? "an integer" : "a number") + " in (" +
                               format_number(lo) + ", " + format_number(hi) + "], got \"" + val +
                               "\"");
      return v;
    };
    if (key == "scale") {
      number(0, 4, false);
      r.overrides.push_back("render.scale=" + val);
    } else if (key == "stride") {
      r.stride = int(number(0, 1e6, true));
    } else if (key == "spp") {
      number(0, 1e6, true);
      r.overrides.push_back("render.spp=" + val);
      if (!render_spp_known())
        r.skipped = "render.spp is not a key of this build's render settings";
    } else if (key.find('.') != std::string::npos || key.find('[') != std::string::npos ||
               key == "seed" || key == "workload") {
      r.overrides.push_back(p);  // a raw override, checked when the rung's config is loaded
    } else {
      throw Error(where, "unknown knob \"" + key +
                             "\" (scale, stride, spp, or a config key.path such as render.scale)");
    }
  }
  return r;
}

// User + system CPU time of this process (all threads): on a machine shared with other jobs a
// rung's CPU time is a steadier measure of its cost than its wall time.
double cpu_seconds() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// The top rung's config with a rung's overrides on top; a stride rung covers the same span of
// the trace with every N-th frame. Images are not written: the ladder measures the simulation.
LoadedConfig rung_config(const LoadedConfig& top_cfg, const FidelityRung& r) {
  LoadedConfig c = top_cfg;
  for (auto& o : r.overrides) apply_override(c.doc, o);
  if (r.stride > 1) {  // the same span of the trace, every N-th frame
    const Json fr = c.doc.contains("frames") ? c.doc["frames"] : Json::object();
    long stride =
        fr.contains("stride") && fr["stride"].is_number_integer() ? fr["stride"].get<long>() : 1;
    long count =
        fr.contains("count") && fr["count"].is_number_integer() ? fr["count"].get<long>() : 0;
    c.doc["frames"]["stride"] = stride * r.stride;
    if (count > 0) c.doc["frames"]["count"] = (count + r.stride - 1) / r.stride;
  }
  // The ladder measures the simulation, not image writing.
  c.doc["outputs"]["image_frames"] = Json::array();
  return c;
}

// A sweep config: every rung runs the whole sweep (shared references, sweep_runner.h); rows
// are per cell x config, config_id "<cell index>/<config_id>".
ResultTable prefixed(const ResultTable& t, int cell) {
  ResultTable out;
  for (auto& r : t.rows()) {
    ResultRow x;
    for (auto& [k, v] : r.text)
      x.set_text(k, k == "config_id" ? std::to_string(cell) + "/" + v : v);
    x.set_text("cell", std::to_string(cell));
    for (auto& [k, v] : r.num) x.set(k, v);
    out.add(std::move(x));
  }
  return out;
}

void append(ResultTable& dst, const ResultTable& src) {
  for (auto& r : src.rows()) dst.add(r);
}

// Runs rung `i`: the analytic prediction on the top rung's config, or the rendered run (the
// whole sweep for a sweep config) into <out>/rungs/<i>-<name>/. Wall and CPU time included.
RungRun run_rung(size_t i, const FidelityRung& r, const LoadedConfig& top_cfg, bool is_sweep,
                 const FidelityOptions& opt, const std::string& out_dir,
                 std::vector<std::string>& notes_out) {
  using Clock = std::chrono::steady_clock;
  RungRun d;
  auto t0 = Clock::now();
  const double c0 = cpu_seconds();
  if (r.analytic && is_sweep) {
    std::vector<std::string> notes;
    SweepPlan plan = expand_sweep(top_cfg);
    for (auto& cell : plan.cells) {
      LoadedConfig cc = top_cfg;
      cc.doc = cell.doc;
      append(d.summary, prefixed(analytic_summary(cc, opt.models_dir, &notes), cell.index));
    }
    for (auto& n : notes) notes_out.push_back(n);
  } else if (r.analytic) {
    std::vector<std::string> notes;
    d.summary = analytic_summary(top_cfg, opt.models_dir, &notes);
    for (auto& n : notes) notes_out.push_back(n);
  } else if (is_sweep) {
    LoadedConfig rc = rung_config(top_cfg, r);
    SweepPlan plan = expand_sweep(rc);
    validate_cells(plan);
    SweepOptions so;
    so.out_dir = out_dir + "/rungs/" + std::to_string(i) + "-" + safe_file_name(r.name);
    so.models_dir = opt.models_dir;
    so.threads = opt.threads;
    so.watchdog_s = opt.watchdog_s;
    so.use_cache = opt.use_cache;
    so.command_line = opt.command_line + " [rung " + r.name + "]";
    run_sweep(plan, rc, so);
    d.dir = so.out_dir;
    for (auto& cell : plan.cells) {
      std::string cd = so.out_dir + "/runs/" + cell.id();
      append(d.summary, prefixed(read_cell_summary(cd), cell.index));
    }
    d.resolved = top_cfg.doc;
  } else {
    RunOptions ro;
    ro.out_dir = out_dir + "/rungs/" + std::to_string(i) + "-" + safe_file_name(r.name);
    ro.models_dir = opt.models_dir;
    ro.threads = opt.threads;
    ro.print_summary = false;
    ro.watchdog_s = opt.watchdog_s;
    ro.use_cache = opt.use_cache;
    ro.command_line = opt.command_line + " [rung " + r.name + "]";
    RunResult rr = run_experiment(rung_config(top_cfg, r), ro);
    d.dir = rr.out_dir;
    d.summary = std::move(rr.summary);
    d.frames = std::move(rr.frames);
    try {
      const std::string mf = rr.out_dir + "/manifest.json";
      d.resolved = parse_json_text(read_file(mf), mf)["resolved_config"];
    } catch (const std::exception&) {
      d.resolved = nullptr;
    }
  }
  d.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  d.cpu_s = cpu_seconds() - c0;
  return d;
}

}  // namespace

bool render_spp_known() {
  Params p(Json{{"spp", 1}}, "", "render");
  try {
    (void)RenderSettings::from_params(p);
    p.finish();
  } catch (const Error&) {
    return false;
  }
  return true;
}

const std::vector<std::string>& fidelity_outputs() {
  static const std::vector<std::string> o = [] {
    std::vector<std::string> v = {"est_ms_total", "est_ms_total_p95", "shaded_fraction"};
    for (auto& n : headline_metric_names()) v.push_back(n);  // the metric registry
    return v;
  }();
  return o;
}

std::vector<FidelityRung> parse_rungs(const std::string& rungs, const std::string& top) {
  std::vector<FidelityRung> out;
  if (trim(rungs).empty()) throw Error("--rungs", "no rungs given (e.g. analytic;scale=0.25)");
  std::set<std::string> names;
  for (auto& tok : split(rungs, ';')) {
    FidelityRung r = parse_rung(tok, "--rungs");
    if (!names.insert(r.name).second) throw Error("--rungs " + r.name, "rung given twice");
    out.push_back(std::move(r));
  }
  if (top.find(';') != std::string::npos)
    throw Error("--top " + top, "the top rung is one rung (overrides separated by ',')");
  FidelityRung t = parse_rung(top, "--top");
  if (t.analytic) throw Error("--top analytic", "the top rung (the truth) must render");
  if (!t.skipped.empty()) throw Error("--top " + t.name, t.skipped);
  t.top = true;
  if (names.count(t.name))
    throw Error("--rungs " + t.name, "equals the top rung (--top), which always runs");
  out.push_back(std::move(t));
  return out;
}

FidelityResult run_fidelity(const LoadedConfig& cfg, const FidelityOptions& opt) {
  std::vector<FidelityRung> rungs = parse_rungs(opt.rungs, opt.top);
  FidelityResult res;
  std::string name = cfg.doc.contains("name") && cfg.doc["name"].is_string()
                         ? cfg.doc["name"].get<std::string>()
                         : fs::path(cfg.file).stem().string();
  res.out_dir = opt.out_dir.empty() ? "results/" + safe_file_name(name) + "_fidelity" : opt.out_dir;
  // Locked (a second fidelity run on this folder stops) and an OutputRoot (no link inside it
  // is written through).
  DirLock lock(res.out_dir, ".lock", "another fovsim fidelity run");
  make_dirs(res.out_dir + "/rungs");

  // The top rung's config; every other rung's overrides apply on top of it.
  LoadedConfig top_cfg = cfg;
  for (auto& o : rungs.back().overrides) apply_override(top_cfg.doc, o);
  const bool is_sweep = cfg.doc.contains("sweep");

  // Every rung's overrides are applied once before anything runs: a bad path fails at once,
  // not after the top rung's minutes. (Unknown keys are found when the rung's config is read.)
  for (auto& r : rungs)
    if (!r.analytic && r.skipped.empty()) (void)rung_config(top_cfg, r);

  // The truth first (its wall time is the unit), then the rungs in the given order.
  std::vector<RungRun> runs(rungs.size());
  std::vector<size_t> order{rungs.size() - 1};
  for (size_t i = 0; i + 1 < rungs.size(); ++i) order.push_back(i);
  Progress progress("fidelity rungs", order.size());  // a rung's sweep or frames nest inside
  for (size_t i : order) {
    const FidelityRung& r = rungs[i];
    if (!r.skipped.empty()) {
      res.notes.push_back("rung " + r.name + " skipped: " + r.skipped);
      progress.step();
      continue;
    }
    progress.phase("rung " + r.name);
    if (opt.progress) {
      std::printf("fidelity: rung %s%s ...\n", r.name.c_str(), r.top ? " (top, the truth)" : "");
      std::fflush(stdout);
    }
    runs[i] = run_rung(i, r, top_cfg, is_sweep, opt, res.out_dir, res.notes);
    progress.step();
  }
  progress.phase("report");
  write_fidelity_report(name, cfg, opt, rungs, runs, res);
  return res;
}

}  // namespace fovsim
