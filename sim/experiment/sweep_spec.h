// Sweep configs (docs/architecture.md "Inputs: displays, traces, scenes, configs", "Sweeps, search
// and fidelity"; docs/sweeps.md): a run config plus a "sweep" block whose parameter axes expand to
// an ordered list of cells. Cell i is always the same run (same assignments, same hash) for a given
// config, so any engine can execute it by index.
//
// Axis kinds: grid (cartesian), list (explicit assignments), zip (advance together),
// random and lhs (Latin hypercube, seeded). Blocks combine as a cartesian product, the first
// block varying slowest. Axis paths address the run config: "render.scale",
// "methods[0].sigma", or method-scoped "methods[kfr].sigma" (the entry whose label, or
// method name when it has no label, is kfr).
#pragma once
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/core/param_table.h"
#include "sim/core/params.h"
#include "sim/experiment/config.h"
#include "sim/experiment/table.h"

namespace fovsim {

struct Assignment {
  std::string path;  // as written in the sweep ("methods[kfr].sigma")
  Json value;
  std::string where;  // location of the axis in the sweep config, for errors
};

struct SweepCell {
  int index = 0;
  std::vector<Assignment> assign;  // axis order
  Json doc;                        // the run config of this cell (sweep block removed)
  std::string hash;                // short_hash of doc: changes whenever the cell's run changes
  std::string id() const;          // "0007-<hash>": its folder under runs/
};

struct Objective {
  std::string column;
  bool maximize = false;
};

// Iso-budget comparison (RMFR §5.1): per method, the best cell whose `column` stays within
// each budget.
struct IsoBudgetSpec {
  std::string column;  // e.g. "shaded_fraction" or "est_ms_total"
  std::vector<double> budgets;
  double tolerance = 0.0;            // relative slack: value <= budget * (1 + tolerance)
  std::vector<std::string> quality;  // first one ranks; all are reported
  bool quality_given = false;        // false: the default list (columns absent are skipped)
  std::vector<std::string> group_by;
  bool enabled() const { return !column.empty(); }
};

// Per-context ask/tell search (docs/sweeps.md "search"): the sweep's axes define contexts
// (e.g. scenes); inside each, a searcher proposes points of `space`.
struct SearchDim {
  std::string path;
  double lo = 0, hi = 1;
  double step = 0;  // > 0: quantized
  bool log = false;
  bool integer = false;
  std::string where = {};
};
// One bound of `subject_to` on a summary column of the scored row: min <= value <= max (either
// side may be absent, +-inf). E.g. "cheapest configuration whose JOD >= 9.5 within the frame
// budget": minimize est_ms_total subject to fvvdp_jod_fl >= 9.5 and headroom_ms >= 0.
struct SearchConstraint {
  std::string column;
  double min = -INFINITY, max = INFINITY;
  std::string describe() const;  // "fvvdp_jod_fl >= 9.5", "est_ms_total <= 11.1", "a <= x <= b"
};
// One method of a search spanning methods (sweep.search.methods): the method entry's label and
// its own parameter space.
struct MethodSpace {
  std::string label;
  std::vector<SearchDim> space;
};
struct SearchSpec {
  std::vector<SearchDim> space;
  // sweep.search.methods: a method axis, one space per method entry (then `space` is empty and
  // select_label unset); per_method() gives the search of each.
  std::vector<MethodSpace> methods;
  Objective objective;  // maximize/minimize a summary column
  // Optional constraints (subject_to), in column-name order; all must hold.
  std::vector<SearchConstraint> constraints;
  // The total violation of `values` (one per constraint, in order): the sum over constraints of
  // how far the value lies outside [min, max], each in its column's unit; 0 = feasible, a
  // missing (NaN) value is infinitely violated.
  double violation(const std::vector<double>& values) const;
  // As violation, with each value `margins[k]` further from constraint k's limits (x - m
  // against min, x + m against max): a measured bias carried into the decision.
  double violation(const std::vector<double>& values, const std::vector<double>& margins) const;
  std::string select_label;  // which summary row is scored (label); "" = first row
  // sweep.search.p_fit: feasible only where the summary's p_fit reaches this level (appended to
  // `constraints` as p_fit >= level, and the cells' budget.p_fit); 0 = not given.
  double fit_level = 0;
  int evaluations = 32;
  int batch = 8;
  uint64_t seed = 1;
  bool enabled() const { return !space.empty() || !methods.empty(); }
  // The searches this one runs: itself, or one per entry of `methods` (its space and label,
  // the seed offset by the entry's index).
  std::vector<SearchSpec> per_method() const;
};

struct SweepPlan {
  std::string name;
  std::string file, base_dir;
  Json base;                            // run config without the sweep block
  std::vector<std::string> axis_paths;  // distinct assignment paths in first-seen order
  std::vector<SweepCell> cells;
  std::vector<Objective> objectives;
  std::vector<std::string> pareto_group_by;  // default {"gpu"}
  IsoBudgetSpec iso;
  SearchSpec search;
  std::string hash;  // of all cell hashes in order
};

// The sweep block's own keys (`sweep.max_cells`) and the declared keys of `sweep.iso_budget`
// and `sweep.search` (sim/core/param_table.h); the axes are documented rows (their keys are
// config paths). configs/README.md's `sweep` tables are generated from these.
struct SweepKeys {
  int max_cells = 100000;
};
const ParamTable<SweepKeys>& sweep_table();
const ParamTable<IsoBudgetSpec>& iso_budget_table();
const ParamTable<SearchSpec>& search_table();

// Expands cfg.doc's "sweep" block (a config without one is a single cell). Every error
// names the sweep's JSON path.
SweepPlan expand_sweep(const LoadedConfig& cfg);

// Checks every cell's method blocks: an axis naming a parameter the method does not have is
// an error at the axis location; each method is constructed once per distinct block, so
// out-of-range values fail before anything is computed.
void validate_cells(const SweepPlan& plan);

// Applies one assignment to a run config; method-scoped indices are resolved by label.
// Returns the concrete path ("methods[1].sigma").
std::string apply_assignment(Json& doc, const std::string& path, const Json& value,
                             const std::string& where);

// Values of one axis spec: a JSON array, {"values": [...]}, {"from","to","step"} (inclusive)
// or {"from","to","count"} (evenly spaced). `where` locates errors.
std::vector<Json> axis_values(const Json& spec, const std::string& where);

// Every column the plan names (objectives, pareto.group_by, iso_budget, search objective and
// constraint) must be a column of the cells' summary rows `summary` (as a --target column must
// be one of the frames'): throws fovsim::Error at the key's JSON path naming the column and
// listing the columns there are. `search_only`: check only the search's columns.
void check_plan_columns(const SweepPlan& plan, const ResultTable& summary,
                        bool search_only = false);
// The same columns checked when the sweep is parsed (expand_sweep calls it), before any cell
// runs: each must be a column some cell's summary can have (results/README.md: row keys,
// counters, est_ms_<pass>, metrics, method and lighting parameter columns, axis paths, with
// the summary's suffixes); otherwise a fovsim::Error at the key's JSON path listing the names.
void check_plan_column_names(const SweepPlan& plan);

// Rounds to 12 significant digits so 1.2 + 0.2*k prints and hashes as typed.
double tidy(double v);

}  // namespace fovsim
