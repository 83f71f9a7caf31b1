// `fovsim search`: the evaluation side of the ask/tell search (search.h). For every context
// (cell of the sweep's axes, e.g. one per scene) a Searcher proposes points of
// sweep.search.space; each point is a run config evaluated by the frame engine (a batch
// shares its references) and cached by hash under <out>/search/evals/, so a rerun after an
// interruption replays the same asks from the cache. Outputs: search_history.csv (every
// evaluation), search_best.csv (one row per context), search_verdict.json (search_verdict.h).
#pragma once
#include <string>
#include <vector>

#include "sim/experiment/sweep_runner.h"

namespace fovsim {

struct SearchReport {
  std::string out_dir;
  int contexts = 0, evaluations = 0, cached = 0;
  // Evaluations found in the output folder but made by another build (git_commit): run again.
  int stale = 0;
  ResultTable best;  // per context; with a constraint: its value and "violation" (0 = met)
  // One line per context where no evaluated point met the constraint (its least violation).
  std::vector<std::string> notes;
  // What the answer means, per context (search_verdict.h): "context <id>: budget does not
  // bind: ...", "... the optimum lies on the lower end of ...", "winner and runner-up tied
  // within noise (...)". Also in search_best.csv (`verdict`) and search_verdict.json.
  std::vector<std::string> verdicts;
};

// A search scores a summary row; when one of its constraint (or objective) columns is an
// interval bound (`<X>_lo`, `<X>_hi`, `<X>_ci95`) that is nan because X's interval is undefined
// (the row's `ci_missing`), every point would be "infeasible" for a reason the search cannot
// change: throws fovsim::Error at `file: sweep.search.subject_to.<column>` with that reason.
void refuse_undefined_bounds(const ResultRow& scored, const SearchSpec& sp,
                             const std::string& file);

SearchReport run_search(const SweepPlan& plan, const LoadedConfig& cfg, const SweepOptions& opt);

}  // namespace fovsim
