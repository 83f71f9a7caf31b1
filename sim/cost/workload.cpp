// Workload descriptors (models/workloads/*.json); keys in docs/cost_model.md.
#include "sim/cost/workload.h"

#include <algorithm>
#include <filesystem>

#include "sim/core/error.h"
#include "sim/core/files.h"

namespace fovsim {

Workload Workload::from_params(Params& p) {
  Workload w;
  auto any = Range::at_least(-1);
  auto nonneg = Range::at_least(0);
  w.name = p.string("name", w.name);
  w.source = p.string("source", "");
  p.ignore("comment");
  p.ignore("assumptions");
  p.ignore("fitted_by");
  w.triangles = p.number("triangles", w.triangles, any);
  w.lights = p.number("lights", w.lights, any);
  w.shadowed_lights = p.number("shadowed_lights", w.shadowed_lights, any);
  w.submitted_fraction = p.number("submitted_fraction", w.submitted_fraction, Range::closed(0, 1));
  w.overdraw = p.number("overdraw", w.overdraw, Range::closed(0, 100));
  w.gbuffer_bytes = p.number("gbuffer_bytes", w.gbuffer_bytes, nonneg);
  w.shadow_map_res = p.number("shadow_map_res", w.shadow_map_res, nonneg);
  w.shading_flops = p.number("shading_flops", w.shading_flops, nonneg);
  w.tri_cost = p.number("tri_cost", w.tri_cost, Range::closed(0, 1e6));
  w.vpl_flops = p.number("vpl_flops", w.vpl_flops, any);
  w.rsm_res = p.number("rsm_res", w.rsm_res, nonneg);
  w.importance_samples = p.number("importance_samples", w.importance_samples, nonneg);
  w.chain_length = p.number("chain_length", w.chain_length, nonneg);
  w.vpl_budget = p.number("vpl_budget", w.vpl_budget, nonneg);
  w.vpl_exponent = p.number("vpl_exponent", w.vpl_exponent, Range::closed(1, 3));
  w.vpl_ref = p.number("vpl_ref", w.vpl_ref, Range::above(0));
  w.interleave = p.number("interleave", w.interleave, Range::at_least(1));
  w.lpt_fraction = p.number("lpt_fraction", w.lpt_fraction, Range::closed(0, 1));
  w.twfr_redraw_fraction =
      p.number("twfr_redraw_fraction", w.twfr_redraw_fraction, Range::closed(0, 1));
  w.twfr_prims_fraction =
      p.number("twfr_prims_fraction", w.twfr_prims_fraction, Range::closed(0, 1));
  w.shaded_fraction = p.number("shaded_fraction", w.shaded_fraction, Range::closed(-1, 1));
  Params pl = p.child("pipeline");
  w.pipeline.depth_prepass = pl.boolean("depth_prepass", w.pipeline.depth_prepass);
  w.pipeline.skybox = pl.boolean("skybox", w.pipeline.skybox);
  w.pipeline.ssao = pl.boolean("ssao", w.pipeline.ssao);
  w.pipeline.tonemap = pl.boolean("tonemap", w.pipeline.tonemap);
  w.pipeline.taa = pl.boolean("taa", w.pipeline.taa);
  w.pipeline.post_aa = pl.boolean("post_aa", w.pipeline.post_aa);
  w.pipeline.frame = pl.boolean("frame", w.pipeline.frame);
  return w;
}

Workload Workload::load(const std::string& name_or_path, const std::string& models_dir) {
  bool path =
      name_or_path.find('/') != std::string::npos ||
      (name_or_path.size() > 5 && name_or_path.compare(name_or_path.size() - 5, 5, ".json") == 0);
  std::string file = path ? name_or_path : models_dir + "/workloads/" + name_or_path + ".json";
  if (!file_exists(file)) throw Error(file, "unknown workload '" + name_or_path + "'");
  Params p = Params::from_file(file);
  Workload w = from_params(p);
  p.finish();
  return w;
}

std::vector<std::string> Workload::available(const std::string& models_dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (auto& e : std::filesystem::directory_iterator(models_dir + "/workloads", ec))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

Json Workload::to_json() const {
  return {{"name", name},
          {"source", source},
          {"triangles", triangles},
          {"lights", lights},
          {"shadowed_lights", shadowed_lights},
          {"submitted_fraction", submitted_fraction},
          {"overdraw", overdraw},
          {"gbuffer_bytes", gbuffer_bytes},
          {"shadow_map_res", shadow_map_res},
          {"shading_flops", shading_flops},
          {"tri_cost", tri_cost},
          {"vpl_flops", vpl_flops},
          {"rsm_res", rsm_res},
          {"importance_samples", importance_samples},
          {"chain_length", chain_length},
          {"vpl_budget", vpl_budget},
          {"vpl_exponent", vpl_exponent},
          {"vpl_ref", vpl_ref},
          {"interleave", interleave},
          {"lpt_fraction", lpt_fraction},
          {"twfr_redraw_fraction", twfr_redraw_fraction},
          {"twfr_prims_fraction", twfr_prims_fraction},
          {"shaded_fraction", shaded_fraction},
          {"pipeline",
           {{"depth_prepass", pipeline.depth_prepass},
            {"skybox", pipeline.skybox},
            {"ssao", pipeline.ssao},
            {"tonemap", pipeline.tonemap},
            {"taa", pipeline.taa},
            {"post_aa", pipeline.post_aa},
            {"frame", pipeline.frame}}}};
}

}  // namespace fovsim
