// `fovsim converge CONFIG [--spp 1,4,16,64] [--out DIR] [key.path=value ...]`
#include <cstdio>
#include <memory>

#include "sim/app/commands.h"
#include "sim/experiment/convergence.h"

namespace fovsim::app {

void register_converge(CLI::App& app, Action& action) {
  struct Args {
    std::string config, out = "results/convergence";
    std::vector<std::string> overrides;
    std::vector<int> spps{1, 4, 16, 64};
    RunFlags run;  // -j, --models, --no-cache, --watchdog (shared with run, sweep, Python)
    double tol_jod = 0.05;
  };
  auto a = std::make_shared<Args>();
  CLI::App* c = app.add_subcommand(
      "converge",
      "Reference convergence study: every method against references of increasing render.spp; "
      "picks the default spp (docs/metrics.md)");
  c->add_option("config", a->config, "Run config (JSON), e.g. configs/convergence.json")
      ->required();
  c->add_option("overrides", a->overrides, "Overrides key.path=value applied to every level");
  add_number(c, "--spp", a->spps, "Increasing perfect squares (default 1,4,16,64)",
             {Range::closed(1, 1024), "samples per pixel (render.spp)"})
      ->delimiter(',');
  c->add_option("-o,--out", a->out, "Output directory (default results/convergence)");
  add_run_flags(c, a->run);  // no --target: the spp levels are fixed
  c->add_option("--models", a->run.models,
                "Models directory (default: $FOVSIM_MODELS, ./models, or the source tree's)");
  add_number(c, "--tol-jod", a->tol_jod,
             "FovVideoVDP tolerance in JOD between levels (default 0.05)",
             {Range::closed(1e-6, 10.0), "JOD"});
  c->callback([a, &action]() {
    action = [a]() {
      ConvergenceOptions o;
      o.spps = a->spps;
      o.out_dir = a->out;
      static_cast<RunControl&>(o) = a->run.control();
      o.tol_jod = a->tol_jod;
      ConvergenceResult r = run_convergence(a->config, a->overrides, o);
      std::printf("%s", r.markdown().c_str());
      std::printf("written: %s/convergence.md, convergence.csv\n", a->out.c_str());
      return 0;
    };
  });
}

}  // namespace fovsim::app
