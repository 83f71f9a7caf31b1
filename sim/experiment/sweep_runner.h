// Executing sweeps (docs/architecture.md "Sweeps, search and fidelity", docs/sweeps.md): cells run
// over shared references (one frame loop per reference group), each cell's results in
// <out>/runs/<index>-<hash>/, completed cells marked by cell.json (written last, atomically) so a
// rerun resumes and skips them; a cell whose config changed has a new hash and is recomputed, never
// mixed with old results. Shards (--shard i/N or SLURM_ARRAY_TASK_ID/COUNT) take contiguous index
// ranges; merge collects cells (also from other folders) into summary.csv, pareto.csv,
// iso_budget.csv.
#pragma once
#include <tbb/global_control.h>

#include <memory>
#include <string>
#include <vector>

#include "sim/experiment/config.h"
#include "sim/experiment/run_options.h"
#include "sim/experiment/sweep_spec.h"
#include "sim/experiment/table.h"

namespace fovsim {

struct SweepOptions : RunControl {  // models_dir, threads, watchdog_s, targets, use_cache
  std::string out_dir;              // empty -> results/<name>
  int shard = 0, shards = 1;        // run only cells [shard_range(n, shard, shards))
  int batch = 0;  // max cells per reference pass; 0 = every pending cell of a group
  // The memory budget of a group's cells run together, GB (EngineOptions::memory_budget_gb:
  // `--memory-budget`; 0 = run.memory_gb, else 75% of MemAvailable); within each batch.
  double memory_budget_gb = 0;
  std::string command_line;  // recorded in manifests
  // (RunControl::targets: every cell stops on its own once its intervals hold; its manifest and
  // cell.json record frames used and achieved half-widths. use_cache: shards on a shared file
  // system reuse each other's references.)
};

struct SweepReport {
  std::string out_dir;
  int cells_total = 0;  // in the whole sweep
  int cells_in_shard = 0;
  int cells_done_before = 0;  // found complete (resumed), not recomputed
  int cells_run = 0;
  int stale_dirs = 0;           // runs/ folders of cells that no longer exist in this config
  int cells_other_build = 0;    // complete cells another build computed: computed again
  int groups = 0;               // distinct reference keys among cells run
  int reference_passes = 0;     // frame loops (groups x batches x memory-budget passes)
  uint64_t peak_rss_bytes = 0;  // the process's peak resident memory (ru_maxrss) at the end
  int reference_frames = 0;     // references rendered (or read from the reference cache)
  int reference_frames_from_cache = 0;
  // Wall times of this call (wall_ms) and its parts: ref_ms, cell_ms and setup_ms are sums of
  // per-group / per-cell wall times, which overlap when cells run in parallel.
  double wall_ms = 0, ref_ms = 0, cell_ms = 0, setup_ms = 0;
  double cpu_ms = 0;      // CPU time (user + system) of the process during this call, all threads
  bool complete = false;  // every cell of the sweep is complete in out_dir (summary written)
  // The reference cache's growth, when this call added more than cache.note_mb to it
  // (cache_growth_note, engine.h); "" otherwise.
  std::string cache_note;
};

// Contiguous index range [first, last) of shard `i` of `n` over `cells` cells.
std::pair<int, int> shard_range(int cells, int i, int n);
// SLURM_ARRAY_TASK_ID (minus SLURM_ARRAY_TASK_MIN when set) / SLURM_ARRAY_TASK_COUNT.
// Returns false when not inside an array job.
bool shard_from_env(int& index, int& count);
// Parses "i/N" (0 <= i < N). Throws fovsim::Error.
void parse_shard(const std::string& s, int& index, int& count);

std::string sweep_out_dir(const SweepPlan& plan, const std::string& out_dir);

SweepReport run_sweep(const SweepPlan& plan, const LoadedConfig& cfg, const SweepOptions& opt);

struct MergeReport {
  int cells = 0, found = 0, copied = 0;
  std::vector<int> missing;
  ResultTable summary;
};

// Collects every cell of the sweep described by <out_dir>/sweep.json from out_dir and the
// `sources` folders (complete cells found only in a source are copied into out_dir). Writes
// summary.csv (one row per cell x method x GPU), pareto.csv, iso_budget.csv and
// sweep_summary.json when no cell is missing (or allow_partial). Throws listing missing cells.
MergeReport merge_sweep(const std::string& out_dir, const std::vector<std::string>& sources,
                        bool allow_partial);

// The plan recorded in <dir>/sweep.json (re-expanded; its hash is checked).
SweepPlan load_sweep_plan(const std::string& dir);

// True when <cell_dir>/cell.json exists and records `hash`.
bool cell_complete(const std::string& cell_dir, const std::string& hash);

// Rows of a complete cell (typed: numbers stay numbers, text stays text).
ResultTable read_cell_summary(const std::string& cell_dir);

}  // namespace fovsim
