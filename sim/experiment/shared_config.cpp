#include "sim/experiment/shared_config.h"

#include <cmath>
#include <cstdio>

#include "sim/core/error.h"
#include "sim/core/limits.h"
#include "sim/experiment/run_config.h"
#include "sim/experiment/table.h"

namespace fovsim {

void Shared::parse(Params& root, const std::string& cfg_file, const std::string& base_dir) {
  const RunSharedKeys top = run_shared_table().read(root);
  seed = uint64_t(top.seed);
  Params tp = parse_display_render(root);
  parse_scene(root, tp);
  // The frame range is read first so that only the part of the trace it uses is resampled
  // (a trace spanning 1e7 s with frames.count = 2 resamples 2 frames, not 1e7 s).
  Params fp = root.child("frames");
  const FramesBlock fb = frames_block_table().read(fp);
  start = fb.start;
  stride = fb.stride;
  count = fb.count;  // 0 = all available
  // Warm-up frames (frames.warmup): the first `warmup` frames of the range are rendered and
  // fed to every method (TWFR's cold first frame, temporal history) but not recorded; the
  // recorded frames, frames.count of them, follow.
  warmup = fb.warmup;
  include_startup = fb.include_startup;
  start += warmup * stride;
  parse_trace(root, base_dir, top.trace_placement);
  check_frame_range(fp, fb.on_short_trace);
  pixel_scale =
      double(display.width) * display.height / (double(sim_display.width) * sim_display.height);
  for (int k = 0; k < count && !tracking_column; ++k)
    tracking_column = !trace.samples[size_t(start + k * stride)].valid;
  {
    Params cp = root.child("cache");
    cache = ReferenceCacheSettings::from_params(cp);
  }
  {
    Params rp = root.child("run");
    memory_gb = run_block_table().read(rp).memory_gb;
  }
  scene_config = root.resolved().contains("scene") ? root.resolved()["scene"] : Json::object();
  (void)cfg_file;
}

Params Shared::parse_display_render(Params& root) {
  display = Display::from_config(root, models);
  Params rp = root.child("render");
  const RenderBlock rb = render_block_table().read(rp);
  scale = rb.scale;
  rs = RenderSettings::from_params(rp);
  Params tp = rp.child("tonemap");
  sim_display = display.scaled(scale);
  // Images and G-buffers scale with the simulated pixel count: refuse before allocating.
  const double max_px = rb.max_pixels;
  const double px = double(sim_display.width) * double(sim_display.height);
  if (px > max_px)
    rp.fail("scale", "simulated resolution " + std::to_string(sim_display.width) + "x" +
                         std::to_string(sim_display.height) + " (" + format_number(px) +
                         " pixels) is over the limit render.max_pixels = " + format_number(max_px) +
                         " (lower render.scale or raise render.max_pixels)");
  return tp;
}

void Shared::parse_scene(Params& root, Params& tp) {
  Params sp = root.child("scene");
  scene = with_memory_context(
      root.where("scene"), "building the scene",
      "lower scene.complexity, use a coarser scene or lower scene.max_triangles",
      [&] { return std::make_unique<Scene>(make_scene(sp, models)); });
  ToneMapBlock tb;
  tb.exposure = scene->exposure;  // the default
  tonemap_block_table().read_into(tp, tb);
  tonemap.exposure = tb.exposure;
  const std::string& curve = tb.curve;
  tonemap.curve = curve == "aces"
                      ? ToneMap::Curve::Aces
                      : (curve == "reinhard" ? ToneMap::Curve::Reinhard : ToneMap::Curve::Clamp);
}

void Shared::parse_trace(Params& root, const std::string& base_dir, const std::string& placement) {
  const double needed_s =
      count > 0 ? (double(start) + double(count - 1) * stride + 2.0) / display.refresh_hz
                : INFINITY;
  Params trp = root.child("trace");
  tracking_column = trp.has("on_invalid");  // else only when a recorded frame is invalid
  Trace raw_trace = with_memory_context(
      root.where("trace"), "reading and resampling the trace",
      "lower trace.max_samples, frames.count or the trace's length", [&] {
        Trace raw = load_trace(trp, display, base_dir, needed_s, &tracking);
        trace = resample(raw, display.refresh_hz,
                         raw.samples.empty() ? INFINITY : raw.samples.front().t + needed_s);
        return raw;
      });
  this->raw_trace = raw_trace;
  if (trace.samples.empty())
    throw Error(root.where("trace"), "trace has no samples after resampling");
  if (placement == "scene") {
    // The trace's first head position is placed at the scene's default eye (recordings use
    // their own world origin); orientation is kept as recorded.
    glm::dvec3 p0 = trace.samples.front().head_pos;
    for (auto& s : trace.samples) s.head_pos = glm::dvec3(scene->default_eye) + (s.head_pos - p0);
  }
  // The eye points the renderer traces from, within the bound `trace validate` applies.
  for (const auto& s : trace.samples)
    for (int c = 0; c < 3; ++c)
      if (!(std::fabs(s.head_pos[c]) <= kMaxCoordinateM)) {
        char b[160];
        std::snprintf(
            b, sizeof b,
            "head position %.6g m at t = %.6g s is beyond the coordinate "
            "bound +-1e5 m%s",
            s.head_pos[c], s.t,
            placement == "scene" ? " (after placing the trace at the scene's default eye)" : "");
        throw Error(root.where("trace"), b);
      }
}

void Shared::check_frame_range(Params& fp, const std::string& on_short) {
  int avail = int(trace.samples.size());
  if (start >= avail)
    fp.fail(warmup > 0 ? "warmup" : "start",
            "frame " + std::to_string(start) +
                (warmup > 0 ? " (after " + std::to_string(warmup) + " warm-up frames)" : "") +
                " is past the end of the trace (" + std::to_string(avail) + " frames at " +
                format_number(display.refresh_hz) + " Hz)");
  int max_count = (avail - start + stride - 1) / stride;
  if (count == 0) count = max_count;
  if (count > max_count) {
    if (on_short == "fail")
      fp.fail("count", "trace is too short: " + std::to_string(count) +
                           " frames requested from frame " + std::to_string(start) +
                           " with stride " + std::to_string(stride) + ", only " +
                           std::to_string(max_count) +
                           " available (set frames.on_short_trace=\"truncate\" to accept)");
    count = max_count;
  }
}

}  // namespace fovsim
