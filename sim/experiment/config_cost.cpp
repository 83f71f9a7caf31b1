// Cost inputs of a run config without rendering (see config_cost.h).
#include "sim/experiment/config_cost.h"

#include "sim/core/error.h"
#include "sim/experiment/config.h"

namespace fovsim {

ConfigCostTarget config_cost_target(const std::string& config, const std::string& models) {
  const LoadedConfig lc = load_config(config);
  ConfigCostTarget t;
  t.config = config;
  Params root(lc.doc, config);
  if (root.has("display") && root.json()["display"].is_object()) {
    Params dp = root.child("display");
    t.display = Display::from_params(dp);
  } else {
    t.display = Display::load(root.string("display", "htc_vive_pro_eye"), models);
  }
  t.workload = Workload::load(root.string("workload", "generic"), models);
  {
    Params sp = root.child("scene");
    const Scene scene = make_scene(sp, models);
    t.features = scene.features();
    // The counts the run resolves against the scene (Workload::tris / nlights / nshadowed)
    // and the RSM size its VPLs come from (scene.vpl.rsm_size, one RSM per light).
    t.workload.triangles = t.workload.tris(t.features);
    t.workload.lights = t.workload.nlights(t.features);
    t.workload.shadowed_lights = t.workload.nshadowed(t.features);
    if (t.features.indirect) t.workload.rsm_res = scene.vpl.rsm_size;
  }
  const Json& ms = lc.doc.contains("methods") ? lc.doc.at("methods") : Json::array();
  if (!ms.is_array() || ms.empty())
    throw Error(config + ": methods", "at least one method is required");
  for (size_t i = 0; i < ms.size(); ++i) {
    const Json& m = ms[i];
    const std::string where = config + ": methods[" + std::to_string(i) + "]";
    if (!m.is_object() || !m.contains("method") || !m.at("method").is_string())
      throw Error(where, "expected an object with \"method\"");
    ConfigMethod cm;
    cm.method = m.at("method").get<std::string>();
    cm.label = m.value("label", cm.method);
    for (auto it = m.begin(); it != m.end(); ++it)
      if (it.key() != "method" && it.key() != "label") cm.params[it.key()] = it.value();
    t.methods.push_back(cm);
  }
  if (lc.doc.contains("gpus") && lc.doc.at("gpus").is_array())
    for (auto& g : lc.doc.at("gpus"))
      if (g.is_string()) t.gpus.push_back(g.get<std::string>());
  if (t.gpus.empty()) t.gpus.push_back("gtx1080");
  return t;
}

}  // namespace fovsim
