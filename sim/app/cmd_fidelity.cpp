// `fovsim fidelity CONFIG [--out DIR] [-j N] [--rungs LIST] [--top RUNG] [key.path=value ...]`
// (logic in sim/experiment/fidelity.h, docs/fidelity.md).
#include <cstdio>
#include <memory>

#include "sim/app/commands.h"
#include "sim/experiment/fidelity.h"
#include "sim/experiment/plots.h"

namespace fovsim::app {

namespace {
struct FidelityArgs {
  std::string config, out;
  std::vector<std::string> overrides;
  std::string rungs = kDefaultRungs, top = kDefaultTop;
  RunFlags run;  // -j, --models, --no-cache, --watchdog (shared with run, sweep, Python)
  bool quiet = false, no_plots = false;
};
}  // namespace

void register_fidelity(CLI::App& app, Action& action) {
  auto a = std::make_shared<FidelityArgs>();
  CLI::App* c = app.add_subcommand(
      "fidelity",
      "Run a config at a ladder of cheaper settings (analytic, render.scale, frame stride, spp) "
      "and report each rung's error and wall time against the top rung (docs/fidelity.md)");
  c->add_option("config", a->config, "Run config (JSON)")->required();
  c->add_option("overrides", a->overrides,
                "Overrides key.path=value applied to the config before the ladder");
  c->add_option("-o,--out", a->out, "Output directory (default: results/<name>_fidelity)");
  add_run_flags(c, a->run);  // no --target: the ladder's rungs are fixed
  c->add_option("--rungs", a->rungs,
                std::string("Rungs separated by ';': analytic, or overrides separated by ',' "
                            "(scale=X, stride=N, spp=N, key.path=value); default \"") +
                    kDefaultRungs + "\"");
  c->add_option("--top", a->top,
                std::string("The top rung, the truth (same syntax, one rung); default \"") +
                    kDefaultTop + "\"");
  c->add_option("--models", a->run.models,
                "Models directory (default: $FOVSIM_MODELS, ./models, or the source tree's)");
  c->add_flag("-q,--quiet", a->quiet, "Print only the table");
  c->add_flag("--no-plots", a->no_plots, "Do not run viz/plot_fidelity.py");
  c->callback([a, &action]() {
    action = [a]() {
      // Rungs are checked before the config is even loaded: a typo fails in one line, at once.
      (void)parse_rungs(a->rungs, a->top);
      LoadedConfig cfg = load_config(a->config, a->overrides);
      FidelityOptions opt;
      opt.out_dir = a->out;
      static_cast<RunControl&>(opt) = a->run.control();
      opt.rungs = a->rungs;
      opt.top = a->top;
      opt.progress = !a->quiet;
      opt.command_line = "fovsim fidelity " + a->config;
      for (auto& o : a->overrides) opt.command_line += " " + o;
      opt.command_line += " --rungs '" + a->rungs + "' --top '" + a->top + "'";
      FidelityResult r = run_fidelity(cfg, opt);
      std::printf("\n%s", r.markdown.c_str());
      for (auto& n : r.notes) std::printf("note: %s\n", n.c_str());
      if (!a->quiet)
        std::printf("results in %s (fidelity.csv, fidelity.json)\n", r.out_dir.c_str());
      if (!a->no_plots) {
        PlotOutcome p = run_plot_script("plot_fidelity.py", {r.out_dir}, a->quiet);
        if (p.status == PlotOutcome::Status::Failed)
          std::fprintf(stderr, "fovsim: %s\n", p.message.c_str());
        else if (p.status == PlotOutcome::Status::Skipped && !p.message.empty() && !a->quiet)
          std::printf("%s\n", p.message.c_str());
      }
      return 0;
    };
  });
}

}  // namespace fovsim::app
