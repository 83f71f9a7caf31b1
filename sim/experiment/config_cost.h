// `fovsim predict --config CONFIG` / `fovsim budget --config CONFIG`: what a run config's
// scene charges, without rendering. The scene is built (as `fovsim run` builds it) for its
// features -- triangles, lights, shadowed lights, indirect light and its RSM size -- and the
// config's workload descriptor, display and method entries are read, so the passes and terms
// predict charges are the ones the run charges (docs/cost_model.md "predict --config").
#pragma once
#include <string>
#include <vector>

#include "sim/core/params.h"
#include "sim/cost/workload.h"
#include "sim/display/display.h"
#include "sim/experiment/config.h"
#include "sim/experiment/table.h"
#include "sim/scene/scene.h"

namespace fovsim {

struct ConfigMethod {
  std::string label, method;
  Json params = Json::object();  // the entry without "method" / "label"
};

struct ConfigCostTarget {
  std::string config;  // the file
  Display display;     // the real display (not render.scale's simulated one)
  Workload workload;   // the config's descriptor with the scene's counts filled in
  SceneFeatures features;
  std::vector<ConfigMethod> methods;
  std::vector<std::string> gpus;  // the config's "gpus" (GpuProfile::names_from_config)
};

// Throws fovsim::Error naming the config file and JSON path.
ConfigCostTarget config_cost_target(const std::string& config, const std::string& models);

// `predict`'s machinery on a run config: per method entry (and GPU) of the
// config, the analytic counters of sim/cost/analytic.h at the real display's resolution (gaze at
// the screen centre, the workload's assumptions) costed by the config's GPU profiles with the
// scene's features. One row per config_id like summary.csv: est_ms_total, est_ms_total_p95 (=
// the mean: one analytic frame), est_ms_<pass>, shaded_fraction and the analytic counters.
// Methods without an analytic model are left out and named in `notes`.
ResultTable analytic_summary(const LoadedConfig& cfg, const std::string& models_dir,
                             std::vector<std::string>* notes = nullptr);

}  // namespace fovsim
