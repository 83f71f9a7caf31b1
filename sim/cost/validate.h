// Cost-model validation (issue 7 item 7): every calibration entry predicted vs. published,
// the seeds' withheld figures predicted, and cross-predictions (fit on some seeds/scenes,
// predict another's per-pass times and speedup).
#pragma once
#include <string>
#include <vector>

#include "sim/cost/calibration.h"

namespace fovsim {

struct ValidationRow {
  std::string experiment;  // "calibration" or "cross:<name>" or "withheld"
  std::string id, table, gpu, workload, config, row;
  std::string kind;        // fitted | check | predicted | refit | withheld
  double published_ms = -1;  // < 0: withheld / none
  double model_ms = 0;
  double rel_err() const { return published_ms > 0 ? (model_ms - published_ms) / published_ms : 0; }
};

struct CrossPrediction {
  std::string name, fit_on, target;
  bool possible = true;
  std::string why;          // when not possible
  double mean_abs_rel_err = 0;
  int n = 0;
  double speedup_published = 0, speedup_model = 0;  // baseline total / foveated total
};

struct ValidationReport {
  std::vector<ValidationRow> rows;
  std::vector<CrossPrediction> cross;
};

// Uses `fit` (normally fit_cost_model over all tables) for the calibration rows and withheld
// predictions; refits for every cross-prediction experiment.
ValidationReport validate_cost(const CalData& data, const CostFit& fit, const FitOptions& opt);

}  // namespace fovsim
