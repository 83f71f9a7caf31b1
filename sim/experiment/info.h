// What `fovsim info --json` prints and the Python bindings return (`_fovsim.info()`): version,
// CPU code paths, the registered methods in registration order, the metric registry, the units
// of the other result columns and the ranges of the cost commands' arguments. Scripts (viz/,
// python/fovsim) read these declarations instead of copying them.
#pragma once
#include <string>
#include <vector>

#include "sim/core/params.h"

namespace fovsim {

// A results column that is not a metric (metrics: sim/metrics/registry.h), with its unit.
struct ResultColumnDecl {
  const char* name;
  const char* label;  // axis label without the unit
  const char* unit;
};
// Exact columns; `est_ms_<pass>` and other families are described in results/README.md.
const std::vector<ResultColumnDecl>& result_column_decls();

// The range of a cost command's argument by name (CostArgRanges, sim/cost/budget.h): "pixels",
// "eyes", "budget_ms", "hz", "scale". Throws InternalError for another name.
Range cost_arg_range(const std::string& name);
const std::vector<std::string>& cost_arg_names();

// The methods `fovsim budget` (and Python's fovsim.budget) compares when none is given.
const std::vector<std::string>& budget_default_methods();

Json info_json();

}  // namespace fovsim
