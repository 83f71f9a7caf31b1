// `fovsim search`: the evaluation side of the ask/tell search (search.h). For every context
// (cell of the sweep's axes, e.g. one per scene) a Searcher proposes points of
// sweep.search.space; each point is a run config evaluated by the frame engine (a batch
// shares its references) and cached by hash under <out>/search/evals/, so a rerun after an
// interruption replays the same asks from the cache. Outputs: search_history.csv (every
// evaluation), search_best.csv (one row per context).
#pragma once
#include <string>
#include <vector>

#include "sim/experiment/sweep_runner.h"

namespace fovsim {

struct SearchReport {
  std::string out_dir;
  int contexts = 0, evaluations = 0, cached = 0;
  ResultTable best;  // per context; with a constraint: its value and "violation" (0 = met)
  // One line per context where no evaluated point met the constraint (its least violation).
  std::vector<std::string> notes;
};

SearchReport run_search(const SweepPlan& plan, const LoadedConfig& cfg, const SweepOptions& opt);

}  // namespace fovsim
