// Cost inputs of a run config without rendering (see config_cost.h).
#include "sim/experiment/config_cost.h"

#include "sim/core/error.h"
#include "sim/cost/analytic.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/experiment/config.h"

namespace fovsim {

ConfigCostTarget config_cost_target(const std::string& config, const std::string& models) {
  const LoadedConfig lc = load_config(config);
  ConfigCostTarget t;
  t.config = config;
  Params root(lc.doc, config);
  t.display = Display::from_config(root, models);
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
  t.gpus = GpuProfile::names_from_config(root);
  return t;
}

// The analytic rung of the fidelity ladder (fidelity.h) and `predict` on a run config's methods.
ResultTable analytic_summary(const LoadedConfig& cfg, const std::string& models_dir,
                             std::vector<std::string>* notes) {
  const std::string models = models_dir.empty() ? default_models_dir() : models_dir;
  const Json& doc = cfg.doc;
  Params root(doc, cfg.file);
  Display d = Display::from_config(root, models);
  Json sj = doc.contains("scene") ? doc["scene"] : Json::object();
  Params sp(sj, cfg.file, "scene");
  Scene scene = make_scene(sp, models);
  const SceneFeatures f = scene.features();
  Workload w = Workload::load(doc.contains("workload") && doc["workload"].is_string()
                                  ? doc["workload"].get<std::string>()
                                  : "generic",
                              models);
  // analytic_counters sees only the workload: what it leaves to the scene (-1: triangles,
  // lights) is resolved from this scene's features, as the cost model does for a rendered run.
  if (w.triangles < 0) w.triangles = double(f.triangles);
  if (w.lights < 0) w.lights = double(f.lights);
  if (w.shadowed_lights < 0) w.shadowed_lights = double(f.shadowed_lights);
  if (f.indirect) w.rsm_res = scene.vpl.rsm_size;  // the scene's VPL set (scene.vpl)
  std::vector<GpuProfile> gpus;
  for (auto& g : GpuProfile::names_from_config(root)) gpus.push_back(GpuProfile::load(g, models));
  ResultTable t;
  if (!doc.contains("methods") || !doc["methods"].is_array()) return t;
  const Json& ms = doc["methods"];
  for (size_t i = 0; i < ms.size(); ++i) {
    Json params = ms[i];
    std::string method = params.value("method", "");
    std::string label = params.value("label", method);
    params.erase("method");
    params.erase("label");
    Counters c;
    CostPasses passes;
    try {
      c = analytic_counters(method, params, w, d, "methods[" + std::to_string(i) + "]", f.indirect,
                            &passes);
    } catch (const Error& e) {
      if (notes) notes->push_back("analytic: " + label + " left out (" + e.what() + ")");
      continue;
    }
    for (auto& g : gpus) {
      CostInputs in;
      in.method = method;
      in.counters = &c;
      in.passes = passes;
      in.features = f;
      in.display = d;
      in.workload = &w;
      FrameCost fc = estimate_frame(g, in);
      ResultRow r;
      r.set_text("config_id", gpus.size() > 1 ? label + "@" + g.name : label);
      r.set_text("method", method);
      r.set_text("label", label);
      r.set_text("gpu", g.name);
      r.set("frames", 1);
      double shaded = c.get(Counter::shaded_samples);
      r.set("shaded_samples", shaded);
      r.set("shaded_fraction", shaded / (double(d.width) * d.height));
      r.set("prims_submitted", c.get(Counter::prims_submitted, double(f.triangles)));
      r.set("prims_culled", c.get(Counter::prims_culled, 0.0));
      for (auto& [cn, cv] : c.items())
        if (const auto k = find_counter(cn); !k || !reported_by_row_builder(k->id)) r.set(cn, cv);
      r.set("est_ms_total", fc.total_ms);
      r.set("est_ms_total_p95", fc.total_ms);
      for (auto& pc : fc.passes) r.set("est_ms_" + pc.pass, pc.ms);
      t.add(std::move(r));
    }
  }
  return t;
}

}  // namespace fovsim
