#include "sim/experiment/engine.h"

#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/hash.h"
#include "sim/core/memory_info.h"
#include "sim/core/progress.h"
#include "sim/core/watchdog.h"
#include "sim/experiment/cell.h"
#include "sim/experiment/cell_manifest.h"
#include "sim/experiment/cell_memo.h"
#include "sim/experiment/cell_outputs.h"
#include "sim/experiment/config.h"
#include "sim/experiment/frame_order.h"
#include "sim/experiment/intervals.h"
#include "sim/experiment/memory_plan.h"
#include "sim/experiment/reference_cache.h"
#include "sim/experiment/reference_side.h"
#include "sim/experiment/shared_config.h"
#include "sim/foveation/frame.h"
#include "sim/foveation/simd_kernels.h"
#include "sim/metrics/frame_metric.h"
#include "sim/metrics/registry.h"
#include "sim/render/embree_device.h"
#include "sim/render/renderer.h"

namespace fovsim {

std::unique_ptr<tbb::global_control> thread_limit(int threads) {
  if (threads <= 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               size_t(threads));
}

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const std::vector<std::string>& per_cell_keys() {
  // Keys a cell reads for itself (Cell::parse); everything else is shared by the group and
  // enters reference_key. `workload` only changes the cost model's charges, never the images.
  static const std::vector<std::string> k = {"name",     "methods", "metrics",     "gpus",
                                             "outputs",  "comment", "description", "latency",
                                             "workload", "budget"};
  return k;
}

std::string reference_key(const Json& run_doc) {
  Json j = run_doc;
  if (j.is_object())
    for (auto& k : per_cell_keys()) j.erase(k);
  j.erase("sweep");
  return short_hash(j.dump());
}

namespace {
std::vector<CellResult> run_cells_impl(const std::vector<CellJob>& jobs, const EngineOptions& opt,
                                       GroupStats* stats);
}

std::string cache_growth_note(const std::vector<GroupStats>& stats) {
  std::string dir;
  double cap = 0, note_mb = -1;
  uint64_t bytes = 0;
  for (auto& g : stats) {
    if (g.cache_dir.empty()) continue;
    if (dir.empty()) dir = g.cache_dir;
    if (g.cache_dir != dir) continue;  // one folder per note (a sweep's groups share one)
    cap = g.cache_cap_gb;
    note_mb = note_mb < 0 ? g.cache_note_mb : std::min(note_mb, g.cache_note_mb);
    bytes += g.cache_bytes_written;
  }
  if (dir.empty()) return "";
  return cache_growth_note(dir, bytes, cap, uint64_t(std::max(note_mb, 0.0) * 1e6));
}

std::vector<CellResult> run_cells(const std::vector<CellJob>& jobs, const EngineOptions& opt,
                                  GroupStats* stats) {
  // Out of memory outside the scene and the trace (which say so themselves): the frames, whose
  // buffers scale with the simulated resolution and the number of cells run side by side.
  const std::string where = jobs.empty() ? std::string() : jobs.front().file + ": render.scale";
  const std::string what = "rendering and measuring " + std::to_string(jobs.size()) +
                           (jobs.size() == 1 ? " configuration's frames"
                                             : " cells side by side over one shared reference");
  return with_memory_context(where, what,
                             jobs.size() > 1
                                 ? "run fewer cells at once with `fovsim sweep --memory-budget "
                                   "GB` (or --batch N), or lower render.scale"
                                 : "lower render.scale, or run fewer methods at once",
                             [&] { return run_cells_impl(jobs, opt, stats); });
}

namespace {

// Configuration: the first cell parses the shared keys (scene, trace, ...) into `sh`; every
// cell parses its own keys; Params::finish fails on any key nobody read. All cells are
// validated before any frame is computed.
std::vector<std::unique_ptr<Cell>> parse_group(const std::vector<CellJob>& jobs,
                                               const EngineOptions& opt, Shared& sh) {
  std::vector<std::unique_ptr<Cell>> cells;
  for (size_t ci = 0; ci < jobs.size(); ++ci) {
    const CellJob& job = jobs[ci];
    // Later cells read only their own keys (the shared ones were validated by the first).
    Json own = job.doc;
    if (ci > 0 && own.is_object())
      for (auto it = job.doc.begin(); it != job.doc.end(); ++it)
        if (std::find(per_cell_keys().begin(), per_cell_keys().end(), it.key()) ==
            per_cell_keys().end())
          own.erase(it.key());
    Params root(own, job.file);
    root.set_origins(job.origins);
    root.set_inherited(job.inherited);
    root.ignore("comment");
    root.ignore("description");
    auto cell = std::make_unique<Cell>();
    cell->job = &job;
    if (ci == 0) {
      // Same reading order as a single run, so the first error reported is the same.
      cell->name = root.string("name", fs::path(job.file).stem().string());
      sh.parse(root, job.file, job.base_dir);
      cell->parse(root, sh.models, opt.print_summary);
    } else {
      cell->parse(root, sh.models, opt.print_summary);
    }
    root.finish();  // any key nobody read is a typo: fail before computing anything
    cell->warnings = config_warnings(job.doc, root, sh, cell->images.io.frames, ci == 0);
    // FPSNR clips at the real display's Nyquist frequency (docs/metrics.md).
    cell->metric.cfg.ppd_scale = double(sh.display.width) / double(sh.sim_display.width);
    cell->gaze = std::make_unique<GazeSource>(cell->latency.config, sh.raw_trace, sh.trace,
                                              sh.tracking, sh.display);
    Json resolved = ci == 0 ? root.resolved() : sh.resolved;
    if (ci == 0) {
      sh.resolved = resolved;
    } else {
      for (auto& k : per_cell_keys()) {
        resolved.erase(k);
        if (root.resolved().contains(k)) resolved[k] = root.resolved()[k];
      }
    }
    cell->manifest = cell_manifest(job, sh, resolved, opt);
    if (!cell->warnings.empty()) cell->manifest["warnings"] = cell->warnings;
    cells.push_back(std::move(cell));
  }
  return cells;
}

// A cell in progress is marked so it never looks complete. Each folder is locked for the run
// (a second writer stops with an error naming the lock) and emptied of an earlier run's
// outputs, so a finished folder holds only this run's files (clear_run_outputs).
std::vector<std::unique_ptr<DirLock>> start_output_folders(
    const std::vector<std::unique_ptr<Cell>>& cells) {
  std::vector<std::unique_ptr<DirLock>> locks;
  for (auto& c : cells) {
    const std::string& out = c->job->out_dir;
    make_dirs(out);
    locks.push_back(std::make_unique<DirLock>(out, ".lock", "another fovsim run"));
    const bool earlier_run = path_kind(out + "/manifest.json") != PathKind::missing;
    // "running" replaces an old "complete" manifest before the old results go, so a kill in
    // between never leaves a manifest that claims files that are gone.
    write_file_atomic(out + "/manifest.json", c->manifest.dump(2) + "\n");
    clear_run_outputs(out, earlier_run);
  }
  return locks;
}

// The reference cache when both the caller and the config's cache.enabled want it; a cache
// without a folder is a warning (`no_cache_dir`), not an error.
std::unique_ptr<ReferenceCache> open_reference_cache(const EngineOptions& opt, Shared& sh,
                                                     std::string& no_cache_dir) {
  if (!opt.use_cache || !sh.cache.enabled) return nullptr;
  sh.cache.resolve_cap();  // the folder, and cache.max_gb 0 -> from the free disk space
  if (sh.cache.dir.empty()) {
    no_cache_dir =
        "reference cache: no folder (cache.dir, FOVSIM_CACHE_DIR, XDG_CACHE_HOME and HOME are "
        "unset): not used";
    return nullptr;
  }
  return std::make_unique<ReferenceCache>(sh.cache, *sh.scene, sh.scene_config, sh.sim_display,
                                          sh.rs);
}

// The shared data of frame `fi` (prepare_frame), its reference from the cache when an earlier
// run computed it (then only G-buffer and VPLs are rendered).
void render_reference(Renderer& renderer, ReferenceCache* rcache, const Shared& sh, int fi,
                      uint32_t channels, const Camera* prev, FrameData& fd) {
  const TraceSample& s = sh.trace.samples[size_t(fi)];
  renderer.set_time(s.t);
  if (rcache) {
    const std::string key =
        rcache->key(fi, s, Camera::from_pose(sh.sim_display, s.head_pos, s.head_rot));
    FrameReference cached;
    if (rcache->load(key, sh.sim_display.width, sh.sim_display.height, cached)) {
      prepare_frame(renderer, sh.sim_display, s, fi, channels, prev, fd, &cached);
    } else {
      prepare_frame(renderer, sh.sim_display, s, fi, channels, prev, fd);
      rcache->store(key, fd);
    }
  } else {
    prepare_frame(renderer, sh.sim_display, s, fi, channels, prev, fd);
  }
}

// Whether any method of the group carries state from frame to frame (then --target keeps the
// trace order).
bool any_temporal(const std::vector<std::unique_ptr<Cell>>& cells, const Shared& sh) {
  bool temporal = false;
  for (auto& c : cells)
    for (auto& m : c->methods)
      temporal = temporal || m.impl->temporal() || m.impl->taa().enabled ||  // TAA's history
                 (sh.scene->wants_indirect && m.impl->lighting() && m.impl->lighting()->temporal());
  return temporal;
}

// The reference sides (RefSide) of a group's cells: one per distinct resolved `metrics` block
// and TAA of the foveation-loss reference (the method's: docs/metrics.md "Foveation loss"), in
// the order of each one's first method.
std::vector<std::unique_ptr<RefSide>> share_reference_sides(
    const std::vector<std::unique_ptr<Cell>>& cells) {
  std::vector<std::unique_ptr<RefSide>> sides;
  for (auto& c : cells) {
    std::vector<RefSide*> counted;
    for (auto& m : c->methods) {
      const TaaSettings taa = side_taa(*c, m);
      const std::string key = method_side_key(*c, m);
      RefSide* s = nullptr;
      for (auto& o : sides)
        if (o->key == key) s = o.get();
      if (!s) {
        sides.push_back(std::make_unique<RefSide>());
        s = sides.back().get();
        s->key = key;
        s->file = c->job->file;
        s->mcfg = c->metric.cfg;
        // temporal_error and any other metric against the reference only are left out.
        s->fl_mcfg = without_reference_only(c->metric.cfg);
        s->taa = taa;
      }
      if (std::find(counted.begin(), counted.end(), s) == counted.end()) {
        ++s->cells;
        counted.push_back(s);
      }
      m.side = s;
    }
    c->metric.side = c->methods.empty() ? nullptr : c->methods.front().side;
  }
  return sides;
}

// Sequence metrics' mode (docs/metrics.md): a video of consecutive frames, else still images;
// recorded in each cell's manifest under the metric's key.
void describe_sequence_metrics(const std::vector<std::unique_ptr<Cell>>& cells, const Shared& sh,
                               bool shuffled) {
  const bool video = sh.stride == 1 && !shuffled;
  for (auto& c : cells) {
    c->metric.side->video = video;
    SequenceSetup su;
    su.display = &sh.display;
    su.width = sh.sim_display.width;
    su.height = sh.sim_display.height;
    su.fps = video ? sh.display.refresh_hz : 0.0;
    su.config = &c->metric.cfg;
    for (auto& d : metric_registry()) {
      if (!d.sequence || !d.sequence->enabled(c->metric.cfg)) continue;
      Json j = d.sequence->describe(su);
      j["mode"] = video ? "video" : "image";
      j["fps"] = su.fps;
      j["why"] = video ? "consecutive frames at the display's refresh rate"
                 : sh.stride != 1
                     ? "frames.stride > 1: frames are not consecutive, each is a still image"
                     : "--target evaluates units in random order: each frame a still image";
      c->manifest[d.sequence->manifest_key] = j;
    }
  }
}

// What every pass of a group shares (run_cells_impl, run_pass).
struct GroupRun {
  const std::vector<CellJob>& jobs;
  const EngineOptions& opt;
  Shared& sh;
  ReferenceCache* rcache;
  const std::string& no_cache_dir;
  const PhaseTimes& setup_phases;
  bool temporal;  // any method of the group is temporal (the frame order of every pass)
  const MemoryPlan& plan;
  const MemoryEstimator& est;
  GroupStats* stats;
};

// The end of a pass: the cells' computed method entries go to the method memo, then each
// cell's outputs (cell_outputs.cpp; atomic, manifest "complete" last) with the pass's memory
// record.
void write_pass_outputs(const GroupRun& g, std::vector<std::unique_ptr<Cell>>& cells, size_t pass,
                        const std::vector<std::unique_ptr<RefSide>>& sides, const FrameOrder& order,
                        const Renderer& renderer, const PhaseTimes& group_phases, MethodMemo* memo,
                        std::vector<CellResult>& results) {
  const Shared& sh = g.sh;
  const EngineOptions& opt = g.opt;
  if (memo) {  // the cells completed: their computed method entries go to the memo
    for (auto& c : cells)
      for (auto& m : c->methods)
        if (m.memo.rec) memo->store(m.memo.key, *m.memo.rec);
    if (g.stats) g.stats->cache_bytes_written += memo->disk().stats().bytes_written;
  }

  // 6. Outputs (cell_outputs.cpp; atomic, manifest "complete" last).
  const MetricsConfig& m0 = cells.front()->metric.cfg;
  const std::string fl_reference = !m0.foveation_loss            ? "off"
                                   : sides.front()->fl_aliased() ? "the reference"
                                                                 : "full at 1 spp";
  const Json memory = g.plan.record(pass, sides.size(), g.est.side(m0, sides.front()->taa),
                                    g.est.sequence(m0).ref, fl_reference);
  const int threads = opt.threads > 0 ? opt.threads : int(tbb::info::default_concurrency());
  const GroupOutputs go{opt,      order,        g.rcache,          g.no_cache_dir,
                        renderer, group_phases, PhaseClock::now(), threads,
                        memo,     memory};
  for (auto& c : cells) results.push_back(write_cell_outputs(*c, sh, go));
}

// One pass of the frames over `cells` (docs/architecture.md "Data flow of one frame"): one
// reference per frame, the reference sides, each cell's process() in parallel, in FrameOrder; then
// write_cell_outputs.
void run_pass(const GroupRun& g, std::vector<std::unique_ptr<Cell>>& cells, size_t pass,
              std::vector<CellResult>& results) {
  const Shared& sh = g.sh;
  const EngineOptions& opt = g.opt;
  PhaseTimes group_phases = g.setup_phases;  // setup, reference, outputs (shared by the cells)
  uint32_t channels = kShadingChannels;
  for (auto& c : cells) channels |= c->channels;
  Renderer renderer(*sh.scene, sh.rs);
  // Slot 0: the frame's reference; slot 1 + i: cell i's methods (watchdog.h).
  Watchdog watchdog(cells.size() + 1, opt.watchdog);
  for (size_t i = 0; i < cells.size(); ++i) {
    cells[i]->watchdog = &watchdog;
    cells[i]->watchdog_slot = i + 1;
  }
  FrameData fd;
  Image ref_display;
  CellWorkspaces workspaces;  // lent per cell and frame (cell_metrics.h)
  std::optional<Camera> prev_cam;
  const std::string of_passes =
      g.plan.passes.size() > 1
          ? ", pass " + std::to_string(pass + 1) + "/" + std::to_string(g.plan.passes.size())
          : std::string();
  // Frames of the group, warm-up frames included (progress.h; inside a sweep's or a
  // ladder's progress this is its innermost level).
  Progress progress(
      (cells.size() > 1 ? "frames x " + std::to_string(cells.size()) + " cells" : "frames") +
          of_passes,
      size_t(sh.count + sh.warmup));
  // A group's cells come from a sweep or a search, whose progress counts cells: this pass
  // stands for its cells, after the cells of the group's earlier passes (progress.h spans).
  progress.spans(results.size(), cells.size());
  progress.phase("frames");
  double ref_total = 0;
  // One frame, in the steps of docs/architecture.md "Data flow of one frame".
  auto do_frame = [&](int k, bool record) {
    // 1. Trace sample fi; 2. the shared reference (from the cache, or rendered), tone-mapped.
    int fi = sh.start + k * sh.stride;
    auto t0 = Clock::now();
    PhaseClock rpc = PhaseClock::now();
    watchdog.begin(0, "frame " + std::to_string(fi) + ", reference rendering");
    render_reference(renderer, g.rcache, sh, fi, channels, prev_cam ? &*prev_cam : nullptr, fd);
    watchdog.end(0);
    check_finite_image(fd.reference, "frame " + std::to_string(fi) + ": reference");
    sh.tonemap.apply(fd.reference, ref_display);
    double ref_ms = elapsed_ms(t0);
    group_phases.lap("reference", rpc);
    ref_total += ref_ms;
    std::vector<Cell*> active;
    std::vector<RefSide*> active_sides;
    for (auto& c : cells)
      if (!c->target.stopped) {
        active.push_back(c.get());
        ++(record ? c->target.used : c->target.warmup);
        for (auto& m : c->methods)
          if (std::find(active_sides.begin(), active_sides.end(), m.side) == active_sides.end())
            active_sides.push_back(m.side);
      }
    // 3. The reference side of the frame, once per group of cells sharing it.
    for (RefSide* s : active_sides)
      s->frame(sh, renderer, fd, ref_display, fi, record, group_phases, workspaces);
    // 4. Per cell, in parallel: gaze, method, metrics, images, rows (Cell::process, cell.cpp).
    if (active.size() == 1) {
      active[0]->process(sh, renderer, fd, ref_display, fi, ref_ms, record, workspaces);
    } else {
      // Cells are independent (own methods, state; a workspace lent per frame); each row list
      // stays in order. Isolated: a thread waiting inside one cell's parallel loops does not
      // start another cell, so at most as many cells (and workspaces) are live as threads.
      tbb::parallel_for(tbb::blocked_range<size_t>(0, active.size(), 1),
                        [&](const tbb::blocked_range<size_t>& r) {
                          for (size_t i = r.begin(); i != r.end(); ++i)
                            tbb::this_task_arena::isolate([&] {
                              active[i]->process(sh, renderer, fd, ref_display, fi, ref_ms, record,
                                                 workspaces);
                            });
                        });
    }
    prev_cam = fd.camera;
    progress.step();
  };
  // 5. Evaluation order (frame_order.h): the trace order; under --target, seeded random units
  // (trace order with a temporal method of the group) until every cell's targets hold; each
  // cell stops on its own, so its frames do not depend on the other cells of its group or pass.
  const bool sampled = !opt.targets.empty();
  std::vector<std::unique_ptr<RefSide>> sides = share_reference_sides(cells);
  FrameOrder order(sh.count, sh.warmup, sampled, !g.temporal, sh.seed);
  describe_sequence_metrics(cells, sh, order.shuffled());
  std::unique_ptr<MethodMemo> memo = open_method_memo(sh, g.rcache, cells, sampled);
  FrameOrder::Steps steps;
  steps.frame = do_frame;
  steps.discontinuity = [&] {
    for (auto& s : sides) s->reset();
    for (auto& c : cells) c->reset_temporal();
    prev_cam.reset();
  };
  steps.unit_done = [&](int units_done) {
    bool all = true;
    for (auto& c : cells) {
      if (c->target.stopped) continue;
      c->target.met = targets_met(opt.targets, c->frames, nullptr);
      if (units_done >= kTargetMinUnits && c->target.met) c->target.stopped = true;
      all = all && c->target.stopped;
    }
    return all;
  };
  order.run(steps);
  progress.phase("outputs");
  write_pass_outputs(g, cells, pass, sides, order, renderer, group_phases, memo.get(), results);
  progress.done();
  if (g.stats) {
    g.stats->frames += order.recorded() + order.warmup();
    g.stats->ref_ms += ref_total;
    g.stats->rays += renderer.rays_traced();
    g.stats->passes += 1;
  }
}

// The stages of docs/architecture.md "Data flow of one frame": parse_group, output folders, the
// memory plan, then per pass the frame loop over its cells (run_pass) and their outputs; a pass's
// cells are freed before the next pass starts.
std::vector<CellResult> run_cells_impl(const std::vector<CellJob>& jobs, const EngineOptions& opt,
                                       GroupStats* stats) {
  auto g0 = Clock::now();
  PhaseTimes setup_phases;
  PhaseClock gpc = PhaseClock::now();
  std::vector<CellResult> results;
  if (jobs.empty()) return results;
  const std::string key = reference_key(jobs.front().doc);
  for (auto& j : jobs)
    FOVSIM_CHECK(reference_key(j.doc) == key,
                 "cells of one reference group differ in a reference key (" + j.file + ")");

  embree_device_config();  // FOVSIM_EMBREE_ISA / FOVSIM_SIMD: a bad value fails here, not mid-run
  simd_path();
  Shared sh;
  sh.models = opt.models_dir.empty() ? default_models_dir() : opt.models_dir;
  std::vector<std::unique_ptr<Cell>> cells = parse_group(jobs, opt, sh);
  const auto locks = start_output_folders(cells);
  std::string no_cache_dir;  // the cache is on but has no folder (a warning, not an error)
  std::unique_ptr<ReferenceCache> rcache = open_reference_cache(opt, sh, no_cache_dir);
  const double setup_ms = elapsed_ms(g0);
  setup_phases.lap("setup", gpc);

  const bool temporal = any_temporal(cells, sh);
  MemoryEstimator est{sh};
  est.threads = opt.threads > 0 ? opt.threads : int(tbb::info::default_concurrency());
  est.video = sh.stride == 1 &&
              !FrameOrder(sh.count, sh.warmup, !opt.targets.empty(), !temporal, sh.seed).shuffled();
  const MemoryPlan plan = plan_memory(opt, sh, cells, est);
  const GroupRun g{jobs,         opt,      sh,   rcache.get(), no_cache_dir,
                   setup_phases, temporal, plan, est,          stats};
  for (size_t p = 0; p < plan.passes.size(); ++p) {
    std::vector<std::unique_ptr<Cell>> pass;
    for (size_t i : plan.passes[p]) pass.push_back(std::move(cells[i]));
    run_pass(g, pass, p, results);
  }  // the pass's cells (their methods and streams) are freed here
  if (stats) {
    stats->setup_ms += setup_ms;
    stats->wall_ms += elapsed_ms(g0);
    if (rcache) {
      stats->frames_from_cache += int(rcache->manifest()["frames_from_cache"].get<int>());
      stats->cache_dir = rcache->disk().dir();
      stats->cache_cap_gb = rcache->max_gb();
      stats->cache_note_mb = sh.cache.note_mb;
      stats->cache_bytes_written += rcache->disk().stats().bytes_written;
    }
    stats->peak_rss_bytes = peak_rss_bytes();
  }
  return results;
}
}  // namespace

}  // namespace fovsim
