// `fovsim predict` and `fovsim budget` as library functions: the per-GPU x method rows that the
// CLI prints (a table, or --json) and that Python's fovsim.predict / fovsim.budget return. One
// definition, so both accept and refuse the same input and give the same numbers
// (docs/cost_model.md).
#pragma once
#include <map>
#include <string>
#include <vector>

#include "sim/core/params.h"
#include "sim/cost/budget.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/workload.h"
#include "sim/display/display.h"

namespace fovsim {

// What predict and budget cost: a workload (or a run config's scene) on a display, for GPU
// profiles and methods ("kfr:sigma=1.8"). `where_*`: how errors name each input (the CLI's
// flags, Python's arguments).
struct CostTarget {
  std::string models;                   // the models folder ("" = default_models_dir())
  std::string display;                  // a name or path; "" = the config's or kDefaultDisplay
  std::string workload;                 // required without `config`
  std::string config;                   // a run config: its scene, workload, display, methods
  std::vector<std::string> gpus;        // required, except with `config` (its gpus)
  std::vector<std::string> methods;     // empty: `default_methods`
  int width = 0, height = 0, eyes = 0;  // 0 keeps the display's value
  std::string where_method = "--method", where_workload = "--workload", where_gpu = "--gpu";
  std::string workload_hint = "or --config CONFIG for a run config's scene";  // when missing
};

struct CostMethod {
  std::string text, name;  // "kfr:sigma=1.8", "kfr" (a config's entries: their label)
  Json params = Json::object();
};

// The target resolved: the workload, display (overrides applied), methods and GPU names.
struct ResolvedCostTarget {
  Workload workload;
  Display display;
  bool indirect = false;  // the config's scene has indirect light
  std::vector<CostMethod> methods;
  std::vector<std::string> gpus;
};
ResolvedCostTarget resolve_cost_target(const CostTarget& t,
                                       const std::vector<std::string>& default_methods);

// Tracking loss for predict (docs/tracking.md "What each policy costs"): `fraction` < 0 = off.
struct PredictLoss {
  double fraction = -1;
  std::string on_invalid = "hold";
  double widen_k = 1.75;
};

struct CostRows {
  ResolvedCostTarget target;
  std::vector<GpuProfile> gpus;              // the profiles used (what-if applied for budget)
  std::vector<nlohmann::ordered_json> rows;  // the --json rows, GPU-major
};

// `fovsim predict`: per GPU x method, est_ms_total (and its interval), est_ms_<pass>,
// resource_ms, speedup_vs_full, and with `loss` the tracking_loss record.
CostRows predict_rows(const CostTarget& t, const PredictLoss& loss = {});

// `fovsim budget`: per GPU x method against `budget_ms` at fit level `level`: the decision
// (verdict, p_fit, fits), headroom, the cheapest changes that reach the level, and the
// throughput factors, with the GPUs' throughput scaled by `what_if`.
CostRows budget_rows(const CostTarget& t, double budget_ms, double level, const WhatIf& what_if);

// A what-if from resource names ("shading", "geometry", "raster", "memory", "fixed"), each in
// CostArgRanges::scale(); an unknown name or a value out of range is an error at `where`.<name>.
WhatIf what_if_from(const std::map<std::string, double>& scale, const std::string& where);

}  // namespace fovsim
