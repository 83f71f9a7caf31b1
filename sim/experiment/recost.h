// `fovsim predict --results DIR`: the counters a finished run measured (frames.csv) re-costed
// for other GPUs, displays or eye counts without rendering again. Per-pixel counters are
// rescaled from the run's simulated resolution to the target display; per-config means.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "sim/display/display.h"

namespace fovsim {

struct RecostOptions {
  std::string results;                  // the run's output directory (manifest.json, frames.csv)
  std::string models;                   // models directory
  std::vector<std::string> gpus;        // GPU profile names or paths
  std::string display;                  // "" = the run's display
  int width = 0, height = 0, eyes = 0;  // overrides (0 = keep)
  std::string workload;  // "" = the run's workload (resolved_config.workload) or generic
};

struct RecostRow {
  // label: the method entry's label (frames.csv `label`, else config_id without "@gpu"); in a
  // sweep config_id is "<cell>/<config_id>" and label stays the entry's label.
  std::string gpu, config_id, method, label;
  double frames = 0, total_ms = 0;
  double lo_ms = -1, hi_ms = -1, level = 0;  // prediction interval of the mean (level 0: none)
  std::vector<std::pair<std::string, double>> pass_ms = {};  // mean per existing pass
};

struct RecostResult {
  Display display;
  std::string workload;
  std::vector<RecostRow> rows;  // per GPU, per config in first-seen order
};

// Errors (incomplete run, missing scene features, malformed frames.csv) name file:line.
RecostResult recost_results(const RecostOptions& o);

}  // namespace fovsim
