// The run config's own blocks as declared tables (sim/core/param_table.h): the top-level keys,
// `render`, `render.tonemap`, `frames`, `outputs` and `latency`. The engine reads each block
// with its table; configs/README.md's tables are generated from them (`fovsim methods
// --markdown --config-keys`, scripts/gen_method_docs.sh) and a test compares.
//
// Adding a run-config key: a member in the block's struct below and one row in its table in
// run_config.cpp; then use the member where the engine needs it. Blocks owned by other layers
// keep their tables there (metrics: metrics_config_table(), render settings:
// render_settings_table(), GPU spec: gpu_spec_table(), methods: their files).
#pragma once
#include <string>
#include <vector>

#include "sim/core/param_table.h"
#include "sim/cost/budget.h"

namespace fovsim {

// Top-level keys read once per group of cells (what the references depend on).
struct RunSharedKeys {
  int seed = 1;
  std::string trace_placement = "scene";
};
const ParamTable<RunSharedKeys>& run_shared_table();

// Top-level keys read per cell.
struct RunCellKeys {
  std::string name;  // default: the config file's stem (set before reading)
  std::string workload = "generic";
};
const ParamTable<RunCellKeys>& run_cell_table();

// `render` (the run's part; the renderer's own keys: render_settings_table()).
struct RenderBlock {
  double scale = 1.0;
  double max_pixels = 5e7;
};
const ParamTable<RenderBlock>& render_block_table();

// `render.tonemap`.
struct ToneMapBlock {
  double exposure = 1.0;  // default: the scene's (set before reading)
  std::string curve = "aces";
};
const ParamTable<ToneMapBlock>& tonemap_block_table();

// `frames`.
struct FramesBlock {
  int start = 0, stride = 1, count = 0, warmup = 0;
  bool include_startup = false;  // keep methods' warm-up and metrics' settle frames in means
  std::string on_short_trace = "fail";
};
const ParamTable<FramesBlock>& frames_block_table();

// `outputs`.
struct OutputsBlock {
  std::vector<double> image_frames;
  bool png = true, exr = false, debug_images = false, error_images = true;
  bool print_summary = true;  // default: the command's (set before reading)
};
const ParamTable<OutputsBlock>& outputs_block_table();

// `run`: how a group of cells runs (never what it computes).
struct RunBlock {
  double memory_gb = 0;  // 0: `--memory-budget`, else 75% of MemAvailable
};
const ParamTable<RunBlock>& run_block_table();

// `budget`: the level of the run's budget decisions (sim/cost/budget.h decide_budget).
struct BudgetBlock {
  double p_fit = kDefaultFitLevel;
};
const ParamTable<BudgetBlock>& budget_block_table();

// `cache` (the reference cache, reference_cache.h).
struct ReferenceCacheSettings;
const ParamTable<ReferenceCacheSettings>& cache_block_table();

// `methods[i]`: the entry's own keys, documented rows (the engine reads them; a method's
// parameters are its own table).
struct MethodEntryKeys {};
const ParamTable<MethodEntryKeys>& method_entry_table();

// Every run-config table as Markdown sections, for configs/README.md (between the markers
// kConfigDocsBegin / kConfigDocsEnd).
std::string config_keys_markdown();
inline constexpr const char* kConfigDocsBegin =
    "<!-- BEGIN GENERATED KEYS by `fovsim methods --markdown --config-keys` "
    "(scripts/gen_method_docs.sh); "
    "do not edit -->";
inline constexpr const char* kConfigDocsEnd = "<!-- END GENERATED KEYS -->";

}  // namespace fovsim
