// Workload descriptor (models/workloads/*.json): what a scene costs the GPU beyond the
// counters a method measures -- triangles, lights, overdraw, shading cost per sample,
// which post-processing passes exist -- so the cost model can run without rendering.
// Its keys are declared once, in workload_table() and pipeline_table() below.
#pragma once
#include <string>
#include <vector>

#include "sim/core/param_table.h"
#include "sim/core/params.h"
#include "sim/scene/scene.h"

namespace fovsim {

// Optional passes of the pipeline (docs/architecture.md "Cost model": a pass that does not exist
// costs nothing).
struct PipelineOptions {
  bool depth_prepass = true;
  bool skybox = false;
  bool ssao = false;
  bool tonemap = true;
  bool taa = false;
  bool post_aa = false;  // FLC's Gaussian blur + TAA (Yang et al. 2021 §6)
  bool frame = false;    // fixed per-frame GPU work outside the passes (Meng 2018 Table 4.1)
};

struct Workload {
  std::string name = "generic";
  std::string source;
  // Geometry and lights. Negative = take from SceneFeatures.
  double triangles = -1;
  double lights = -1;               // lights evaluated per shaded sample
  double shadowed_lights = -1;      // shadow maps rendered per frame
  double submitted_fraction = 1.0;  // triangles left after frustum culling
  double overdraw = 1.5;            // rasterised fragments per pixel
  double gbuffer_bytes = 16;        // bytes written per G-buffer fragment
  double shadow_map_res = 2048;     // texels per side of a shadow map
  // Effective FP32 operations per shaded sample and light at the GPU's peak rate (fitted by
  // `fovsim calibrate` for the seeds' scenes). The default is the mean of the fitted scenes.
  double shading_flops = 3000;
  // Cost of a submitted triangle in the G-buffer pass relative to the mean of the calibrated
  // scenes (vertex shading, attributes, materials differ per scene). Fitted by
  // `fovsim calibrate` for the seeds' scenes from their Render rows; 1 = the mean.
  double tri_cost = 1.0;
  // FLC (Yang et al. 2021 §6): per-VPL shading cost, RSM size, importance samples, VPL budget.
  double vpl_flops = -1;  // <0: shading_flops
  double rsm_res = 64;
  double importance_samples = 4096;
  double chain_length = 8;  // M in Alg. 1
  double vpl_budget = 1024;
  // VPL shading work per VPL grows as (kept / vpl_ref)^(vpl_exponent - 1) (Yang et al. 2021
  // §7, Fig. 7: "almost quadratically"); 1 = linear in the VPLs kept.
  double vpl_exponent = 1.0;
  double vpl_ref = 1024;
  double interleave =
      4;  // interleaved-sampling factor (each pixel shades 1/interleave of the VPLs)
  double lpt_fraction =
      1.0;  // shaded samples / pixels with the log-polar transform (Yang et al. 2021 §6)
  // TWFR (Franke et al. 2021 §8.4) analytic defaults.
  double twfr_redraw_fraction = 0.059;  // 108K / 1.84M fragments
  double twfr_prims_fraction = 0.667;   // 1.8M / 2.7M primitives
  // fVRS / baselines: shaded fraction when no density model is given (<0: computed).
  double shaded_fraction = -1;
  PipelineOptions pipeline;

  // Resolves negatives against the scene's features.
  double tris(const SceneFeatures& f) const {
    return triangles >= 0 ? triangles : double(f.triangles);
  }
  double nlights(const SceneFeatures& f) const { return lights >= 0 ? lights : double(f.lights); }
  double nshadowed(const SceneFeatures& f) const {
    return shadowed_lights >= 0 ? shadowed_lights : double(f.shadowed_lights);
  }

  static Workload from_params(Params& p);
  // models_dir/workloads/NAME.json or a path.
  static Workload load(const std::string& name_or_path, const std::string& models_dir);
  // Workload names in models_dir/workloads (sorted).
  static std::vector<std::string> available(const std::string& models_dir);
  // The workload `fovsim predict` / `budget` (and the Python estimate, predict, budget) cost a
  // method on: a named one. Without a scene the generic workload knows no triangles and no
  // lights, so every method's shading cost (and KFR's speedup) would be meaningless: "" and
  // "generic" are an Error at `where` listing the available workloads; `alternative` ends the
  // message (the CLI's "or --config CONFIG for a run config's scene").
  static Workload load_for_costing(const std::string& name_or_path, const std::string& models_dir,
                                   const std::string& where, const std::string& alternative);
  Json to_json() const;
};

// The declared keys of a workload file and of its `pipeline` object (sim/core/param_table.h).
const ParamTable<Workload>& workload_table();
const ParamTable<PipelineOptions>& pipeline_table();

}  // namespace fovsim
