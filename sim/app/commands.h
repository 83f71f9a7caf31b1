// Each CLI subcommand group lives in its own file and registers itself here, called
// explicitly from main.cpp (no static registration).
#pragma once
#include <CLI/CLI.hpp>
#include <functional>

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

// --plot-format, --plot-dpi, --plot-configs of `run` and `sweep` (the viz scripts' --format,
// --dpi, --configs).
template <class Flags>
void add_plot_flags(CLI::App* c, Flags& f) {
  c->add_option("--plot-format", f.format,
                "Also write every plot as pdf or svg next to its png (viz --format)")
      ->check(CLI::IsMember({"png", "pdf", "svg"}));
  c->add_option("--plot-dpi", f.dpi, "Resolution of raster plots (default 110)")
      ->check(CLI::Range(1.0, 2400.0));
  c->add_option("--plot-configs", f.configs,
                "Comma-separated configurations (labels) to draw, in that order (default: all)");
}
}  // namespace fovsim::app
