#include "sim/experiment/run_config.h"

#include <cmath>

#include "sim/core/message_text.h"
#include "sim/cost/budget.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/workload.h"
#include "sim/display/display.h"
#include "sim/display/display_keys.h"
#include "sim/experiment/latency.h"
#include "sim/experiment/reference_cache.h"
#include "sim/experiment/sweep_spec.h"
#include "sim/metrics/metrics.h"
#include "sim/render/renderer.h"
#include "sim/scene/scene_keys.h"
#include "sim/trace/synth.h"
#include "sim/trace/trace_keys.h"

namespace fovsim {

// Each table: one row per key (type, default, range, source, meaning, the member it fills).

const ParamTable<RunSharedKeys>& run_shared_table() {
  using K = RunSharedKeys;
  static const std::string display_def = std::string("`\"") + kDefaultDisplay + "\"`";
  static const auto t =
      ParamTable<K>()
          .integer("seed", 1, Range::closed(0, 2e9), &K::seed)
          .doc("",
               "seed for every stochastic part (synthetic traces, FLC sampling, the frame "
               "order of `fovsim run --target`)")
          .documented("display", "string or object", display_def.c_str(), "", "",
                      "a model name from `models/displays/` or an inline display object (keys: "
                      "\"Display\" below)")
          .text("trace_placement", "scene", {"scene", "absolute"}, &K::trace_placement)
          .doc("",
               "`scene`: the trace's first head position is placed at the scene's default "
               "eye (recordings use their own world origin); `absolute`: head positions are "
               "used as recorded");
  return t;
}

const ParamTable<RunCellKeys>& run_cell_table() {
  using K = RunCellKeys;
  static const std::string gpus_def = std::string("`[\"") + kDefaultGpu + "\"]`";
  static const auto t =
      ParamTable<K>()
          .text("name", nullptr, {}, &K::name)
          .default_from_member("file stem")
          .doc("",
               "results go to `results/<name>/` unless `--out` is given; the name becomes "
               "one folder name through the same rule as labels, so `\"../../x\"` writes to "
               "`results/_._.._x/`")
          .text("workload", "generic", {}, &K::workload)
          .doc("",
               "workload descriptor from `models/workloads/` for what the scene does not say "
               "(overdraw, G-buffer bytes, flops per shaded sample and per VPL pair, post "
               "passes); see `docs/cost_model.md`")
          .documented("gpus", "array of strings", gpus_def.c_str(), "", "",
                      "GPU profiles from `models/gpus/` (see `docs/cost_model.md`); one row per "
                      "frame x method x GPU; each profile once")
          // Objects read by their own tables (sections below) and free text.
          .documented("methods", "array of objects", "required", "", "",
                      "one entry per configuration: `method`, `label`, the method's keys and "
                      "its `lighting` block (tables under \"Methods\")")
          .documented("render", "object", "", "", "", "`render` and `render.tonemap` below")
          .documented("scene", "object", "", "", "",
                      "built-in or imported scene: `scene` below, one table per `type`")
          .documented("trace", "object", "", "", "",
                      "`{\"file\": ...}` or `{\"synthetic\": {...}}`: `trace` below, with the "
                      "tracking-loss policy")
          .documented("frames", "object", "", "", "", "`frames` below")
          .documented("metrics", "object", "", "", "", "`metrics` below")
          .documented("outputs", "object", "", "", "", "`outputs` below")
          .documented("cache", "object", "", "", "", "the reference cache: `cache` below")
          .documented("run", "object", "", "", "", "the memory budget: `run` below")
          .documented("budget", "object", "", "", "",
                      "the level of the frame-time budget decisions: `budget` below")
          .documented("latency", "object", "absent", "", "",
                      "latency what-if (`docs/latency.md`): methods foveate around the gaze at "
                      "t - latency, metrics use the true gaze at t; adds the columns of "
                      "`results/README.md` \"Latency what-if\"; a per-cell key (sweeps over it "
                      "share references). Keys: `latency` below")
          .documented("sweep", "object", "", "", "",
                      "makes the config a sweep, run with `fovsim sweep` (`sweep` below, "
                      "docs/sweeps.md); `fovsim run` refuses it")
          .documented("base", "string", "", "", "",
                      "a config loaded first, this one merged over it (\"Inheritance and "
                      "overrides\" above)")
          .documented("description", "string", "", "", "", "free text, ignored")
          .documented("comment", "string", "", "", "", "free text, ignored");
  return t;
}

const ParamTable<RenderBlock>& render_block_table() {
  using B = RenderBlock;
  static const auto t =
      ParamTable<B>()
          .number("scale", 1.0, Range::above(0, 4), &B::scale)
          .doc("",
               "simulated resolution = display resolution x scale (same FOV). Pixel counters "
               "are scaled back to the real display for the cost model and "
               "`shaded_samples`; `shaded_fraction` is resolution-independent")
          .number("max_pixels", 5e7, Range::closed(1, 1e10), &B::max_pixels)
          .doc("",
               "largest simulated resolution (width x height after `scale`); a larger one "
               "is refused before any image or G-buffer is allocated");
  return t;
}

const ParamTable<ToneMapBlock>& tonemap_block_table() {
  using B = ToneMapBlock;
  static const auto t =
      ParamTable<B>()
          .number("exposure", 1.0, Range::above(0, 1e6), &B::exposure)
          .default_from_member("scene's")
          .doc("", "linear scale before the curve")
          .text("curve", "aces", {"aces", "reinhard", "clamp"}, &B::curve)
          .doc("", "tone curve, then sRGB encoding; metrics are computed on the encoded values");
  return t;
}

const ParamTable<FramesBlock>& frames_block_table() {
  using B = FramesBlock;
  static const auto t =
      ParamTable<B>()
          .integer("start", 0, Range::at_least(0), &B::start)
          .doc("", "first frame of the trace resampled to the display's refresh rate")
          .integer("stride", 1, Range::closed(1, 1e6), &B::stride)
          .doc("",
               "simulate every stride-th frame (a speed/fidelity knob; temporal methods see "
               "the larger step)")
          .integer("count", 0, Range::at_least(0), &B::count)
          .doc("", "number of frames, 0 = all (recorded ones; warm-up frames come on top)")
          .integer("warmup", 0, Range::closed(0, 1e6), &B::warmup)
          .doc("",
               "frames rendered before the recorded ones and fed to every method (TWFR's "
               "cold first frame, temporal history), but not recorded: no rows, no images")
          .boolean("include_startup", false, &B::include_startup)
          .doc("",
               "keep the start-up frames in the means: by default the first frames a method "
               "declares as warm-up (TWFR: 1) and a metric's settle time (FovVideoVDP: 15 "
               "frames at 90 Hz) are in frames.csv but left out of summary.csv and "
               "paired.csv (docs/intervals.md)")
          .text("on_short_trace", "fail", {"fail", "truncate"}, &B::on_short_trace)
          .doc("", "what to do when the trace has fewer frames than requested");
  return t;
}

const ParamTable<OutputsBlock>& outputs_block_table() {
  using B = OutputsBlock;
  static const auto t =
      ParamTable<B>()
          .numbers("image_frames", {}, Range::closed(0, 2e9), &B::image_frames)
          .doc("",
               "frames for which images are written to `images/frame_<n>/`: "
               "`reference.png`, `<label>.png`, `<label>_error.png` (heat map of the "
               "absolute luma error, 0-0.25), debug buffers")
          .boolean("png", true, &B::png)
          .doc("", "write display-encoded PNGs")
          .boolean("exr", false, &B::exr)
          .doc("", "also write linear float EXRs")
          .boolean("error_images", true, &B::error_images)
          .doc("", "write `<label>_error.png` (luma error heat map) for each image frame")
          .boolean("debug_images", false, &B::debug_images)
          .doc("", "methods' debug buffers (LP/RS buffer, redraw map, importance map, ...)")
          .boolean("print_summary", true, &B::print_summary)
          .default_from_member("true")
          .doc("", "print the summary table on stdout at the end")
          .validate([](const B& b, Params& p) {  // frame indices: whole numbers only
            for (size_t i = 0; i < b.image_frames.size(); ++i)
              if (b.image_frames[i] != std::floor(b.image_frames[i]))
                p.fail("image_frames[" + std::to_string(i) + "]",
                       "expected a frame index (an integer), got " +
                           shortest_number(b.image_frames[i]));
          });
  return t;
}

const ParamTable<ReferenceCacheSettings>& cache_block_table() {
  using B = ReferenceCacheSettings;
  static const auto t =
      ParamTable<B>()
          .boolean("enabled", true, &B::enabled)
          .doc("",
               "use the cache: the shared references and the method memo (every command that "
               "renders references has `--no-cache`; the "
               "environment `FOVSIM_NO_CACHE=1` turns it off for the commands and the Python "
               "module; library callers leave it off unless they ask: `RunOptions::use_cache`)")
          .text("dir", "", {}, &B::dir)
          .shown("`\"\"`")
          .doc("",
               "folder of the cache; `\"\"` = `$FOVSIM_CACHE_DIR`, else "
               "`$XDG_CACHE_HOME/fovsim`, else `~/.cache/fovsim`. A relative path is relative "
               "to the current directory (as `--out` is: one cache for every config). Runs "
               "and sweep shards that point at one folder (also on a shared file system) "
               "reuse each other's frames")
          .number("max_gb", 0, Range::closed(0, 1e6), &B::max_gb)
          .shown("`0` (automatic)")
          .doc("",
               "size cap of the folder's cached references and method memo entries together, GB "
               "of 2^30 bytes; `0`: min(20 GB, 10% of the free disk space at the folder plus "
               "what the cache holds), chosen when a run opens the cache (the manifest's "
               "`reference_cache.max_gb`, `max_gb_auto`); `fovsim cache info` shows it, `fovsim "
               "cache prune` shrinks the folder now. The least recently used entries (by "
               "mtime; a read renews it) are removed first. The quickstart writes 5.2 MB per "
               "frame at render.scale 0.25; size grows with render.scale^2 (about 21 MB per "
               "frame at its shipped 0.5)")
          .number("note_mb", 100, Range::closed(0, 1e9), &B::note_mb)
          .doc("",
               "a run that adds more than this many MB (10^6 bytes) to the cache prints one "
               "line on stderr: the folder, what it holds, its cap, and the `fovsim cache` "
               "commands")
          .validate([](const B& b, Params& p) {
            if (b.dir.find('\0') != std::string::npos) p.fail("dir", "contains a NUL character");
          });
  return t;
}

const ParamTable<RunBlock>& run_block_table() {
  using B = RunBlock;
  static const auto t =
      ParamTable<B>()
          .number("memory_gb", 0, Range::closed(0, 1e6), &B::memory_gb)
          .shown("`0`")
          .doc("",
               "memory budget of a group of cells sharing references, GB (10^9 bytes): as many "
               "cells as fit (an estimate from the simulated resolution, the methods and "
               "FovVideoVDP's temporal window, docs/architecture.md \"Memory\") run side by "
               "side over one pass of the frames, the rest in later passes over the cached "
               "references, with the same numbers; `0` = `--memory-budget GB` when given, else "
               "75% of the machine's available memory (MemAvailable) when the group starts; the "
               "flag overrides this key. Passes and peak resident memory: the manifest's "
               "`memory`");
  return t;
}

const ParamTable<BudgetBlock>& budget_block_table() {
  using B = BudgetBlock;
  static const auto t =
      ParamTable<B>()
          .number("p_fit", kDefaultFitLevel, fit_level_range(), &B::p_fit)
          .doc("",
               "level of every budget decision of the run (docs/cost_model.md \"Budget "
               "decisions\"): a configuration fits (`fits_budget` 1) when the probability that "
               "its p95 frame fits the display's budget (`p_fit`, from the GPU profile's "
               "held-out frame-total errors) reaches it; `fit_threshold_ms` is the largest p95 "
               "estimate that does. The same rule as `fovsim budget --p`");
  return t;
}

const ParamTable<MethodEntryKeys>& method_entry_table() {
  static const auto t =
      ParamTable<MethodEntryKeys>()
          .documented("method", "string", "required", "", "",
                      "factory name: `full`, and the methods in `docs/methods.md`")
          .documented(
              "label", "string", "the method name", "", "",
              "unique name of this configuration (`config_id` in the results). In image file "
              "names every character other than `A-Z a-z 0-9 . _ + -` becomes `_`, and a "
              "leading `.` becomes `_` (one function, `safe_file_name` in `sim/core/files.h`, "
              "so nothing is written outside the output folder); two labels that give the same "
              "file name, or the name `reference`, are an error")
          .documented("lighting", "object", "`{\"method\": \"all_vpls\"}`", "", "",
                      "the lighting strategy for the scene's indirect light (only used when the "
                      "scene has it, `scene.indirect`): `{\"method\": \"flc\", \"vpl_budget\": "
                      "1024, ...}`; its keys are the strategy tables at the end of the methods' "
                      "section below; sweepable as `methods[kfr].lighting.vpl_budget`. Not "
                      "allowed on `flc`, which brings its own")
          .documented("other keys", "", "", "", "",
                      "the method's parameters: the tables below (generated from the methods' "
                      "declarations; `docs/methods.md` explains each method)");
  return t;
}

std::string config_keys_markdown() {
  auto section = [](const std::string& title, const std::string& md) {
    return "#### " + title + "\n\n" + md + "\n";
  };
  std::string md;
  md += section(
      "Top-level keys", run_shared_table().markdown(false) + [] {
        // continuation rows of the same table
        std::string s = run_cell_table().markdown(false);
        return s.substr(s.find('\n', s.find('\n') + 1) + 1);
      }());
  md += section(
      "`render`", render_block_table().markdown(false) + [] {
        std::string s = render_settings_table().markdown(false);
        return s.substr(s.find('\n', s.find('\n') + 1) + 1);
      }());
  md += section("Display (`display` object, `models/displays/*.json`)", display_table().markdown());
  md += section("`render.tonemap`", tonemap_block_table().markdown(false));
  md += section("`frames`", frames_block_table().markdown(false));
  md += section("`outputs`", outputs_block_table().markdown(false));
  md += section("`trace` (traces/README.md)", trace_block_table().markdown(false));
  md += section("`trace.synthetic`", synth_block_table().markdown(false));
  for (auto& sec : eye_model_tables()) {  // trace.synthetic.params (models/eyemodel/default.json)
    std::string path = sec.path;
    for (char& ch : path)
      if (ch == '/') ch = '.';
    md += section("`trace.synthetic.params` eye model" +
                      (path.empty() ? std::string(" (top level)") : ": `" + path + "`"),
                  sec.table.markdown());
  }
  md += section("`scene` (models/scenes/README.md)", scene_table().markdown(false));
  md += section("`scene.vpl` (scenes with indirect light)", vpl_table().markdown());
  md += section("`scene` of `\"type\": \"atrium\"`", atrium_table().markdown(false));
  md += section("`scene` of `\"type\": \"patterns\"`", patterns_table().markdown());
  md += section("`scene` of `\"type\": \"cornell\"`", cornell_table().markdown(false));
  md += section("`scene` of `\"type\": \"file\"`", file_scene_table().markdown(false));
  md += section("`cache` (the reference cache)", cache_block_table().markdown(false));
  md += section("`run` (the memory budget)", run_block_table().markdown(false));
  md += section("`budget` (frame-time budget decisions)", budget_block_table().markdown(false));
  md += section("`sweep` (docs/sweeps.md)", sweep_table().markdown(false));
  md += section("`sweep.iso_budget`", iso_budget_table().markdown());
  md += section("`sweep.search`", search_table().markdown(false));
  md += section("`metrics` (docs/metrics.md)", metrics_config_table().markdown());
  md += section("`latency` (docs/latency.md)", latency_table().markdown(false));
  md += section("`latency.saccade`", latency_saccade_table().markdown(false));
  md += section("`latency.main_sequence`", latency_main_sequence_table().markdown(false));
  md += section("GPU profile `spec` (`models/gpus/*.json`, docs/cost_model.md)",
                gpu_spec_table().markdown());
  md += section("Workload (`models/workloads/*.json`, the top-level `workload` key)",
                workload_table().markdown());
  md += section("Workload `pipeline`", pipeline_table().markdown());
  md += section("`methods[i]` (read by the run engine; each method's keys: \"Methods\" below)",
                method_entry_table().markdown(false));
  return md;
}

}  // namespace fovsim
