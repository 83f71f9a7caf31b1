#include "sim/experiment/plots.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "sim/core/files.h"

namespace fovsim {

namespace fs = std::filesystem;

std::string find_viz_script(const std::string& name) {
  // Beside the running binary first (build/fovsim -> viz/, bin/fovsim -> share/fovsim/viz/),
  // so a copied or installed fovsim run from any directory finds its own scripts.
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec)
    for (const char* rel : {"../viz/", "../share/fovsim/viz/", "viz/"}) {
      fs::path p = exe.parent_path() / (rel + name);
      if (file_exists(p.string())) return p.lexically_normal().string();
    }
  std::string src = std::string(FOVSIM_SOURCE_DIR) + "/viz/" + name;
  if (file_exists(src)) return src;
  return file_exists("viz/" + name) ? "viz/" + name : "";
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'')
      q += "'\\''";
    else
      q += c;
  }
  return q + "'";
}

std::string plot_command(const std::string& script_path, const std::vector<std::string>& args,
                         bool quiet) {
  std::string cmd = std::string(kPlotPython) + " " + shell_quote(script_path);
  for (auto& a : args) cmd += " " + shell_quote(a);
  return cmd + (quiet ? " >/dev/null 2>&1" : " 2>&1");
}

PlotOutcome run_plot_script(const std::string& script, const std::vector<std::string>& args,
                            bool quiet) {
  PlotOutcome r;
  const char* off = std::getenv("FOVSIM_NO_PLOTS");
  if (off && *off && std::string(off) != "0") return r;  // silent, like --no-plots
  std::string path = find_viz_script(script);
  if (path.empty()) {
    r.message =
        "plots skipped: viz/" + script + " not found (run from the repository or its build)";
    return r;
  }
  if (!file_exists(kPlotPython)) {
    r.message = std::string("plots skipped: ") + kPlotPython +
                " not found (apt-get install python3-matplotlib)";
    return r;
  }
  std::string probe = std::string(kPlotPython) + " -c 'import matplotlib' >/dev/null 2>&1";
  if (std::system(probe.c_str()) != 0) {
    r.message = std::string("plots skipped: ") + kPlotPython +
                " cannot import matplotlib (apt-get install python3-matplotlib); use --no-plots to "
                "silence this";
    return r;
  }
  std::fflush(stdout);  // our summary table before the script's lines
  std::fflush(stderr);
  int rc = std::system(plot_command(path, args, quiet).c_str());
  if (rc != 0) {
    r.status = PlotOutcome::Status::Failed;
    r.message =
        "warning: " + path + " failed (exit " + std::to_string(rc) + "); results are complete";
    return r;
  }
  r.status = PlotOutcome::Status::Made;
  return r;
}

}  // namespace fovsim
