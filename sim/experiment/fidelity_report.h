// The fidelity ladder's report: every rung compared with the top rung (compare_to_truth,
// same_ranking, resolved_swaps of fidelity_stats.cpp), written as fidelity.csv, fidelity.json
// and the ladder table fidelity.md (docs/fidelity.md).
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "sim/experiment/fidelity.h"

namespace fovsim {

// One rung as run_fidelity ran it (wall_s NaN: not run).
struct RungRun {
  double wall_s = NAN, cpu_s = NAN;
  std::string dir;  // its results folder; "" for the analytic rung
  ResultTable summary, frames;
  Json resolved;  // the resolved config of a rendered rung
};

// Fills res.table, res.markdown and res.json, appends its notes to res.notes and writes
// fidelity.csv, fidelity.json and fidelity.md into res.out_dir. runs[i] is rungs[i]'s run; the
// last rung is the top one.
void write_fidelity_report(const std::string& name, const LoadedConfig& cfg,
                           const FidelityOptions& opt, const std::vector<FidelityRung>& rungs,
                           const std::vector<RungRun>& runs, FidelityResult& res);

}  // namespace fovsim
