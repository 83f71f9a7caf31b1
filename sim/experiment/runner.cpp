#include "sim/experiment/runner.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/stats.h"
#include "sim/experiment/engine.h"
#include "sim/experiment/intervals.h"
#include "sim/experiment/tracking_summary.h"
#include "sim/metrics/registry.h"

namespace fovsim {

namespace {
// What run_experiment returns of its one cell, and the note when it grew the reference cache
// by more than cache.note_mb (engine.h cache_growth_note).
RunResult result_of(CellResult& c, const GroupStats& gs) {
  RunResult result;
  result.out_dir = c.out_dir;
  result.frames = std::move(c.frames);
  result.summary = std::move(c.summary);
  result.target = c.target;
  result.warnings = c.warnings;
  result.printed_summary = c.print_summary;
  result.fidelity_note = c.fidelity_note;
  result.notes = c.notes;
  const std::string grew = cache_growth_note({gs});
  if (!grew.empty()) result.notes.push_back(grew);
  return result;
}
}  // namespace

RunResult run_experiment(const LoadedConfig& cfg, const RunOptions& opt) {
  const auto threads = thread_limit(opt.threads);
  if (cfg.doc.is_object() && cfg.doc.contains("sweep"))
    throw Error(cfg.file + ": sweep", "this is a sweep config: run it with `fovsim sweep " +
                                          cfg.file + "` (`fovsim run` runs one config)");
  // A run is a group of one cell (sim/experiment/engine.h).
  CellJob job;
  job.doc = cfg.doc;
  job.file = cfg.file;
  job.origins = cfg.overridden;
  job.inherited = cfg.inherited;
  job.base_dir = cfg.base_dir;
  job.command_line = opt.command_line;
  std::string name = cfg.doc.contains("name") && cfg.doc["name"].is_string()
                         ? cfg.doc["name"].get<std::string>()
                         : std::filesystem::path(cfg.file).stem().string();
  // The name becomes a folder only through safe_file_name: "../../x" stays under results/.
  job.out_dir = opt.out_dir.empty() ? "results/" + safe_file_name(name) : opt.out_dir;
  EngineOptions eo;
  eo.models_dir = opt.models_dir;
  eo.print_summary = opt.print_summary;
  eo.threads = opt.threads;
  eo.watchdog.min_s = opt.watchdog_s;
  eo.use_cache = opt.use_cache;
  for (auto& t : opt.targets) eo.targets.push_back(parse_target(t));
  GroupStats gs;
  auto cells = run_cells({job}, eo, &gs);
  CellResult& c = cells.front();
  RunResult result = result_of(c, gs);
  if (c.print_summary) {
    // `+-`: half-widths of the 95% intervals (summary.csv `<col>_ci95`; nan below 20 frames).
    // The metric columns are the registry's headline metrics present in the run.
    // `_fl`: against full at the method's sampling rate (the foveation loss alone).
    std::vector<std::pair<std::string, int>> shown;  // column, precision
    if (!result.summary.rows().empty())
      for (auto& n : headline_metric_names(true))
        if (!std::isnan(result.summary.rows().front().get(n, NAN)))
          shown.push_back({n, find_metric(n)->precision});
    std::printf("\n%-16s %-10s %7s %9s %18s", "config", "gpu", "frames", "shaded%", "est_ms");
    for (auto& [n, p] : shown) std::printf(" %16s", n.c_str());
    std::printf("\n");
    auto cell = [](double v, double ci, int prec) {
      char b[64];
      if (std::isnan(ci))
        std::snprintf(b, sizeof b, "%.*f", prec, v);
      else
        std::snprintf(b, sizeof b, "%.*f+-%.*f", prec, v, prec, ci);
      return std::string(b);
    };
    for (auto& r : result.summary.rows()) {
      const std::string* id = r.text_of("label");
      const std::string* g = r.text_of("gpu");
      // Labels are user text: control bytes are escaped, never sent to the terminal raw.
      std::printf("%-16s %-10s %7.0f %8.1f%% %18s", id ? escape_control(*id).c_str() : "?",
                  g ? escape_control(*g).c_str() : "?", r.get("frames", 0),
                  100 * r.get("shaded_fraction", NAN),
                  cell(r.get("est_ms_total", NAN), r.get("est_ms_total_ci95", NAN), 3).c_str());
      for (auto& [n, p] : shown)
        std::printf(" %16s", cell(r.get(n, NAN), r.get(n + "_ci95", NAN), p).c_str());
      std::printf("\n");
    }
    // Tracking loss (docs/tracking.md): the same means per tracking state, for the states
    // that occur (summary.csv frames_<state>, <col>_<state>, <col>_<state>_ci95).
    if (!result.summary.rows().empty() &&
        !std::isnan(result.summary.rows().front().get("frames_valid", NAN))) {
      std::printf("\nper tracking state (trace.on_invalid; docs/tracking.md):\n");
      std::printf("%-16s %-10s %-6s %7s %9s %18s", "config", "gpu", "state", "frames", "shaded%",
                  "est_ms");
      for (auto& [n, p] : shown) std::printf(" %16s", n.c_str());
      std::printf("\n");
      for (auto& r : result.summary.rows())
        for (const std::string& st : tracking_states()) {
          const double nf = r.get("frames_" + st, 0);
          if (!(nf > 0)) continue;
          const std::string* id = r.text_of("label");
          const std::string* g = r.text_of("gpu");
          auto col = [&](const std::string& n) { return r.get(n + "_" + st, NAN); };
          auto ci = [&](const std::string& n) { return r.get(n + "_" + st + "_ci95", NAN); };
          std::printf("%-16s %-10s %-6s %7.0f %8.1f%% %18s", id ? id->c_str() : "?",
                      g ? g->c_str() : "?", st.c_str(), nf, 100 * col("shaded_fraction"),
                      cell(col("est_ms_total"), ci("est_ms_total"), 3).c_str());
          for (auto& [n, p] : shown)
            std::printf(" %16s", std::isnan(col(n)) ? "-" : cell(col(n), ci(n), p).c_str());
          std::printf("\n");
        }
    }
    std::printf("budget %.2f ms (%.0f Hz); results in %s\n", c.budget_ms, c.refresh_hz,
                c.out_dir.c_str());
    // summary `at_floor`: metrics that measure the reference comparison's 1-spp floor, not the
    // method (a `full` row is that floor by construction and is not listed).
    for (auto& r : result.summary.rows()) {
      const std::string* at = r.text_of("at_floor");
      const std::string* method = r.text_of("method");
      const std::string* id = r.text_of("config_id");
      if (!at || at->empty() || (method && *method == "full")) continue;
      std::printf(
          "at the reference's floor: %s: %s (indistinguishable from full at the same "
          "sampling: the 1-spp aliasing, not the foveation; read the _fl columns)\n",
          id ? id->c_str() : "?", at->c_str());
    }
    for (auto& f : c.flags) std::printf("flag: %s\n", f.c_str());
    if (!c.fidelity_note.empty()) std::printf("fidelity: %s\n", c.fidelity_note.c_str());
    if (c.target.is_object())
      std::printf(
          "target %s after %d of %d frames (+%d warm-up); achieved half-widths in manifest.json\n",
          c.target["met"].get<bool>() ? "met" : "NOT met", c.target["frames_used"].get<int>(),
          c.target["frames_available"].get<int>(), c.target["warmup_frames"].get<int>());
  }
  return result;
}

}  // namespace fovsim
