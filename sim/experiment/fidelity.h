// `fovsim fidelity CONFIG` (docs/architecture.md "Sweeps, search and fidelity", docs/fidelity.md):
// the user's config run at a ladder of cheaper settings (rungs) -- the analytic prediction (no
// rendering), lower `render.scale`, a frame stride over the same span, fewer reference samples per
// pixel when `render.spp` exists -- each compared with the top rung, the truth: wall time, and the
// error of every headline output per method with a 95% interval, and whether the ranking of the
// methods is preserved.
#pragma once
#include <string>
#include <vector>

#include "sim/core/params.h"
#include "sim/experiment/config.h"
#include "sim/experiment/config_cost.h"
#include "sim/experiment/run_options.h"
#include "sim/experiment/table.h"

namespace fovsim {

// One rung: a named set of overrides applied on top of the top rung's (so a stride rung runs
// at the top rung's scale), or the analytic prediction.
struct FidelityRung {
  std::string name;                    // the token as given, e.g. "scale=0.125", "analytic"
  bool analytic = false;               // `predict`'s counters and cost, no rendering
  bool top = false;                    // the truth every other rung is compared with
  int stride = 1;                      // "stride=N": every N-th frame over the same span
  std::vector<std::string> overrides;  // key.path=value (stride expanded at run time)
  std::string skipped;                 // non-empty: not run, and why (e.g. render.spp unknown)
};

// Default ladder (docs/fidelity.md): cheapest first; the top rung last.
inline constexpr const char* kDefaultRungs =
    "analytic;scale=0.125;scale=0.25;stride=2;stride=4;stride=8;spp=1;spp=4";
// Default truth: a quarter of the pixels of the real display (scale 1 costs 4x more again and
// would take tens of minutes for the quickstart on 2 cores; see docs/fidelity.md).
inline constexpr const char* kDefaultTop = "scale=0.5";

// Parses the ladder. `rungs`: rungs separated by ';', each either "analytic" or overrides
// separated by ','; an override is "scale=X" (render.scale), "stride=N" (frames.stride x N and
// frames.count / N: the same span of the trace), "spp=N" (render.spp) or any key.path=value.
// `top` has the same syntax (one rung, not "analytic"). Errors name the flag ("--rungs TOKEN:
// ..."). spp rungs are kept with `skipped` set when this build's render settings have no
// render.spp key.
std::vector<FidelityRung> parse_rungs(const std::string& rungs, const std::string& top);

// True when this build's render settings accept `render.spp`.
bool render_spp_known();

// models_dir, threads, watchdog_s, use_cache (RunControl; targets unused: every rung runs its
// frames). The reference cache (sim/experiment/reference_cache.h) serves every rendered rung:
// a ladder run twice, or a rung that repeats an earlier run's settings, renders no reference
// again.
struct FidelityOptions : RunControl {
  std::string out_dir;  // empty -> results/<name>_fidelity
  std::string rungs = kDefaultRungs;
  std::string top = kDefaultTop;
  std::string command_line;
  bool progress = true;  // one line per rung on stdout
};

struct FidelityResult {
  std::string out_dir;
  ResultTable table;               // fidelity.csv: one row per rung x config x output
  Json json;                       // fidelity.json
  std::string markdown;            // the ladder table (one row per rung)
  std::vector<std::string> notes;  // skipped rungs, rungs meeting the 0.2 dB / 2% / 1/4 test
};

// Runs every rung (rendered rungs through run_experiment into <out>/rungs/<index>-<name>/,
// without images) and writes <out>/fidelity.csv, fidelity.json (resolved config, code version),
// fidelity.md. A config with a "sweep" block runs the whole sweep at every rung (run_sweep:
// shared references); its rows are per cell, config_id "<cell index>/<config_id>", methods
// ranked within a cell, and err_ci95_paired / resolved swaps are not computed (nan / 0).
FidelityResult run_fidelity(const LoadedConfig& cfg, const FidelityOptions& opt);

// analytic_summary, the analytic rung: sim/experiment/config_cost.h.

// Error of each output of `rung` (a summary table) against `top` (its summary), per config_id
// present in both: rows {rung, config_id, method, output, top, value, err (rung - top), err_rel
// (err / |top|), err_ci95 (sqrt(h_rung^2 + h_top^2) from the `<output>_ci95` columns; nan where
// either is undefined), err_ci95_paired (batch means over the per-frame differences when
// both frames tables are given and hold the same frames, else nan)}. `outputs` empty: the
// headline outputs present in `top`.
ResultTable compare_to_truth(const std::string& rung, const ResultTable& rung_summary,
                             const ResultTable& top_summary,
                             const std::vector<std::string>& outputs,
                             const ResultTable* rung_frames = nullptr,
                             const ResultTable* top_frames = nullptr);

// The headline outputs of the ladder: est_ms_total, est_ms_total_p95, shaded_fraction, psnr,
// fpsnr, ssim, flip.
const std::vector<std::string>& fidelity_outputs();

// Config ids ordered by `output` (descending mean; ties by id), per GPU, among configs with a
// finite value. Two summaries rank alike when every GPU's order is the same.
bool same_ranking(const ResultTable& a, const ResultTable& b, const std::string& output);

// Pairs (a above b) ranked by the truth `top` whose paired interval over the truth's frames
// (`top_frames`) excludes zero, that `rung` ranks the other way round (among configs finite in
// both).
int resolved_swaps(const ResultTable& rung, const ResultTable& top, const ResultTable& top_frames,
                   const std::string& output);

}  // namespace fovsim
