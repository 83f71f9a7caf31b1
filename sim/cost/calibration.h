// Calibration: the seeds' per-pass tables (models/calibration/*.json) are
// fitted by non-negative least squares on relative error. Unknowns: per (pass, term) a work
// amount per counter unit (theta, shared by all GPUs: a GPU's coefficient is theta divided by
// its spec-sheet rate of the term's resource, models/calibration/gpu_specs.json), a fixed
// overhead per pass, and one shading cost per workload (shading_flops, or vpl_flops for FLC).
#pragma once
#include <map>
#include <set>
#include <string>
#include <vector>

#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/workload.h"

namespace fovsim {

struct CalEntry {
  std::string table, id, row, config, workload, gpu, method;
  std::vector<std::string> passes;  // empty: every pass of the frame
  std::vector<std::string> except;  // with every pass: these left out (key `except`)
  double published_ms = 0;
  bool fit = true;        // false: a check row (totals), compared but not fitted
  bool baseline = false;  // a non-foveated config (full-resolution method)
  Json params = Json::object();
  Json workload_overrides = Json::object();
  Display display;
};

struct CalTable {
  std::string id, source, gpu, file;
  Json json;
  std::vector<CalEntry> entries;
};

struct GpuSpecEntry {
  std::string description;
  GpuSpec spec;
  // A GPU no calibration table used: its interval's log-widths are multiplied by this
  // (key `extrapolation_widen`, >= 1), and `architecture` states what the transfer assumes.
  double widen = 1.0;
  std::string architecture;
};

struct CalData {
  std::string models_dir;
  std::vector<CalTable> tables;
  std::map<std::string, GpuSpecEntry> specs;
  std::map<std::string, Workload> workloads;
};

CalData load_calibration(const std::string& models_dir);

struct FitOptions {
  std::set<std::string> tables;  // tables used for the fit (empty: all)
  double ridge = 1e-4;           // on standardised term columns
  double ridge_overhead = 3e-3;  // on standardised overheads: per-unit terms explain first
  CostModelKind model = CostModelKind::Roofline;  // how a pass combines its resources
};

struct CostFit {
  std::map<std::string, double>
      theta;  // "pass.term" (work units per counter unit), "pass.overhead_ms"
  std::map<std::string, Workload> workloads;  // with fitted shading costs
  std::set<std::string> fitted_workloads;
  std::set<std::string> seen_passes;  // passes that had data
  int rows = 0;
  CostModelKind model = CostModelKind::Linear;
  int iterations = 0;  // roofline: active-set refits until the bottlenecks stop changing
  // Passes no fitted row measured (a paper's own passes when that paper is left out) are
  // costed from their nominal work (nominal_work) at the pooled efficiency of their resource:
  // efficiency[r] = geometric mean of nominal / theta over the fitted terms of r that have a
  // nominal work; prior_overhead_ms = median fitted overhead of the single-resource passes.
  std::map<Resource, double> efficiency;
  double prior_overhead_ms = 0;
  bool unseen(const std::string& pass) const {
    return !seen_passes.empty() && !seen_passes.count(pass);
  }
};

// Work per counter unit of a (pass, term) at 100% efficiency, derived from the algorithm the
// papers describe (docs/cost_model.md "Absolute times across papers"): bytes per pixel or tap
// (memory), FP32 operations per unit (shading). 0: none stated. `like`: instead, the fitted
// theta of that "pass.term" times the returned factor (e.g. an RSM is a shadow map with three
// render targets). `why` receives the derivation.
double nominal_work(const std::string& pass, const std::string& term, std::string* like = nullptr,
                    std::string* why = nullptr);
// Theta of a term of a pass the fit never measured (CostFit::unseen): nominal work at the
// pooled efficiency, or its `like` term's fitted theta times the factor; floor when neither.
double prior_theta(const CostFit& fit, const std::string& pass, const std::string& term);

// Roofline floor of theta (work per counter unit at 100% efficiency): 1 for terms counted in
// their resource's own unit (triangles, fragments, texels, bytes), 0 for the others.
double theta_floor(const std::string& pass, const std::string& term);

CostFit fit_cost_model(const CalData& data, const FitOptions& opt);
// The unit of a fitted parameter (a key of CostFit::theta), for the printed tables.
std::string theta_unit(const std::string& key);
// The workload's fitted parameter: "vpl_flops" for FLC workloads, else "shading_flops".
std::string fitted_param(const Workload& w);
// Fits only the shading cost of `workload` from `rows`, other parameters fixed.
void refit_workload(CostFit& fit, const CalData& data, const std::string& workload,
                    const std::vector<const CalEntry*>& rows);

GpuProfile profile_from_fit(const CostFit& fit, const std::string& gpu, const CalData& data);
// Inputs for an entry (analytic counters); `display`/`params` override the entry's.
Workload entry_workload(const CostFit& fit, const CalData& data, const CalEntry& e);
double predict_entry(const CostFit& fit, const CalData& data, const CalEntry& e);
// Sum of the entry's passes (all when e.passes is empty) for a given profile/workload.
double entry_ms(const GpuProfile& g, const Workload& w, const CalEntry& e, FrameCost* fc = nullptr);

}  // namespace fovsim
