// Design-space analysis over a sweep's summary table (docs/architecture.md "Sweeps, search and
// fidelity"): Pareto fronts over the declared objectives and iso-budget comparison tables (RMFR
// §5.1: every method tuned to the same budget, then compared on quality).
#pragma once
#include <string>
#include <vector>

#include "sim/experiment/sweep_spec.h"
#include "sim/experiment/table.h"

namespace fovsim {

// a dominates b: no worse in every objective and strictly better in one. A NaN objective
// never dominates and is always dominated by a finite value.
bool dominates(const std::vector<double>& a, const std::vector<double>& b,
               const std::vector<Objective>& obj);

// Indices of the non-dominated rows (ascending index order). Rows are compared only within
// the same values of `group_by` text/numeric columns (e.g. per GPU). Duplicated points are all
// kept. O(n^2) per group; sweeps have at most thousands of rows.
std::vector<size_t> pareto_front(const ResultTable& t, const std::vector<Objective>& obj,
                                 const std::vector<std::string>& group_by = {});

// Per group × method label × budget: the row with the best first quality column among
// rows whose `column` <= budget·(1 + tolerance); for a frame-time column (est_ms_*) the budget
// decision of sim/cost/budget.h instead (p_fit >= the cell's budget.p_fit, through its
// fit_threshold_ms / budget_ms; also fit_level and within_ms columns). Columns: budget, group
// columns, label, method, config_id, cell, the budget column, every quality column, the swept
// parameters.
ResultTable iso_budget_table(const ResultTable& summary, const IsoBudgetSpec& spec,
                             const std::vector<std::string>& param_columns);

// The group key of a row ("" when group_by is empty).
std::string group_key(const ResultRow& r, const std::vector<std::string>& group_by);

}  // namespace fovsim
