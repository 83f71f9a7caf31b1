// Pass assembly (docs/architecture.md "Cost model"): which passes exist for a scene + method, and
// the value of every term of their linear models. Shared by estimate_frame and calibration so the
// fit and the prediction use the same equations. Term units are in docs/cost_model.md.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/workload.h"
#include "sim/foveation/method.h"

namespace fovsim {

struct Term {
  std::string name;
  Resource res;
  double value = 0;  // counter units for the whole frame (all eyes)
  // The dispatch of the pass the term belongs to (term_stage): a pass of several dependent
  // dispatches (TWFR's reprojection: the point-sprite warp, then push-pull and confidence)
  // costs the sum of each dispatch's roofline, not one roofline over all its terms.
  int stage = 0;
};

struct PassWork {
  std::string pass;
  std::vector<Term> terms;
};

// Method names the cost model knows (the factory's); the passes it charges come from the
// declaration (CostInputs::passes, declared_passes in factory.h).
bool is_cost_method(const std::string& m);
const std::vector<std::string>& cost_methods();

// The resource class of a (pass, term); throws fovsim::Error(where, ...) for unknown pairs.
Resource term_resource(const std::string& pass, const std::string& term, const std::string& where);
// The same lookup without an error: nullopt when (pass, term) is not a cost term.
std::optional<Resource> find_term_resource(const std::string& pass, const std::string& term);
// Every term name of the term table, each once, in the table's order.
const std::vector<std::string>& term_names();
// The dispatch (0, 1, ...) of a (pass, term) within its pass: 0 for every single-dispatch pass.
int term_stage(const std::string& pass, const std::string& term);
// Roofline time (ms) of a pass's terms given each term's time: the slowest resource of each
// dispatch, summed over the dispatches; `bound` (optional) receives each dispatch's slowest
// resource and its time.
double roofline_ms(const std::vector<Term>& terms, const std::vector<double>& term_ms,
                   std::vector<std::pair<Resource, double>>* bound = nullptr);
// Every pass name the model knows, in pipeline order (est_ms_<pass> columns).
const std::vector<std::string>& known_passes();
bool is_known_pass(const std::string& p);

// Roofline model only: factor on a term's work for the working-set effect. TWFR's
// reprojection warps the previous frame to reprojected positions (Franke et al. 2021 §4), so its
// DRAM traffic is the L2 miss fraction of a W*H*kReprojectBytesPerPixel buffer (one eye at
// a time), and its sprites, each waiting on the fetch of its world position, stall on the same
// misses (estimate_frame keeps them at or above the peak primitive rate); the hole counts and
// every other term stream and are 1.
// FLC's contribution pass (Yang et al. 2021 §5) in FP32 operations of the algorithm as the paper
// states it: per VPL-sample pair eq. 14 (geometry term, the eq. 11 mix, the summand) and per BLSO
// lookup eqs. 12-13 (a position in the cone around d, its light-space projection, the depth
// compare with its sqrt and exp, the running mean). Counted like docs/cost_model.md says.
constexpr double kEq14FlopsPerPair = 80;
constexpr double kBlsoFlopsPerLookup = 120;
double contribution_flops(double evals, double lookups);
// FLC's post-antialiasing (Yang et al. 2021 §6) in texel reads per full-resolution pixel: the
// 3x3 Gaussian (9), the TAA neighbourhood clamp of eta x eta texels with eta from eq. 15
// (the mean of eta^2 over the display, gaze at the centre), the history (1) and motion (1).
constexpr double kPostAaGaussianTaps = 9;
constexpr double kPostAaHistoryTaps = 2;
double post_aa_taps_per_pixel(int width, int height);

double working_set_factor(const std::string& pass, const std::string& term, const GpuSpec& spec,
                          const Display& display);

// Passes that exist for these inputs, with term values: the ones in.passes declares (unset: those
// of in.method with its default lighting strategy), never inferred from which counters are
// present. `missing` receives the names of counters the passes read but the method did not fill.
std::vector<PassWork> assemble_passes(const CostInputs& in, const Workload& w,
                                      std::vector<std::string>* missing = nullptr);

}  // namespace fovsim
