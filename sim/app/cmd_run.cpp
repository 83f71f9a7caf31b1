// `fovsim run CONFIG.json [--out DIR] [key.path=value ...]`
#include <cstdio>
#include <memory>

#include "sim/app/commands.h"
#include "sim/core/disk_cache.h"
#include "sim/experiment/plots.h"
#include "sim/experiment/runner.h"

namespace fovsim::app {

namespace {
struct RunArgs {
  std::string config, out;
  std::vector<std::string> overrides;
  RunFlags run;  // -j, --models, --no-cache, --watchdog, --target (shared with sweep, Python)
  bool quiet = false, no_plots = false;
  PlotFlags plot;
};
}  // namespace

void register_run(CLI::App& app, Action& action) {
  auto a = std::make_shared<RunArgs>();
  CLI::App* c = app.add_subcommand(
      "run", "Run one config: replay a trace through every method, write results/<name>/");
  c->add_option("config", a->config, "Run config (JSON); see configs/README.md for every key")
      ->required();
  c->add_option("overrides", a->overrides,
                "Overrides key.path=value applied after loading (e.g. render.scale=0.5 "
                "methods[1].sigma=2.2)");
  c->add_option("-o,--out", a->out, "Output directory (default: results/<name>)");
  add_run_flags(c, a->run,
                "Stop early: COLUMN:VALUE[%|dB|ms] or ranking[:COLUMN] (repeatable, e.g. "
                "est_ms_total:1%); "
                "frames are evaluated in a seeded random order of 10-frame units until "
                "every config's 95% half-width is within target (docs/intervals.md)");
  c->add_option("--models", a->run.models,
                "Models directory (default: $FOVSIM_MODELS, ./models, or the source tree's)");
  c->add_flag("-q,--quiet", a->quiet, "Do not print the summary table");
  c->add_flag("--no-plots,!--plots", a->no_plots,
              "--no-plots: do not run viz/plot_run.py at the end; --plots (the default): plots, "
              "run.mp4 (with ffmpeg) and index.html in <out>/plots/, skipped with a message when "
              "/usr/bin/python3 has no matplotlib");
  add_plot_flags(c, a->plot);
  c->callback([a, &action, c]() {
    action = [a]() {
      LoadedConfig cfg = load_config(a->config, a->overrides);
      RunOptions opt;
      static_cast<RunControl&>(opt) = a->run.control();
      opt.out_dir = a->out;
      opt.print_summary = !a->quiet;
      opt.command_line = "fovsim run " + a->config;
      for (auto& o : a->overrides) opt.command_line += " " + o;
      for (auto& t : a->run.targets) opt.command_line += " --target " + t;
      RunResult r = run_experiment(cfg, opt);
      for (auto& w : r.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
      for (auto& n : r.notes) std::fprintf(stderr, "note: %s\n", n.c_str());
      if (!r.printed_summary) {
        std::printf("results in %s\n", r.out_dir.c_str());
        if (!a->quiet && !r.fidelity_note.empty())
          std::printf("fidelity: %s\n", r.fidelity_note.c_str());
      }
      if (!a->no_plots) {
        std::vector<std::string> args{r.out_dir};
        for (auto& x : a->plot.args()) args.push_back(x);
        PlotOutcome p = run_plot_script("plot_run.py", args, a->quiet);
        if (p.status == PlotOutcome::Status::Failed)
          std::fprintf(stderr, "fovsim: %s\n", p.message.c_str());
        else if (p.status == PlotOutcome::Status::Skipped && !p.message.empty() && !a->quiet)
          std::printf("%s\n", p.message.c_str());
      }
      return 0;
    };
    (void)c;
  });
}

}  // namespace fovsim::app
