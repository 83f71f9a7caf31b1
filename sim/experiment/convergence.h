// Reference convergence study (docs/architecture.md "Rendering and the shared reference",
// docs/metrics.md "Reference convergence"): every method of a config measured against references of
// increasing render.spp. The default spp is the lowest level from which every method's means move
// by less than a tolerance to the next level (PSNR/FPSNR 0.1 dB, FLIP 0.005) and the ranking of the
// methods no longer changes.
#pragma once
#include <string>
#include <vector>

#include "sim/experiment/run_options.h"

namespace fovsim {

// models_dir, threads, watchdog_s, use_cache: the run options of every level (RunControl;
// targets unused: every level runs all its frames).
struct ConvergenceOptions : RunControl {
  std::vector<int> spps{1, 4, 16, 64};  // increasing perfect squares
  std::string out_dir;                  // per-level runs in <out>/spp_<n>/, tables at the top
  double tol_db = 0.1;                  // PSNR, FPSNR
  double tol_flip = 0.005;              // FLIP mean
  double tol_jod = 0.05;                // FovVideoVDP JOD
};

// The metrics of the study: the metric registry's headline metrics (sim/metrics/registry.h) in
// its order (psnr, fpsnr, ssim, flip, fvvdp_jod): name, higher is better, tolerance kind
// (0: dB, 1: FLIP, 2: JOD, -1: none, ranking only). A metric that is nan at two levels (not
// computed by the run) does not take part in the rule.
struct ConvergenceMetric {
  std::string name;
  bool higher_better;
  int tol_kind;
};
const std::vector<ConvergenceMetric>& convergence_metrics();

struct ConvergenceResult {
  std::vector<int> spps;
  std::vector<std::string> labels;  // method labels, config order
  // value[level][label][metric] (per-config means from summary.csv; nan when absent)
  std::vector<std::vector<std::vector<double>>> value;
  std::vector<double> ref_seconds;  // wall time of each level's run
  std::vector<bool> level_ok;       // level i meets the criterion (last level: false)
  int chosen_spp = 0;               // lowest level meeting it; 0 = none
  std::string markdown() const;     // the table for docs/metrics.md
  std::string csv() const;
};

// Decides level_ok and chosen_spp from `value` (no rendering; tested on its own).
void evaluate_convergence(ConvergenceResult& r, const ConvergenceOptions& opt);

// Runs CONFIG (with overrides) once per spp level (render.spp=<n>) and evaluates.
// Writes <out>/convergence.csv and <out>/convergence.md.
ConvergenceResult run_convergence(const std::string& config,
                                  const std::vector<std::string>& overrides,
                                  const ConvergenceOptions& opt);

}  // namespace fovsim
