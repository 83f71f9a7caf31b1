// The keys every cell of a reference group shares (docs/architecture.md "Data flow of one
// frame", step 0 "Configuration"): display and render settings, the scene and its tone map, the
// frame range, the trace (resampled over the range the run uses), the reference cache's block
// and run.memory_gb. Parsed once per group by its first cell (parse_group, engine.cpp); they
// enter reference_key.
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "sim/core/params.h"
#include "sim/display/display.h"
#include "sim/experiment/reference_cache.h"
#include "sim/render/renderer.h"
#include "sim/render/tonemap.h"
#include "sim/scene/scene.h"
#include "sim/trace/trace.h"
#include "sim/trace/tracking.h"

namespace fovsim {

// Everything the references depend on, parsed once per group.
struct Shared {
  std::string models;
  uint64_t seed = 1;
  Display display, sim_display;
  double scale = 1;
  RenderSettings rs;
  std::unique_ptr<Scene> scene;  // the Renderer keeps a reference: stable address
  ToneMap tonemap;
  Trace trace;
  Trace raw_trace;               // before resampling: gaze at any time for the latency what-if
  TrackingPolicy tracking;       // trace.on_invalid (sim/trace/tracking.h)
  bool tracking_column = false;  // frames.csv `tracking`: a policy given or invalid frames
  int start = 0, stride = 1, count = 0;
  int warmup = 0;                // frames.warmup: rendered before `start`, not recorded
  bool include_startup = false;  // frames.include_startup (startup.h)
  double pixel_scale = 1;
  Json resolved;                 // resolved shared keys (for every cell's manifest)
  ReferenceCacheSettings cache;  // the `cache` block (reference_cache.h)
  Json scene_config;             // the resolved `scene` block (the reference cache's key)
  double memory_gb = 0;          // run.memory_gb (0: the option's, else the machine's)

  // Reads the shared keys in the order a single run reads them (the first error reported is
  // the same): display and render, scene and tone map, frame range, trace, the range's checks.
  void parse(Params& root, const std::string& cfg_file, const std::string& base_dir);

  // The display, the render block and the simulated display (render.scale, under
  // render.max_pixels). Returns render.tonemap, read after the scene (its exposure default).
  Params parse_display_render(Params& root);
  // The scene and the tone map (whose exposure defaults to the scene's).
  void parse_scene(Params& root, Params& tp);
  // The trace: loaded and resampled to the refresh rate over only the frames the run uses (the
  // raw trace is kept for the latency what-if), placed at the scene's default eye
  // (trace_placement "scene"), every head position within the coordinate bound.
  void parse_trace(Params& root, const std::string& base_dir, const std::string& placement);
  // The frame range against the trace: past its end is an error; a range longer than the trace
  // is one too unless frames.on_short_trace = "truncate"; frames.count 0 takes all.
  void check_frame_range(Params& fp, const std::string& on_short);
};

}  // namespace fovsim
