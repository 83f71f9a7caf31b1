// Cost-model validation: every calibration entry predicted vs. published,
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
  // fitted | check | predicted | refit | withheld | total (a held-out check row: a frame total
  // whose passes the refit all saw; scored for interval coverage) | prior / total_prior (a pass
  // row / frame total with passes the refit never measured, costed from their nominal work)
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
  // Fitted parameters of every leave-one-paper-out refit (key -> one value per refit; absent
  // keys are not listed): their spread is the jackknife uncertainty of the full fit.
  std::map<std::string, std::vector<double>> lopo_theta;
  // Pooled efficiencies and prior overhead of each leave-one-paper-out refit, by left-out
  // table: what the passes that paper alone measures were costed with.
  std::map<std::string, std::map<std::string, double>> lopo_priors;
};

// Coverage of the intervals at one level on the nested held-out rows (each table's rows
// against intervals calibrated without that table), with a Wilson score interval (95%) on the
// coverage and the median half-width (hi - lo) / 2 as a fraction of the estimate.
struct CoverageStat {
  double level = 0;
  int n = 0, inside = 0;
  double coverage = 0, wilson_lo = 0, wilson_hi = 0;
  double median_half_width = 0;
};
// Wilson score interval for k successes in n trials at z (1.96: 95%).
void wilson_interval(int k, int n, double z, double* lo, double* hi);
// Split-conformal quantile of scores: the ceil((n+1) q)-th smallest for q >= 1/2, the
// floor((n+1) q)-th for q < 1/2 (clamped to the extreme score when n is too small to
// guarantee q; Vovk, Gammerman and Shafer 2005; Lei et al. 2018).
double conformal_quantile(std::vector<double> scores, double q);

// Transfer summary of one model: fitted and held-out relative errors, the
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
  // The same for held-out frame totals (kinds "total" and "total_prior"), against the total's
  // interval from the other tables' held-out totals (where too few: the passes' intervals
  // combined).
  double total_coverage = 0;
  int total_coverage_n = 0;
  // Nested coverage and width at 50%, 80% and 95% (per-pass rows; frame totals).
  std::vector<CoverageStat> pass_cov, total_cov;
};

// Interval of a row (or any sum of passes): each pass's factors around its ms, combined.
// `total`: the row is a whole frame (a held-out total or a withheld figure): the interval's total
// factors when it has them.
void row_interval(const PredictionInterval& iv, const std::vector<PassCost>& parts, double* lo_ms,
                  double* hi_ms, bool total = false);

// Interval factors [q_lo, q_hi] of published/model over held-out rows: split-conformal
// (1-level)/2 and (1+level)/2 quantiles of the log-ratios (asymmetric), pooled over every
// per-pass row, per pass over the single-pass rows of that pass (kept when at least
// kMinPassIntervalRows, shrunk toward the pooled ones), and for the total over the held-out
// frame totals (kinds "total" and "total_prior"; their sorted scores too). `exclude_table`: rows of
// that table (paper = GPU) are not used, so a group never calibrates itself.
PredictionInterval interval_from_rows(const std::vector<ValidationRow>& rows, double level,
                                      const std::string& exclude_table = "");
ModelSummary summarize_model(const ValidationReport& rep, CostModelKind model, double level);

// Leave-one-paper-out transfer (fit every other paper, predict this one's milliseconds): mean
// |rel err| of its frame totals (kinds "total" and "total_prior") and of its per-pass rows
// (kinds "predicted" and "prior"), per calibration table (= paper = GPU).
struct TransferError {
  std::string table;
  double totals_mean = 0, rows_mean = 0;
  int totals_n = 0, rows_n = 0;
};
std::vector<TransferError> lopo_errors(const ValidationReport& rep, const CalData& data);
// Speedups of the leave-one-paper-out frame totals: a baseline config's total over a foveated
// config's, same table, workload and row name, published and modelled.
struct TransferSpeedup {
  std::string table, workload, row, base, fov;
  double published = 0, model = 0;
};
std::vector<TransferSpeedup> lopo_speedups(const ValidationReport& rep, const CalData& data);

// Uses `fit` (normally fit_cost_model over all tables) for the calibration rows and withheld
// predictions; refits for every cross-prediction experiment.
ValidationReport validate_cost(const CalData& data, const CostFit& fit, const FitOptions& opt);

}  // namespace fovsim
