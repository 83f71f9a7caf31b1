// Pass assembly (docs/architecture.md §6): which passes exist for a scene + method, and the value
// of every term of their linear models. Shared by estimate_frame and calibration so the fit and the
// prediction use the same equations. Term units are in docs/cost_model.md.
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
};

struct PassWork {
  std::string pass;
  std::vector<Term> terms;
};

// Method names the cost model knows (the factory's); the passes it charges come from the
// declaration (CostInputs::passes, declared_passes in factory.h).
bool is_cost_method(const std::string& m);
CostFamily cost_family(const std::string& m);  // throws Error for an unknown method
const std::vector<std::string>& cost_methods();

// The resource class of a (pass, term); throws fovsim::Error(where, ...) for unknown pairs.
Resource term_resource(const std::string& pass, const std::string& term, const std::string& where);
// The same lookup without an error: nullopt when (pass, term) is not a cost term.
std::optional<Resource> find_term_resource(const std::string& pass, const std::string& term);
// Every pass name the model knows, in pipeline order (est_ms_<pass> columns).
const std::vector<std::string>& known_passes();
bool is_known_pass(const std::string& p);

// Roofline model only: factor on a term's work for the working-set effect. TWFR's
// reprojection gathers the previous frame at reprojected positions (Franke et al. 2021 §4), so its
// DRAM traffic is the L2 miss fraction of a W*H*kReprojectBytesPerPixel buffer (one eye at
// a time); every other term streams and is 1.
double working_set_factor(const std::string& pass, const std::string& term, const GpuSpec& spec,
                          const Display& display);

// Passes that exist for these inputs, with term values: the ones in.passes declares (unset: those
// of in.method with its default lighting strategy), never inferred from which counters are
// present. `missing` receives the names of counters the passes read but the method did not fill.
std::vector<PassWork> assemble_passes(const CostInputs& in, const Workload& w,
                                      std::vector<std::string>* missing = nullptr);

}  // namespace fovsim
