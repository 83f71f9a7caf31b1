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
  std::vector<std::string> gpus;  // the config's "gpus" (default gtx1080, as run)
};

// Throws fovsim::Error naming the config file and JSON path.
ConfigCostTarget config_cost_target(const std::string& config, const std::string& models);

}  // namespace fovsim
