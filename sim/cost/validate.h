// Cost-model validation (issue 7 item 7): every calibration entry predicted vs. published,
// the seeds' withheld figures predicted, and cross-predictions (fit on some seeds/scenes,
// predict another's per-pass times and speedup).
#pragma once
#include <map>
#include <string>
#include <vector>

#include "sim/cost/calibration.h"

namespace fovsim {

struct ValidationRow {
  std::string experiment;  // "calibration" or "cross:<name>" or "withheld"
  std::string id, table, gpu, workload, config, row;
  // fitted | check | predicted | refit | withheld | unseen | total (a held-out check row:
  // a frame total whose passes the refit all saw; scored for interval coverage only)
  std::string kind;
  double published_ms = -1;  // < 0: withheld / none
  double model_ms = 0;
  std::vector<PassCost> parts;  // model ms of each pass the row sums (lo/hi unset)
  double rel_err() const { return published_ms > 0 ? (model_ms - published_ms) / published_ms : 0; }
};

struct CrossPrediction {
  std::string name, fit_on, target;
  bool possible = true;
  std::string why;  // when not possible
  double mean_abs_rel_err = 0;
  int n = 0;
  double speedup_published = 0, speedup_model = 0;  // baseline total / foveated total
};

struct ValidationReport {
  std::vector<ValidationRow> rows;
  std::vector<CrossPrediction> cross;
};

// Transfer summary of one model (issue 14): fitted and held-out relative errors, the
// prediction interval from the held-out rows, and its nested empirical coverage.
struct ModelSummary {
  CostModelKind model = CostModelKind::Linear;
  double fitted_mean = 0, fitted_worst = 0;  // |rel err| over the fitted rows (full fit)
  int fitted_n = 0;
  double leaveout_mean = 0, leaveout_worst = 0;  // |rel err| over held-out ("predicted") rows
  int leaveout_n = 0;
  PredictionInterval interval;  // from every held-out row
  // Coverage of the per-pass intervals on each target table's held-out rows when the
  // intervals are built from the other tables' held-out rows only (so no row judges an
  // interval it helped build).
  double coverage = 0;
  int coverage_n = 0;
  // The same for held-out frame totals (kind "total"), intervals combined from their passes.
  double total_coverage = 0;
  int total_coverage_n = 0;
};

// Interval of a row (or any sum of passes): each pass's factors around its ms, combined.
void row_interval(const PredictionInterval& iv, const std::vector<PassCost>& parts, double* lo_ms,
                  double* hi_ms);

// Interval factors [q_lo, q_hi] of published/model over held-out rows: the empirical
// (1-level)/2 and (1+level)/2 quantiles (linear interpolation), pooled over every row and per
// pass over the single-pass rows of that pass (kept when at least kMinPassIntervalRows).
// `exclude_table`: rows of that table are not used.
PredictionInterval interval_from_rows(const std::vector<ValidationRow>& rows, double level,
                                      const std::string& exclude_table = "");
ModelSummary summarize_model(const ValidationReport& rep, CostModelKind model, double level);

// Uses `fit` (normally fit_cost_model over all tables) for the calibration rows and withheld
// predictions; refits for every cross-prediction experiment.
ValidationReport validate_cost(const CalData& data, const CostFit& fit, const FitOptions& opt);

}  // namespace fovsim
