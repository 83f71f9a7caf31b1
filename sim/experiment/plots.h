// One way of launching the plotting scripts in viz/ (used by `fovsim run` and `fovsim sweep`).
// Plots are optional: a missing /usr/bin/python3, matplotlib or script is reported in one line
// and skipped; a failing script is a warning, never an error (the results are complete).
#pragma once

#include <string>
#include <vector>

namespace fovsim {

struct PlotOutcome {
  enum class Status { Made, Skipped, Failed };
  Status status = Status::Skipped;
  std::string message;  // one line for the user: what was skipped or failed and why
};

// Interpreter used for every viz script (Debian's python3 with python3-matplotlib).
inline constexpr const char* kPlotPython = "/usr/bin/python3";

// Path of a viz/ script, found from the running binary (../viz, ../share/fovsim/viz, viz
// beside it), else in the source tree fovsim was built from, else ./viz; "" if none.
std::string find_viz_script(const std::string& name);

// Quotes one argument for /bin/sh (single quotes; embedded ' becomes '\'').
std::string shell_quote(const std::string& s);

// The shell command that runs viz/<script> with `args` (script path from find_viz_script).
std::string plot_command(const std::string& script_path, const std::vector<std::string>& args,
                         bool quiet);

// Runs viz/<script> on `args`. Skips (Status::Skipped, message says why) when the script is
// not found, /usr/bin/python3 is missing or cannot import matplotlib; skips silently (empty
// message) when the environment sets FOVSIM_NO_PLOTS to a value other than "0" (used by the
// test suites). `quiet` silences the script's own output.
// Figure options shared by `fovsim run` and `fovsim sweep`: --plot-format png|pdf|svg,
// --plot-dpi, --plot-configs, passed to the viz scripts as --format/--dpi/--configs.
struct PlotFlags {
  std::string format = "png", configs;
  double dpi = 110;
  std::vector<std::string> args() const {
    std::vector<std::string> a{"--format", format, "--dpi", std::to_string(dpi)};
    if (!configs.empty()) a.insert(a.end(), {"--configs", configs});
    return a;
  }
};

PlotOutcome run_plot_script(const std::string& script, const std::vector<std::string>& args,
                            bool quiet);

}  // namespace fovsim
