// `fovsim sweep CONFIG`, `fovsim sweep expand CONFIG`, `fovsim merge DIR`, `fovsim search CONFIG`
// (docs/sweeps.md).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <thread>

#include "sim/app/commands.h"
#include "sim/core/disk_cache.h"
#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/version.h"
#include "sim/experiment/intervals.h"
#include "sim/experiment/plots.h"
#include "sim/experiment/search_runner.h"
#include "sim/experiment/sweep_runner.h"

namespace fovsim::app {

namespace {

struct SweepArgs {
  std::string config, out, shard;
  std::vector<std::string> overrides;
  RunFlags run;  // -j, --models, --no-cache, --watchdog, --target (shared with run, Python)
  int batch = 0;
  double memory_budget_gb = 0;
  bool bench = false, no_plots = false, quiet = false, json = false, allow_partial = false;
  PlotFlags plot;
  std::vector<std::string> sources;
};

std::string command_line(const std::string& cmd, const SweepArgs& a) {
  std::string s = "fovsim " + cmd + " " + a.config;
  for (auto& o : a.overrides) s += " " + o;
  for (auto& t : a.run.targets) s += " --target " + t;
  return s;
}

// Plots and index.html (viz/plot_sweep.py) through the one launcher (sim/experiment/plots.h):
// skipped with one line when /usr/bin/python3 or matplotlib is missing.
void make_plots(const std::string& out, bool quiet, const PlotFlags& flags = {}) {
  std::vector<std::string> args{out};
  for (auto& x : flags.args()) args.push_back(x);
  PlotOutcome p = run_plot_script("plot_sweep.py", args, quiet);
  if (p.status == PlotOutcome::Status::Failed)
    std::fprintf(stderr, "fovsim: %s\n", p.message.c_str());
  else if (p.status == PlotOutcome::Status::Skipped && !p.message.empty() && !quiet)
    std::printf("%s\n", p.message.c_str());
}

void options_common(CLI::App* c, SweepArgs& a) {
  c->add_option("overrides", a.overrides,
                "Overrides key.path=value applied after loading (before expansion)");
  c->add_option("--models", a.run.models,
                "Models directory (default: $FOVSIM_MODELS, ./models, or the source tree's)");
}

// The lines `fovsim sweep` prints about a finished run (or its shard).
void print_sweep_report(const SweepArgs& a, const SweepPlan& plan, const SweepOptions& opt,
                        const SweepReport& r) {
  if (!a.quiet) {
    std::printf("sweep %s: %d cells", plan.name.c_str(), r.cells_total);
    if (opt.shards > 1)
      std::printf(", shard %d/%d holds %d", opt.shard, opt.shards, r.cells_in_shard);
    std::printf("; %d already complete (skipped), %d run in %d reference pass%s (%d references",
                r.cells_done_before, r.cells_run, r.reference_passes,
                r.reference_passes == 1 ? "" : "es", r.reference_frames);
    if (r.reference_frames_from_cache > 0)
      std::printf(", %d from the reference cache", r.reference_frames_from_cache);
    std::printf("); peak resident memory %.2f GB\n", double(r.peak_rss_bytes) / 1e9);
    if (r.cells_other_build)
      std::printf(
          "note: %d complete cell%s in %s/runs came from another build of fovsim (not %s) "
          "and %s computed again\n",
          r.cells_other_build, r.cells_other_build == 1 ? "" : "s", r.out_dir.c_str(),
          fovsim::git_commit().c_str(), r.cells_other_build == 1 ? "was" : "were");
    if (r.stale_dirs)
      std::printf(
          "note: %d folder%s in %s/runs belong to cells no longer in this config (ignored)\n",
          r.stale_dirs, r.stale_dirs == 1 ? "" : "s", r.out_dir.c_str());
    std::printf(
        r.complete
            ? "results in %s (summary.csv)\n"
            : "results in %s; other shards pending: run `fovsim merge %s` when all are done\n",
        r.out_dir.c_str(), r.out_dir.c_str());
  } else {
    std::printf("results in %s\n", r.out_dir.c_str());
  }
  if (!r.cache_note.empty()) std::fprintf(stderr, "note: %s\n", r.cache_note.c_str());
}

// --bench: the timing report and bench.json.
void print_bench(const SweepArgs& a, const SweepReport& r) {
  int threads = a.run.threads > 0 ? a.run.threads : int(std::thread::hardware_concurrency());
  // Elapsed wall over the CPU work per thread: 1.0 when every thread was busy for the
  // whole run; the excess is serial or idle time. Correct for any -j (the summed
  // per-cell wall times below overlap across threads and are shown for the breakdown).
  const double cpu_per_thread = r.cpu_ms / std::max(threads, 1);
  const double ratio = cpu_per_thread > 0 ? r.wall_ms / cpu_per_thread : 0.0;
  Json b{{"cells_run", r.cells_run},
         {"reference_passes", r.reference_passes},
         {"reference_frames", r.reference_frames},
         {"reference_frames_from_cache", r.reference_frames_from_cache},
         {"peak_rss_bytes", r.peak_rss_bytes},
         {"threads", threads},
         {"wall_ms", r.wall_ms},
         {"cpu_ms", r.cpu_ms},
         {"reference_ms", r.ref_ms},
         {"cells_own_ms", r.cell_ms},
         {"setup_ms", r.setup_ms},
         {"ratio_wall_over_cpu_per_thread", ratio}};
  write_file_atomic(r.out_dir + "/bench.json", b.dump(2) + "\n");
  std::printf("bench: %d cells, %d references rendered in %d pass%s, %d threads\n", r.cells_run,
              r.reference_frames, r.reference_passes, r.reference_passes == 1 ? "" : "es", threads);
  std::printf(
      "bench: wall %.1f ms; setup %.1f + references %.1f + cells' own work %.1f (wall "
      "times summed over groups and cells; they overlap across threads)\n",
      r.wall_ms, r.setup_ms, r.ref_ms, r.cell_ms);
  std::printf("bench: CPU %.1f ms (user + sys, all threads) = %.1f ms per thread\n", r.cpu_ms,
              cpu_per_thread);
  std::printf("bench: wall / (CPU / threads) = %.3f\n", ratio);
}

// `sweep expand`: the ordered cell list of a sweep.
void register_sweep_expand(CLI::App* c, Action& action) {
  auto e = std::make_shared<SweepArgs>();
  CLI::App* ex = c->add_subcommand(
      "expand", "Print the ordered cell list of a sweep (cell i is always the same run)");
  ex->add_option("config", e->config, "Sweep config")->required();
  options_common(ex, *e);
  ex->add_flag("--json", e->json, "Print each cell's full run config as JSON lines");
  ex->callback([e, &action]() {
    action = [e]() {
      LoadedConfig cfg = load_config(e->config, e->overrides);
      SweepPlan plan = expand_sweep(cfg);
      validate_cells(plan);
      for (auto& cell : plan.cells) {
        if (e->json) {
          std::printf(
              "%s\n",
              Json{{"index", cell.index}, {"id", cell.id()}, {"config", cell.doc}}.dump().c_str());
          continue;
        }
        std::string as;
        for (auto& x : cell.assign) as += (as.empty() ? "" : " ") + x.path + "=" + x.value.dump();
        std::printf("%d %s %s\n", cell.index, cell.id().c_str(), as.c_str());
      }
      if (!e->json)
        std::fprintf(stderr, "%zu cells, plan %s\n", plan.cells.size(), plan.hash.c_str());
      return 0;
    };
  });
}

void register_sweep(CLI::App& app, Action& action) {
  auto a = std::make_shared<SweepArgs>();
  CLI::App* c = app.add_subcommand("sweep",
                                   "Run a sweep config: every cell over shared references, "
                                   "results/<name>/runs/<index>-<hash>/ + summary.csv; "
                                   "rerunning resumes");
  c->add_option("config", a->config,
                "Sweep config (JSON with a \"sweep\" block); see docs/sweeps.md");
  options_common(c, *a);
  c->add_option("-o,--out", a->out, "Output directory (default: results/<name>)");
  add_run_flags(c, a->run,
                "Stop each cell early: COLUMN:VALUE[%|dB|ms] or ranking[:COLUMN] (repeatable); "
                "each cell's manifest records frames used and achieved half-widths "
                "(docs/intervals.md)");
  c->add_option("--shard", a->shard,
                "Run only shard i of N (\"i/N\", contiguous index ranges); default from "
                "SLURM_ARRAY_TASK_ID/COUNT");
  add_number(c, "--batch", a->batch, "Cells per reference pass (default 0)",
             {Range::closed(0, 1000000), "cells", true,
              "all pending cells of a reference group share one pass"});
  add_number(c, "--memory-budget", a->memory_budget_gb,
             "Memory budget of the cells run together (over the config's run.memory_gb; 10^9 "
             "bytes): as many cells as fit share one pass over the frames, the rest run in later "
             "passes with the same numbers",
             {Range::above(0, 1e6), "GB", false, "75% of MemAvailable"});
  c->add_flag("--bench", a->bench,
              "Print the timing report (references vs. cells' own work) and write bench.json");
  add_plot_flags(c, a->plot);
  c->add_flag("--no-plots,!--plots", a->no_plots,
              "--no-plots: do not run viz/plot_sweep.py at the end; --plots: the default");
  c->add_flag("-q,--quiet", a->quiet, "Print only errors");
  register_sweep_expand(c, action);

  c->callback([a, &action, c]() {
    if (!c->get_subcommands().empty()) return;  // `sweep expand`
    action = [a]() {
      if (a->config.empty())
        throw Error("fovsim sweep", "missing CONFIG (see fovsim sweep --help)");
      for (auto& t : a->run.targets) (void)parse_target(t);  // a bad spec fails before any work
      LoadedConfig cfg = load_config(a->config, a->overrides);
      SweepPlan plan = expand_sweep(cfg);
      validate_cells(plan);
      SweepOptions opt;
      static_cast<RunControl&>(opt) = a->run.control();
      opt.out_dir = a->out;
      opt.batch = a->batch;
      opt.memory_budget_gb = a->memory_budget_gb;
      opt.command_line = command_line("sweep", *a);
      if (!a->shard.empty())
        parse_shard(a->shard, opt.shard, opt.shards);
      else
        shard_from_env(opt.shard, opt.shards);
      SweepReport r = run_sweep(plan, cfg, opt);
      print_sweep_report(*a, plan, opt, r);
      if (a->bench) print_bench(*a, r);
      if (r.complete && !a->no_plots) make_plots(r.out_dir, a->quiet, a->plot);
      return 0;
    };
  });
}

void register_merge(CLI::App& app, Action& action) {
  auto a = std::make_shared<SweepArgs>();
  CLI::App* c = app.add_subcommand("merge",
                                   "Merge a sharded sweep: collect complete cells (also from "
                                   "--from folders), write summary.csv, pareto.csv");
  c->add_option("dir", a->out, "Sweep output folder (holds sweep.json)")->required();
  c->add_option("--from", a->sources,
                "Other output folders of the same sweep (e.g. node-local shard folders)");
  c->add_flag("--allow-partial", a->allow_partial,
              "Write the summaries even when cells are missing");
  c->add_flag("--no-plots", a->no_plots, "Do not run viz/plot_sweep.py");
  c->add_flag("-q,--quiet", a->quiet, "Print only errors");
  c->callback([a, &action]() {
    action = [a]() {
      MergeReport r = merge_sweep(a->out, a->sources, a->allow_partial);
      if (!a->quiet)
        std::printf("merge %s: %d of %d cells (%d copied), %zu missing; %zu summary rows\n",
                    a->out.c_str(), r.found, r.cells, r.copied, r.missing.size(),
                    r.summary.rows().size());
      if (!a->no_plots) make_plots(a->out, a->quiet);
      return 0;
    };
  });
}

void register_search(CLI::App& app, Action& action) {
  auto a = std::make_shared<SweepArgs>();
  CLI::App* c = app.add_subcommand("search",
                                   "Ask/tell search of sweep.search.space per context (sweep "
                                   "cell), e.g. best fx, fy per scene under a budget");
  c->add_option("config", a->config, "Config with a sweep.search block; see docs/sweeps.md")
      ->required();
  options_common(c, *a);
  c->add_option("-o,--out", a->out, "Output directory (default: results/<name>)");
  add_number(c, "-j,--threads", a->run.threads, "Worker threads (default: all cores)",
             {RunControl::threads_range(), "threads", true, "all cores"});
  c->add_option("--shard", a->shard, "Search only contexts of shard i of N (\"i/N\")");
  c->add_flag("-q,--quiet", a->quiet, "Print only errors");
  c->add_flag("--no-cache", a->run.no_cache,
              "Do not read or write the reference cache (cache.dir, default "
              "~/.cache/fovsim; configs/README.md \"cache\"); FOVSIM_NO_CACHE=1 does the same");
  c->callback([a, &action]() {
    action = [a]() {
      LoadedConfig cfg = load_config(a->config, a->overrides);
      SweepPlan plan = expand_sweep(cfg);
      validate_cells(plan);
      SweepOptions opt;
      opt.out_dir = a->out;
      opt.models_dir = a->run.models;
      opt.threads = a->run.threads;
      opt.use_cache = !a->run.no_cache && !cache_disabled_by_env();
      opt.command_line = command_line("search", *a);
      if (!a->shard.empty())
        parse_shard(a->shard, opt.shard, opt.shards);
      else
        shard_from_env(opt.shard, opt.shards);
      SearchReport r = run_search(plan, cfg, opt);
      for (auto& n : r.notes) std::fprintf(stderr, "warning: %s\n", n.c_str());
      if (!a->quiet) {
        std::printf("search %s: %d context%s, %d evaluations (%d from cache)\n", plan.name.c_str(),
                    r.contexts, r.contexts == 1 ? "" : "s", r.evaluations, r.cached);
        std::printf("%s", r.best.to_csv().c_str());
        for (auto& v : r.verdicts) std::printf("%s\n", v.c_str());
        std::printf("results in %s (search_best.csv, search_history.csv)\n", r.out_dir.c_str());
      }
      return 0;
    };
  });
}

}  // namespace

void register_sweeps(CLI::App& app, Action& action) {
  register_sweep(app, action);
  register_merge(app, action);
  register_search(app, action);
}

}  // namespace fovsim::app
