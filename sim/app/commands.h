// Each CLI subcommand group lives in its own file and registers itself here, called
// explicitly from main.cpp (no static registration).
#pragma once
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

#include "sim/app/flags.h"
#include "sim/core/disk_cache.h"
#include "sim/core/error.h"
#include "sim/core/params.h"
#include "sim/experiment/run_options.h"

namespace fovsim::app {

// A registered subcommand sets `action`; main runs it inside the one try/catch.
using Action = std::function<int()>;

void register_run(CLI::App& app, Action& action);  // fovsim run
void register_cost(CLI::App& app,
                   Action& action);  // fovsim calibrate | predict | budget | validate-cost
void register_sweeps(CLI::App& app,
                     Action& action);  // fovsim sweep | sweep expand | merge | search
void register_trace(CLI::App& app,
                    Action& action);  // fovsim trace import | validate | stats | synth
void register_density(CLI::App& app, Action& action);  // fovsim density
void register_info(CLI::App& app, Action& action);     // fovsim info
void register_methods(CLI::App& app, Action& action);  // fovsim methods
void register_compare(CLI::App& app, Action& action);  // fovsim compare REF TEST
// fovsim converge CONFIG
void register_converge(CLI::App& app, Action& action);
// fovsim fidelity CONFIG (docs/fidelity.md)
void register_fidelity(CLI::App& app, Action& action);
// fovsim cache info | prune (the reference cache's size and cap)
void register_cache(CLI::App& app, Action& action);
// Every command group above, in --help order (main.cpp; tests/app/flags_test.cpp walks them).
void register_commands(CLI::App& app, Action& action);

// The run options every command that runs configs shares (RunControl,
// sim/experiment/run_options.h; the Python bindings take the same): -j/--threads, --no-cache,
// --watchdog and, where frames can stop early (`run`, `sweep`, `search`), --target. --models
// is declared with each command's other common options and binds RunFlags::models.
struct RunFlags {
  std::string models;
  int threads = 0;
  bool no_cache = false;
  double watchdog_s = 60;
  std::vector<std::string> targets;

  RunControl control() const {  // the cache also off with FOVSIM_NO_CACHE (disk_cache.h)
    RunControl c;
    c.models_dir = models;
    c.threads = threads;
    c.watchdog_s = watchdog_s;
    c.targets = targets;
    c.use_cache = !no_cache && !cache_disabled_by_env();
    return c;
  }
};
// -j/--threads, --no-cache, --watchdog: commands with no --target (`fidelity` runs a fixed
// ladder, `converge` fixed spp levels).
inline void add_run_flags(CLI::App* c, RunFlags& f) {
  add_number(c, "-j,--threads", f.threads,
             "Worker threads (default: all cores); results are identical at any count",
             {RunControl::threads_range(), "threads", true, "all cores"});
  c->add_flag("--no-cache", f.no_cache,
              "Do not read or write the reference cache (cache.dir, default "
              "~/.cache/fovsim; configs/README.md \"cache\"); FOVSIM_NO_CACHE=1 does the same");
  add_number(c, "--watchdog", f.watchdog_s,
             "Stop with an error naming the frame and method when one method's frame runs "
             "longer than\n"
             "max(SECONDS, 50x the median of its previous frames) (its first frame: 10x "
             "SECONDS); 0 disables",
             {RunControl::watchdog_range(), "s", false, "off"});
}
// The same and --target; `target_help` says what --target stops.
inline void add_run_flags(CLI::App* c, RunFlags& f, const std::string& target_help) {
  add_run_flags(c, f);
  c->add_option("--target", f.targets, target_help)
      ->expected(1)  // one spec per --target, so overrides after it stay overrides
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

// --plot-format, --plot-dpi, --plot-configs of `run` and `sweep` (the viz scripts' --format,
// --dpi, --configs).
template <class Flags>
void add_plot_flags(CLI::App* c, Flags& f) {
  c->add_option("--plot-format", f.format,
                "Also write every plot as pdf or svg next to its png (viz --format)")
      ->check(CLI::IsMember({"png", "pdf", "svg"}));
  add_number(c, "--plot-dpi", f.dpi, "Resolution of raster plots (default 110)",
             {Range::closed(10, 2400), "dpi"});
  c->add_option("--plot-configs", f.configs,
                "Comma-separated configurations (labels) to draw, in that order (default: all)");
}
}  // namespace fovsim::app
