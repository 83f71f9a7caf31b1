// `fovsim run`: one config = scene + display + trace + methods + metrics + GPU profiles +
// outputs (docs/architecture.md "Data flow of one frame", "Outputs"). Frames stream: the reference
// of a frame is rendered once and shared by every method; no whole-trace image storage.
#pragma once
#include <string>
#include <vector>

#include "sim/experiment/config.h"
#include "sim/experiment/run_options.h"
#include "sim/experiment/table.h"

namespace fovsim {

struct RunOptions : RunControl {  // models_dir, threads, watchdog_s, targets, use_cache
  std::string out_dir;            // empty -> results/<name>
  bool print_summary = true;      // summary table on stdout at the end
  std::string command_line;       // recorded in the manifest
};

struct RunResult {
  std::string out_dir;
  ResultTable frames;
  ResultTable summary;
  Json target;                        // manifest "target" record when targets were given
  std::vector<std::string> warnings;  // suspicious but valid values (manifest "warnings")
  bool printed_summary = false;       // the summary table (with the results path) was printed
  std::string fidelity_note;          // manifest "fidelity" note (empty at scale >= 0.5)
  // Notes for stderr: intervals that are missing or short-run (interval_notes), start-up
  // frames left out of the means.
  std::vector<std::string> notes;
};

RunResult run_experiment(const LoadedConfig& cfg, const RunOptions& opt);

}  // namespace fovsim
