// GPU pipeline cost model (docs/architecture.md "Cost model"). A frame is the list of passes that
// exist for this scene and method; each pass time is a small linear model of measured counters with
// coefficients from a GPU profile (models/gpus/*.json) plus a fixed overhead.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sim/core/counters.h"
#include "sim/core/params.h"
#include "sim/display/display.h"
#include "sim/foveation/method.h"
#include "sim/scene/scene.h"

namespace fovsim {

struct PassCost {
  std::string pass;  // column suffix: est_ms_<pass>
  double ms = 0;
  // Prediction interval of this pass (est_ms_<pass>_lo/_hi; equal to ms without an interval).
  double lo_ms = 0, hi_ms = 0;
};

struct FrameCost {
  std::vector<PassCost> passes;
  double total_ms = 0;
  // Prediction interval on total_ms (interval_level 0: the profile has none),
  // combined from the passes' intervals (combine_pass_intervals, gpu_profile.h).
  double interval_level = 0, total_lo_ms = 0, total_hi_ms = 0;
  // Counters the passes read that the method did not fill (charged as 0, docs/architecture.md "Cost
  // model" note).
  std::vector<std::string> missing_counters;
  // Time per resource class (geometry, raster, shading, memory, fixed = overheads); sums to total.
  std::map<std::string, double> resource_ms;
  double pass_ms(const std::string& pass) const;  // 0 when the pass does not exist
};

struct GpuProfile;  // defined in gpu_profile.h
struct Workload;    // defined in workload.h

struct CostInputs {
  std::string method;                  // factory name
  const Counters* counters = nullptr;  // measured at the simulated resolution
  // The passes the method and its lighting strategy declare (declared_passes, factory.h); unset:
  // those of `method` with its default lighting strategy.
  std::optional<CostPasses> passes;
  // The frame's shared work (its counters: rsm_texels), charged to a method that declares it
  // uses it (CostPasses::frame_rsm) and did not count it itself. nullptr: none.
  const Counters* shared = nullptr;
  SceneFeatures features;
  Display display;           // the real (unscaled) display being costed
  double pixel_scale = 1.0;  // (display W*H) / (simulated W*H): scales pixel counters
  // Scene cost descriptor (overdraw, shading cost, optional passes). nullptr: defaults
  // resolved against `features` (Workload{}), see docs/cost_model.md.
  const Workload* workload = nullptr;
};

// Per-pass and total estimate. Per-eye passes are charged display.eyes times; shadow maps
// and RSMs once per frame. Pixel counters are multiplied by pixel_scale, triangles are not.
FrameCost estimate_frame(const GpuProfile& gpu, const CostInputs& in);

// The shared counters (CostInputs::shared) the method declares it uses, for its frames.csv row.
Counters shared_counters(const CostInputs& in);

}  // namespace fovsim
