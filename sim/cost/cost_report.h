// Orchestration of `fovsim calibrate` and `fovsim validate-cost` (library logic out
// of sim/app): fit, interval, profile and workload files, the validation report and CSVs.
// The app only parses arguments, calls these and prints. Formats: docs/cost_model.md.
#pragma once
#include <set>
#include <string>
#include <vector>

#include "sim/cost/calibration.h"
#include "sim/cost/validate.h"

namespace fovsim {

// "kfr, rmfr" -> {"kfr", "rmfr"} (comma-separated, spaces trimmed, empty items dropped).
std::set<std::string> parse_id_list(const std::string& text, const std::string& where);

struct CalibrateOptions {
  std::string models;            // models directory
  std::set<std::string> tables;  // empty: all
  CostModelKind model = CostModelKind::Roofline;
  bool write = true;  // false (--dry-run): fit and report only, no interval
  // Where profiles and fitted workloads are written: OUT/gpus/<gpu>.json and
  // OUT/workloads/<workload>.json (the models directory's file, fitted keys replaced). "" =
  // the models directory itself.
  std::string out;
};

struct CalibrationRun {
  CalData data;
  FitOptions opt;
  CostFit fit;
  struct Row {
    CalEntry entry;
    double model_ms = 0, rel_err = 0;
  };
  std::vector<Row> rows;  // every entry of every table, table order
  double fitted_mean_abs_err = 0;
  int fitted_n = 0;
  PredictionInterval interval;       // from this model's leave-out rows (write only)
  std::vector<GpuProfile> profiles;  // one per GPU of gpu_specs.json (write only)
  std::vector<std::string> written;  // files written
};

// Fits, and unless !write: computes the interval from validate_cost of the same model and
// writes models/gpus/<gpu>.json (GpuProfile::to_json) and the fitted workloads' keys.
CalibrationRun run_calibration(const CalibrateOptions& o);

// The profile of `gpu` as `fovsim calibrate` writes it: coefficients, interval, residuals.
GpuProfile calibrated_profile(const CostFit& fit, const CalData& data, const std::string& gpu,
                              const PredictionInterval& iv, const std::set<std::string>& tables);

struct ValidationOutputs {
  CostModelKind model = CostModelKind::Roofline;  // the detailed report's model
  ValidationReport report;
  std::vector<ModelSummary> ranked;  // every model, by held-out mean |rel err|
  std::string report_txt, validate_csv, cross_csv;
};

// Both models' leave-out experiments, the ranking, and the report text and CSVs.
ValidationOutputs run_validation(const std::string& models, double level = 0.8);
// Writes report.txt, validate_cost.csv, cross_predictions.csv into `dir`.
void write_validation(const ValidationOutputs& v, const std::string& dir);

}  // namespace fovsim
