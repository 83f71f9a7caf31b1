// Workload descriptors (models/workloads/*.json): the keys are workload_table() and
// pipeline_table() (configs/README.md "Workload" is generated from them).
#include "sim/cost/workload.h"

#include <algorithm>
#include <filesystem>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/message_text.h"

namespace fovsim {

const ParamTable<Workload>& workload_table() {
  using W = Workload;
  // Every number has an upper bound far above any real scene (and far below overflow: the
  // largest products of passes.cpp, e.g. shadow_map_res^2 x shadowed_lights or shaded samples x
  // lights x shading_flops, stay finite); -1 takes the scene's value (validator below).
  const auto from_scene = [](double hi) { return Range::closed(-1, hi); };
  static const auto t =
      ParamTable<W>()
          .text("name", "generic", {}, &W::name)
          .doc("", "workload name (results, manifest)")
          .text("source", "", {}, &W::source)
          .shown("\"\"")
          .doc("", "where the numbers come from")
          .documented("comment", "any", "", "", "", "ignored")
          .documented("assumptions", "any", "", "", "", "free text: what the numbers assume")
          .documented("fitted_by", "any", "", "", "", "free text: what fitted the numbers")
          .number("triangles", -1, from_scene(1e10), &W::triangles)
          .doc("", "triangles of the scene; -1: from the scene's features")
          .number("lights", -1, from_scene(1e6), &W::lights)
          .doc("", "lights evaluated per shaded sample; -1: from the scene's features")
          .number("shadowed_lights", -1, from_scene(1e4), &W::shadowed_lights)
          .doc("", "shadow maps rendered per frame; -1: from the scene's features")
          .number("submitted_fraction", 1.0, Range::closed(0, 1), &W::submitted_fraction)
          .doc("", "triangles left after frustum culling")
          .number("overdraw", 1.5, Range::closed(0, 100), &W::overdraw)
          .doc("", "rasterised fragments per pixel")
          .number("gbuffer_bytes", 16, Range::closed(0, 1024), &W::gbuffer_bytes)
          .doc("", "bytes written per G-buffer fragment")
          .number("shadow_map_res", 2048, Range::closed(0, 65536), &W::shadow_map_res)
          .doc("", "texels per side of a shadow map")
          .number("shading_flops", 3000, Range::closed(0, 1e9), &W::shading_flops)
          .doc("",
               "effective FP32 operations per shaded sample and light at the GPU's peak rate "
               "(fitted by `fovsim calibrate`; the default is the mean of the fitted scenes)")
          .number("tri_cost", 1.0, Range::closed(0, 1e6), &W::tri_cost)
          .doc("",
               "cost of a submitted triangle in the G-buffer pass relative to the mean of the "
               "calibrated scenes (fitted; 1 = the mean)")
          .number("vpl_flops", -1, from_scene(1e9), &W::vpl_flops)
          .doc("Yang et al. 2021 §6", "per-VPL shading cost (fitted); -1: `shading_flops`")
          .number("rsm_res", 64, Range::closed(0, 16384), &W::rsm_res)
          .doc("Yang et al. 2021 §6", "RSM texels per side")
          .number("importance_samples", 4096, Range::closed(0, 1e8), &W::importance_samples)
          .doc("Yang et al. 2021 Alg. 1", "importance samples N_s")
          .number("chain_length", 8, Range::closed(0, 1e4), &W::chain_length)
          .doc("Yang et al. 2021 Alg. 1", "proposals per chain M")
          .number("vpl_budget", 1024, Range::closed(0, 1e8), &W::vpl_budget)
          .doc("Yang et al. 2021 §7", "VPLs kept for shading")
          .number("vpl_exponent", 1.0, Range::closed(1, 3), &W::vpl_exponent)
          .doc("Yang et al. 2021 §7, Fig. 7",
               "VPL shading work per VPL grows as (kept / vpl_ref)^(vpl_exponent - 1); 1 = "
               "linear in the VPLs kept")
          .number("vpl_ref", 1024, Range::closed(1, 1e8), &W::vpl_ref)
          .doc("Yang et al. 2021 §7", "reference VPL count of `vpl_exponent`")
          .number("interleave", 4, Range::closed(1, 1e4), &W::interleave)
          .doc("Yang et al. 2021 §6",
               "interleaved-sampling factor (each pixel shades 1/interleave of the VPLs)")
          .number("lpt_fraction", 1.0, Range::closed(0, 1), &W::lpt_fraction)
          .doc("Yang et al. 2021 §6", "shaded samples / pixels with the log-polar transform")
          .number("twfr_redraw_fraction", 0.059, Range::closed(0, 1), &W::twfr_redraw_fraction)
          .doc("Franke et al. 2021 §8.4", "redrawn fragments (108K / 1.84M)")
          .number("twfr_prims_fraction", 0.667, Range::closed(0, 1), &W::twfr_prims_fraction)
          .doc("Franke et al. 2021 §8.4", "redrawn primitives (1.8M / 2.7M)")
          .number("shaded_fraction", -1, Range::closed(-1, 1), &W::shaded_fraction)
          .doc("",
               "fVRS and the baselines: shaded fraction when no density model is given; -1: "
               "computed")
          .documented("pipeline", "object", "", "", "", "optional passes: `pipeline` below")
          .validate([](const W& w, Params& p) {
            // -1 is "from the scene"; any other negative value is a typo, not a default.
            const std::pair<const char*, double> keys[] = {{"triangles", w.triangles},
                                                           {"lights", w.lights},
                                                           {"shadowed_lights", w.shadowed_lights},
                                                           {"vpl_flops", w.vpl_flops},
                                                           {"shaded_fraction", w.shaded_fraction}};
            for (auto& [key, v] : keys)
              if (v < 0 && v != -1)
                p.fail(key, "value " + shortest_number(v) +
                                " is out of range: -1 (from the scene) or a value >= 0");
          });
  return t;
}

const ParamTable<PipelineOptions>& pipeline_table() {
  using P = PipelineOptions;
  static const auto t =
      ParamTable<P>()
          .boolean("depth_prepass", true, &P::depth_prepass)
          .doc("", "a depth pre-pass before the G-buffer")
          .boolean("skybox", false, &P::skybox)
          .doc("", "a skybox pass")
          .boolean("ssao", false, &P::ssao)
          .doc("", "screen-space ambient occlusion")
          .boolean("tonemap", true, &P::tonemap)
          .doc("", "a tone-mapping pass")
          .boolean("taa", false, &P::taa)
          .doc("", "temporal anti-aliasing")
          .boolean("post_aa", false, &P::post_aa)
          .doc("Yang et al. 2021 §6", "FLC's Gaussian blur + TAA")
          .boolean("frame", false, &P::frame)
          .doc("Meng 2018 Table 4.1", "fixed per-frame GPU work outside the passes");
  return t;
}

Workload Workload::from_params(Params& p) {
  Workload w;
  p.ignore("comment");
  p.ignore("assumptions");
  p.ignore("fitted_by");
  workload_table().read_into(p, w);
  Params pl = p.child("pipeline");
  pipeline_table().read_into(pl, w.pipeline);
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

Workload Workload::load_for_costing(const std::string& name_or_path, const std::string& models_dir,
                                    const std::string& where, const std::string& alternative) {
  if (name_or_path.empty() || name_or_path == "generic") {
    std::string av;
    for (auto& n : available(models_dir))
      if (n != "generic") av += (av.empty() ? "" : ", ") + n;
    throw Error(where,
                std::string(name_or_path.empty() ? "required" : "'generic' describes no scene") +
                    " (the scene's triangles, lights and shading cost decide every estimate; "
                    "available: " +
                    av + (alternative.empty() ? "" : "; " + alternative) + ")");
  }
  return load(name_or_path, models_dir);
}

Json Workload::to_json() const {
  Json j = Json::object();
  for (const auto& r : workload_table().rows())
    if (!r.doc_only) j[r.key] = r.get(*this);
  Json pl = Json::object();
  for (const auto& r : pipeline_table().rows()) pl[r.key] = r.get(pipeline);
  j["pipeline"] = pl;
  return j;
}

}  // namespace fovsim
