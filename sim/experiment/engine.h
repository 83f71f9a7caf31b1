// The frame engine behind `fovsim run` and `fovsim sweep` (docs/architecture.md "Data flow of one
// frame", "Sweeps, search and fidelity"). A group of cells (run configs) that agree on everything a
// reference depends on — scene, display, render settings, trace, frame range — is replayed in one
// frame loop: each frame's G-buffer and reference are rendered once, then every cell's methods run
// on it in parallel (TBB), each cell writing its own results folder. Frames stream; no whole-trace
// image storage.
#pragma once
#include <tbb/global_control.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim/core/params.h"
#include "sim/core/watchdog.h"
#include "sim/experiment/intervals.h"
#include "sim/experiment/table.h"

namespace fovsim {

// Keys of a run config that do not influence the reference images (per-cell keys).
const std::vector<std::string>& per_cell_keys();
// Hash of everything a reference depends on: cells with equal keys share references.
std::string reference_key(const Json& run_doc);

struct CellJob {
  Json doc;                  // the run config
  std::string file;          // config file (error locations)
  std::string base_dir;      // for relative paths in the config
  std::string out_dir;       // results folder of this cell
  std::string command_line;  // recorded in its manifest
  Json extra_manifest;       // merged into manifest.json (e.g. sweep cell index, hash)
  std::vector<std::pair<std::string, std::string>> origins;    // command-line overrides (config.h)
  std::vector<std::pair<std::string, std::string>> inherited;  // values from "base" files
};

struct EngineOptions {
  std::string models_dir;     // empty -> default_models_dir()
  bool print_summary = true;  // default of outputs.print_summary
  int threads = 0;            // recorded in manifests (the caller sets TBB's limit)
  WatchdogLimits watchdog;    // a frame far slower than its neighbours is reported (watchdog.h)
  std::vector<IntervalTarget> targets;  // --target: sampled order; each cell stops when its hold
  // The reference cache (reference_cache.h) when the config's cache.enabled is true too.
  // Off by default: library callers and tests opt in; `fovsim run`/`sweep` do unless
  // --no-cache or FOVSIM_NO_CACHE.
  bool use_cache = false;
  // The memory budget of a group's cells, GB (10^9 bytes; docs/architecture.md "Memory"):
  // as many cells as the estimate fits run side by side over one pass of the frames, the rest
  // in later passes (the same numbers). > 0: `--memory-budget`, over the config's
  // run.memory_gb; 0: run.memory_gb, else 75% of the machine's MemAvailable at the start.
  double memory_budget_gb = 0;
};

// TBB's thread limit at `threads` while the result lives; none (nullptr) for threads <= 0
// (`fovsim run`, `sweep` and `search` -j).
std::unique_ptr<tbb::global_control> thread_limit(int threads);

struct CellResult {
  std::string out_dir;
  std::string name;
  ResultTable frames, summary;
  double budget_ms = 0;
  double refresh_hz = 0;
  bool print_summary = false;
  std::vector<std::string> flags;
  std::vector<std::string>
      warnings;               // valid but suspicious values (cell_manifest.h config_warnings)
  std::string fidelity_note;  // manifest "fidelity" note: the known bias of this render.scale
  Json fidelity;              // the manifest's "fidelity" record (its "jod": JOD vs native)
  double cell_ms = 0;  // wall time spent in this cell's own work (methods, metrics, cost, images)
  Json target;         // with targets: the manifest's "target" record (else null)
  // Notes for stderr (the CLI prints them): missing or short-run intervals (interval_notes,
  // runner.h), start-up frames left out of the means.
  std::vector<std::string> notes;
};

struct GroupStats {
  int frames = 0;       // references rendered (= frames of the group)
  double ref_ms = 0;    // wall time of reference rendering
  double wall_ms = 0;   // whole group, including setup
  double setup_ms = 0;  // scene build, trace load, BVH
  uint64_t rays = 0;
  int frames_from_cache = 0;    // references read from the reference cache (of `frames`)
  int passes = 0;               // frame loops over the group's cells (the memory budget)
  uint64_t peak_rss_bytes = 0;  // the process's peak resident memory at the group's end
  // The reference cache (references and method memo together), when used: its folder, its
  // cap (cache.max_gb, resolved), cache.note_mb, and the bytes this group wrote to it.
  std::string cache_dir;
  double cache_cap_gb = 0, cache_note_mb = 0;
  uint64_t cache_bytes_written = 0;
};

// The line for stderr after a run whose groups (`stats`, one per run_cells call) wrote more
// than cache.note_mb to the reference cache (cache_growth_note, sim/core/disk_cache.h); "" when
// they wrote less or used no cache.
std::string cache_growth_note(const std::vector<GroupStats>& stats);

// Runs `jobs`, which must share one reference_key (checked). Every cell's config is fully
// validated before the first frame. Each cell's folder receives manifest.json (status
// "running", then "complete"), frames.csv, summary.csv, summary.json, images.
std::vector<CellResult> run_cells(const std::vector<CellJob>& jobs, const EngineOptions& opt,
                                  GroupStats* stats = nullptr);

}  // namespace fovsim
