#include "sim/experiment/cell_outputs.h"

#include <cmath>

#include "sim/core/files.h"
#include "sim/core/memory_info.h"
#include "sim/experiment/cell.h"
#include "sim/experiment/cell_manifest.h"
#include "sim/experiment/intervals.h"
#include "sim/experiment/latency.h"
#include "sim/experiment/reference_side.h"
#include "sim/experiment/summary.h"
#include "sim/experiment/tracking_summary.h"
#include "sim/metrics/registry.h"

namespace fovsim {

StartupPlan startup_plan(const Cell& c, const Shared& sh) {
  StartupPlan p;
  p.include = sh.include_startup;
  p.warmup_rendered = sh.warmup;
  for (const MethodRun& m : c.methods) p.method_frames[m.label] = m.impl->warmup_frames();
  const double fps = c.metric.side->video ? sh.display.refresh_hz : 0.0;  // as the streams ran
  for (auto& d : metric_registry()) {
    if (!d.sequence || !d.sequence->enabled(c.metric.cfg) || !d.sequence->settle_frames) continue;
    StartupPlan::Metric m;
    m.name = d.name;
    m.frames = d.sequence->settle_frames(fps);
    m.seconds = fps > 0 ? m.frames / fps : 0.0;
    for (const std::string& col : {d.pooled_column, d.name})
      m.columns.insert(m.columns.end(), {col, col + kFoveationLossSuffix});
    p.metrics.push_back(std::move(m));
  }
  return p;
}

CellResult write_cell_outputs(Cell& c, const Shared& sh, const GroupOutputs& g) {
  const std::string& out = c.job->out_dir;
  CellResult r;
  r.out_dir = out;
  r.name = c.name;
  r.budget_ms = sh.display.frame_budget_ms();
  r.refresh_hz = sh.display.refresh_hz;
  r.print_summary = c.print_table;
  r.flags.assign(c.flags_seen.begin(), c.flags_seen.end());
  if (g.rcache) {  // entries found unusable (recomputed), a cache that could not be written
    for (auto& w : g.rcache->warnings()) c.warnings.push_back(w);
    if (g.memo)
      for (auto& w : g.memo->warnings()) c.warnings.push_back(w);
    if (!c.warnings.empty()) c.manifest["warnings"] = c.warnings;
  } else if (!g.no_cache_dir.empty()) {
    c.warnings.push_back(g.no_cache_dir);
    c.manifest["warnings"] = c.warnings;
  }
  r.warnings = c.warnings;
  if (c.manifest["fidelity"].contains("note"))
    r.fidelity_note = c.manifest["fidelity"]["note"].get<std::string>();
  r.fidelity = c.manifest["fidelity"];
  r.cell_ms = c.cell_ms;
  // The means leave out the start-up frames (startup.h; frames.csv keeps them).
  const StartupPlan plan = startup_plan(c, sh);
  StartupReport startup;
  const ResultTable means = exclude_startup(c.frames, plan, startup);
  c.manifest["startup"] = startup.manifest;
  FitRule fit;  // the budget decisions: budget.p_fit and each profile's interval
  fit.level = c.cost.fit_level;
  for (auto& g : c.cost.gpus) fit.intervals.emplace(g.name, g.interval);
  r.summary = summarize(means, r.budget_ms, &fit);
  mark_startup(r.summary, startup, plan);
  r.notes = startup.notes;
  for (auto& n : interval_notes(r.summary)) r.notes.push_back(n);
  if (c.metric.cfg.foveation_loss)
    mark_reference_floor(r.summary, means, [&c](const std::string& label) -> const FloorValues* {
      for (auto& m : c.methods)
        if (m.label == label) return &m.side->floor_vals;
      return nullptr;
    });
  if (c.latency.config.enabled)
    r.summary = summarize_phases(means, r.summary, c.latency.metric_names);
  // Tracking states (docs/tracking.md): means with intervals per state, next to the phases.
  if (sh.tracking_column) r.summary = summarize_tracking(means, r.summary);
  if (g.order.sampled()) {  // what --target asked for and what it achieved (results/README.md)
    Json specs = Json::array(), achieved;
    for (auto& t : g.opt.targets) specs.push_back(t.spec);
    targets_met(g.opt.targets, c.frames, &achieved);
    r.target = {{"targets", specs},
                {"met", c.target.met},
                {"seed", sh.seed},
                {"order", g.order.shuffled() ? "random_units" : "trace"},
                {"unit_frames", g.order.unit_frames()},
                {"warmup_per_unit", kTargetWarmupFrames},
                {"frames_available", sh.count},
                {"frames_used", c.target.used},
                {"warmup_frames", c.target.warmup},
                {"achieved", achieved}};
    c.manifest["target"] = r.target;
  }
  // A JOD metric below native resolution: its bias (or that it has none measured) is said.
  const Json& jod = c.manifest["fidelity"]["jod"];
  bool has_jod = false;
  for (auto& row : r.summary.rows())
    has_jod = has_jod || !std::isnan(row.get("fvvdp_jod", NAN)) ||
              !std::isnan(row.get("fvvdp_jod_fl", NAN));
  if (has_jod && jod.contains("note"))
    r.fidelity_note += (r.fidelity_note.empty() ? "" : "; ") + jod["note"].get<std::string>();
  write_file_atomic(out + "/frames.csv", c.frames.to_csv());
  write_file_atomic(out + "/summary.csv", r.summary.to_csv());
  // Paired differences with the known bias of the run's fidelity (docs/intervals.md): a
  // difference whose interval excludes 0 but that is smaller than the bias is named.
  size_t n_below = 0;
  const ResultTable paired =
      with_fidelity_bias(paired_differences(means), c.manifest["fidelity"], &n_below);
  write_file_atomic(out + "/paired.csv", paired.to_csv());
  if (c.manifest["fidelity"]["known_bias"].is_object())
    c.manifest["fidelity"]["paired_real_below_bias"] = n_below;
  if (n_below > 0)
    r.fidelity_note += "; " + std::to_string(n_below) +
                       " paired difference(s) in paired.csv exclude 0 but are smaller than "
                       "that bias (paired.csv below_fidelity_bias = 1)";
  Json sj = Json::array();
  for (auto& row : r.summary.rows()) {
    Json o;
    for (auto& [k, v] : row.text) o[k] = v;
    for (auto& [k, v] : row.num) o[k] = std::isfinite(v) ? Json(v) : Json(format_number(v));
    sj.push_back(o);
  }
  Json summary{{"name", c.name}, {"budget_ms", r.budget_ms}, {"configs", sj}, {"flags", r.flags}};
  summary["fidelity"] = c.manifest["fidelity"];  // the fidelity used and its known bias
  write_file_atomic(out + "/summary.json", summary.dump(2) + "\n");
  // The methods' limitation flags (as summary.json), e.g. a size below a simulated pixel.
  c.manifest["flags"] = r.flags;
  c.manifest["status"] = "complete";
  c.manifest["end_time"] = iso_now();
  c.manifest["rays_traced"] = g.renderer.rays_traced();
  // How many frames' references came from the reference cache (reference_cache.h).
  c.manifest["reference_cache"] = g.rcache ? Json(g.rcache->manifest()) : Json{{"used", false}};
  if (g.rcache) c.manifest["reference_cache"]["used"] = true;
  // Method entries whose outputs came from the method memo (method_memo.h; their sim_ms is the
  // one recorded when they were computed).
  c.manifest["method_memo"] = g.memo ? Json(g.memo->manifest()) : Json{{"used", false}};
  if (g.memo) c.manifest["method_memo"]["used"] = true;
  if (!c.manifest.contains("memoised_methods")) c.manifest["memoised_methods"] = Json::array();
  PhaseTimes ph = g.group_phases;
  ph.merge(c.phases);
  ph.lap("outputs", g.outputs_start);  // this cell's output files so far (one cell: all of them)
  c.manifest["phases"] = ph.to_json(g.threads);
  // The memory budget, this cell's pass, the estimate and the process's peak resident memory
  // (ru_maxrss) so far (docs/architecture.md "Memory").
  c.manifest["memory"] = g.memory;
  c.manifest["memory"]["peak_rss_bytes"] = double(peak_rss_bytes());
  write_file_atomic(out + "/manifest.json", c.manifest.dump(2) + "\n");
  r.frames = std::move(c.frames);
  return r;
}

}  // namespace fovsim
