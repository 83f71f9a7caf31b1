// A GPU profile (docs/architecture.md "Cost model"): spec-sheet throughputs, per-pass linear
// coefficients (ms per counter unit, see docs/cost_model.md for every term) plus a fixed overhead
// per pass, and the calibration residuals the coefficients were fitted with. Files:
// models/gpus/NAME.json, written by `fovsim calibrate`.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "sim/core/param_info.h"
#include "sim/core/params.h"

namespace fovsim {

// Resource classes a term loads; what-if scaling (`fovsim budget`) divides every coefficient
// of a class by the throughput factor.
enum class Resource { Geometry, Raster, Shading, Memory, Fixed };
const char* resource_name(Resource r);
Resource resource_from_name(const std::string& s, const std::string& where);

// Spec-sheet peak rates (boost clock), the normalisation of the cross-GPU fit.
struct GpuSpec {
  double fp32_gflops = 0;  // shading
  double mem_gbps = 0;     // memory bandwidth, GB/s
  double fill_gpix = 0;    // ROP fill rate, Gpixel/s (raster)
  double tri_gtris = 0;    // primitive rate, Gtriangles/s (geometry)
  double boost_mhz = 0;
  double l2_mb = 0;  // last-level (L2) cache, MB; 0: unknown (no working-set effect)
  std::string source;
  // Peak rate of a class in units per millisecond (flop, byte, pixel, triangle).
  double rate_per_ms(Resource r) const;
};
// The declaration of a profile's `spec` keys (parsing, docs, the order profile files write).
const ParamTable<GpuSpec>& gpu_spec_table();

// How a pass combines its terms (docs/architecture.md "Cost model"). Linear: overhead + Σ
// coef·value. Roofline: overhead + max over resources of Σ_{terms of that resource} coef·value,
// i.e. the pass runs at the speed of its bottleneck resource (Williams, Waterman, Patterson,
// "Roofline: an insightful visual performance model for multicore architectures", CACM 2009).
enum class CostModelKind { Linear, Roofline };
const char* model_name(CostModelKind k);

// Multiplicative interval factors of one pass (or of every pass pooled).
struct IntervalFactors {
  double lo_factor = 1, hi_factor = 1;
  int n = 0;  // held-out rows the quantiles came from
};

// Prediction interval: multiplicative factors from the empirical quantiles of
// published / model over held-out rows (leave-one-seed/GPU/scene-out experiments of
// `fovsim validate-cost`). lo_factor <= 1 <= hi_factor. `passes` holds the factors of the
// passes with at least kMinPassIntervalRows held-out single-pass rows of their own, partially
// pooled: log factor = (n log q_pass + kPassIntervalPrior log q_pooled) / (n + kPassIntervalPrior);
// every other pass takes the pooled factors. A frame's total combines its passes' intervals
// (combine_pass_intervals).
struct PredictionInterval {
  double level = 0;                     // 0: none known
  double lo_factor = 1, hi_factor = 1;  // pooled over every held-out row
  int n = 0;
  std::map<std::string, IntervalFactors> passes;
  // Split-conformal factors of the frame total, from held-out frame totals (n 0: none; the
  // total then combines its passes' intervals). Used for every estimate's total interval.
  IntervalFactors total;
  // Held-out log(published / model) of the frame totals, sorted: the predictive distribution
  // behind budget's probability of fitting (fit_probability). Empty: none.
  std::vector<double> total_scores;
  // Extrapolation (profiles no calibration table used): log-widths are multiplied by this
  // (>= 1), documented per profile in `extrapolation` (docs/cost_model.md "Current GPUs").
  double widen = 1.0;
  std::string method;  // how the factors were made (profile documentation)
  IntervalFactors for_pass(const std::string& pass) const;
  IntervalFactors for_total() const;  // `total` when known, widened; else n = 0
};
// P(published total <= budget) for a model total `ms` under the held-out score distribution
// (conformal: (k + 1/2) / (n + 1) smoothing, k scores with ms * e^s <= budget; scores widened
// by `widen`). Without scores: the interval's factors as a log-uniform spread; without any
// interval 1 or 0 (the point estimate).
double fit_probability(const PredictionInterval& iv, double ms, double budget_ms);
// A 10%/90% quantile from fewer rows is noise: such passes take the pooled factors.
constexpr int kMinPassIntervalRows = 5;
// Weight of the pooled quantiles, in rows, when a pass's own quantiles are shrunk toward them.
constexpr double kPassIntervalPrior = 8;

// The total's interval from its passes' intervals [lo_p, hi_p] around ms_p: the
// half-widths below and above add in quadrature, i.e. pass errors are treated as independent
// (docs/cost_model.md "Prediction intervals" gives the measured coverage of this choice).
struct PassSpan {
  double ms = 0, lo_ms = 0, hi_ms = 0;
};
void combine_pass_intervals(const std::vector<PassSpan>& parts, double* lo_ms, double* hi_ms);

// Working-set effect: the fraction of a pass's reads that miss an L2 of `l2_mb`
// when the pass gathers from a `working_set_bytes` buffer at data-dependent positions (hits
// assumed free, misses at DRAM bandwidth): max(0, 1 - L2 / working set). 1 when l2_mb is 0.
double l2_miss_fraction(const GpuSpec& s, double working_set_bytes);
// Bytes per pixel of the buffers TWFR's reprojection gathers from (previous colour RGBA16F
// 8 B, depth 4 B, motion/confidence 4 B), one eye at a time.
constexpr double kReprojectBytesPerPixel = 16;

struct PassCoef {
  double overhead_ms = 0;
  std::map<std::string, double> terms;  // term name -> ms per unit
};

struct CalibrationResidual {
  std::string id;      // calibration entry id
  bool fitted = true;  // false: a check row (compared, not fitted)
  double published_ms = 0, model_ms = 0, rel_err = 0;
};

// The GPU profile every command and config uses when none is named (the one place it is
// written; Python reads it as fovsim.DEFAULT_GPU).
inline constexpr const char* kDefaultGpu = "gtx1080";

// The keys of a profile document, declared once (path, type, default, range, allowed values,
// meaning): GpuProfile::from_json reads every typed key through the getters below, so a default
// or a range is written only in the table, and docs/cost_model.md "GPU profile" is generated
// from it (`fovsim methods --markdown --gpu-profile-keys`, scripts/gen_method_docs.sh;
// tests/app/docs_test.cpp checks they match). `spec` keys are gpu_spec_table().
//
// Adding a GPU-profile key is one row in gpu_profile.cpp (`gpu_profile_key_table`), its member
// in GpuProfile (or the struct it belongs to), one getter call in from_json and its line in
// to_json, then `make docs`.
enum class ProfileKeyType { String, Bool, Int, Number, Numbers, Strings, Object };
struct ProfileKey {
  std::string path;  // "interval.total.lo_factor", "passes.{pass}.terms.{term}"
  ProfileKeyType type = ProfileKeyType::Object;
  Json def;               // null: no default (required, or read only when given)
  bool required = false;  // the key must be given (where its parent is)
  Range range;
  std::vector<std::string> allowed;  // String: the accepted values (empty: any)
  std::string doc;
};
// Every key, in the order of the generated table.
const std::vector<ProfileKey>& gpu_profile_keys();
// The row of `path`; an unknown one is a bug (FOVSIM_CHECK).
const ProfileKey& gpu_profile_key(const std::string& path);
// Read the key of `path` from `p`, the object that holds it, with the row's default, range and
// values. `key`: the JSON key when the path's last part is a placeholder ("{term}"); "" for
// the path's last part.
std::string profile_string(Params& p, const std::string& path);
bool profile_boolean(Params& p, const std::string& path);
int profile_integer(Params& p, const std::string& path);
double profile_number(Params& p, const std::string& path, const std::string& key = "");
std::vector<double> profile_numbers(Params& p, const std::string& path);
// The table as Markdown (key, type, default, values, meaning).
std::string gpu_profile_keys_markdown();
inline constexpr const char* kProfileKeyDocsBegin =
    "<!-- BEGIN GENERATED GPU PROFILE KEYS by `fovsim methods --markdown --gpu-profile-keys` "
    "(scripts/gen_method_docs.sh); do not edit -->";
inline constexpr const char* kProfileKeyDocsEnd = "<!-- END GENERATED GPU PROFILE KEYS -->";

// The ranges of a profile's numbers outside `spec` (gpu_spec_table has those), read from
// gpu_profile_keys(). They keep every product of the cost evaluation finite for inputs in the
// workload's ranges.
struct ProfileRanges {
  Range overhead_ms = gpu_profile_key("passes.{pass}.overhead_ms").range;
  Range coefficient = gpu_profile_key("passes.{pass}.terms.{term}").range;
  Range lo_factor = gpu_profile_key("interval.lo_factor").range;
  Range hi_factor = gpu_profile_key("interval.hi_factor").range;
  Range score = gpu_profile_key("interval.total_scores").range;
  Range residual_ms = gpu_profile_key("calibration.residuals[i].published_ms").range;
  Range rel_err = gpu_profile_key("calibration.residuals[i].rel_err").range;
};
inline const ProfileRanges kProfileRanges{};

struct GpuProfile {
  std::string name;
  std::string file;  // where it was loaded from (errors name it); "" when built in code
  std::string description;
  Json data;  // the profile document as loaded
  GpuSpec spec;
  std::map<std::string, PassCoef> passes;
  std::vector<CalibrationResidual> residuals;
  std::vector<std::string> calibration_tables;  // "id: source" of the tables fitted
  std::string calibration_comment;
  bool calibrated = false;  // false: coefficients transferred from the fit through spec ratios only
  std::string architecture;  // key `architecture`: what a spec transfer assumes (uncalibrated)
  CostModelKind model = CostModelKind::Linear;  // key `model`: "linear" (default) | "roofline"
  PredictionInterval interval;                  // key `interval` (optional)

  // `name_or_path`: a file path (contains '/' or ends in .json) or a name in
  // models_dir/gpus/NAME.json. Throws fovsim::Error naming the file and JSON path.
  static GpuProfile load(const std::string& name_or_path, const std::string& models_dir);
  static GpuProfile from_json(const Json& j, const std::string& file);
  // The config key `gpus` of `root`: a non-empty array of distinct profile names or paths, or
  // {kDefaultGpu} when absent; anything else is an error at that key.
  static std::vector<std::string> names_from_config(Params& root);
  // The whole profile document (the file `fovsim calibrate` writes; from_json reads it back).
  Json to_json() const;
  // to_json() as file text: keys in the documented order, passes in pipeline order.
  std::string to_file_text() const;
  // Lists profile names found in models_dir/gpus.
  static std::vector<std::string> available(const std::string& models_dir);

  // What-if: throughput of `r` multiplied by `factor` (> 0): its coefficients divide by it.
  GpuProfile scaled(Resource r, double factor) const;
  // Coefficient of (pass, term) in ms per unit; 0 when absent.
  double coef(const std::string& pass, const std::string& term) const;
};

}  // namespace fovsim
