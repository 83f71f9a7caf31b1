#include "sim/experiment/pareto.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace fovsim {

namespace {
// Objective value oriented so that smaller is better; NaN becomes +inf (worst).
double oriented(double v, const Objective& o) {
  if (std::isnan(v)) return INFINITY;
  return o.maximize ? -v : v;
}
}  // namespace

std::string group_key(const ResultRow& r, const std::vector<std::string>& group_by) {
  std::string k;
  for (auto& g : group_by) {
    if (const std::string* s = r.text_of(g))
      k += *s;
    else
      k += format_number(r.get(g, NAN));
    k += '\x1f';
  }
  return k;
}

bool dominates(const std::vector<double>& a, const std::vector<double>& b,
               const std::vector<Objective>& obj) {
  bool strictly = false;
  for (size_t i = 0; i < obj.size(); ++i) {
    double x = oriented(a[i], obj[i]), y = oriented(b[i], obj[i]);
    if (x > y) return false;
    if (x < y) strictly = true;
  }
  return strictly;
}

std::vector<size_t> pareto_front(const ResultTable& t, const std::vector<Objective>& obj,
                                 const std::vector<std::string>& group_by) {
  const auto& rows = t.rows();
  std::vector<std::vector<double>> v(rows.size());
  std::vector<std::string> g(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    for (auto& o : obj) v[i].push_back(rows[i].get(o.column, NAN));
    g[i] = group_key(rows[i], group_by);
  }
  std::vector<size_t> front;
  if (obj.empty()) return front;
  for (size_t i = 0; i < rows.size(); ++i) {
    bool all_nan = true;
    for (double x : v[i]) all_nan = all_nan && std::isnan(x);
    if (all_nan) continue;
    bool dominated = false;
    for (size_t j = 0; j < rows.size() && !dominated; ++j)
      if (j != i && g[j] == g[i] && dominates(v[j], v[i], obj)) dominated = true;
    if (!dominated) front.push_back(i);
  }
  return front;
}

ResultTable iso_budget_table(const ResultTable& summary, const IsoBudgetSpec& spec,
                             const std::vector<std::string>& param_columns) {
  ResultTable out;
  if (!spec.enabled() || spec.quality.empty()) return out;
  // Group order = first appearance; method labels in first-appearance order within a group.
  std::vector<std::string> gorder;
  std::map<std::string, std::vector<std::string>> labels;
  std::map<std::string, const ResultRow*> first_of_group;
  for (auto& r : summary.rows()) {
    std::string gk = group_key(r, spec.group_by);
    if (!labels.count(gk)) {
      gorder.push_back(gk);
      first_of_group[gk] = &r;
    }
    const std::string* lab = r.text_of("label");
    std::string l = lab ? *lab : "";
    auto& ls = labels[gk];
    if (std::find(ls.begin(), ls.end(), l) == ls.end()) ls.push_back(l);
  }
  const std::string& q0 = spec.quality.front();
  // A frame-time column (est_ms_*) is decided as every budget decision is (sim/cost/budget.h):
  // p_fit >= the cell's budget.p_fit. p_fit depends on budget / ms only, so the cell's
  // fit_threshold_ms / budget_ms (the largest estimate that fits, as a fraction of the budget)
  // carries its whole rule to any budget B: within B when value <= B x that fraction. Other
  // columns (shaded_fraction, ...) are compared as given.
  const bool time_column = spec.column.rfind("est_ms_", 0) == 0;
  auto fit_fraction = [&](const ResultRow& r) {
    const double t = r.get("fit_threshold_ms", NAN), b = r.get("budget_ms", NAN);
    return time_column && t >= 0 && b > 0 ? t / b : 1.0;
  };
  for (double budget : spec.budgets) {
    for (auto& gk : gorder) {
      for (auto& l : labels[gk]) {
        const ResultRow* best = nullptr;
        for (auto& r : summary.rows()) {
          const std::string* lab = r.text_of("label");
          if ((lab ? *lab : "") != l || group_key(r, spec.group_by) != gk) continue;
          double c = r.get(spec.column, NAN);
          if (!(c <= budget * fit_fraction(r) * (1 + spec.tolerance))) continue;
          double q = r.get(q0, NAN);
          if (std::isnan(q)) continue;
          // Ties on quality go to the cheaper row, then to the earlier one (stable).
          if (!best || q > best->get(q0, NAN) ||
              (q == best->get(q0, NAN) && c < best->get(spec.column, NAN)))
            best = &r;
        }
        ResultRow row;
        for (auto& g : spec.group_by) {
          const ResultRow* f = first_of_group[gk];
          if (const std::string* s = f->text_of(g)) row.set_text(g, *s);
        }
        row.set_text("label", l);
        if (best) {
          for (const char* k : {"method", "config_id", "cell_id"})
            if (const std::string* s = best->text_of(k)) row.set_text(k, *s);
        } else {
          row.set_text("config_id", "none_within_budget");
        }
        row.set("budget", budget);
        if (time_column && best) {  // the rule the chosen cell met
          row.set("fit_level", best->get("fit_level", NAN));
          row.set("within_ms", budget * fit_fraction(*best));
        }
        // Each value with its 95% half-width from the cell's summary (nan when it has none).
        row.set(spec.column, best ? best->get(spec.column, NAN) : NAN);
        row.set(spec.column + "_ci95", best ? best->get(spec.column + "_ci95", NAN) : NAN);
        for (auto& q : spec.quality) {
          row.set(q, best ? best->get(q, NAN) : NAN);
          row.set(q + "_ci95", best ? best->get(q + "_ci95", NAN) : NAN);
        }
        if (best)
          if (const std::string* k = best->text_of("kernel")) row.set_text("kernel", *k);
        row.set("cell", best ? best->get("cell", NAN) : NAN);
        for (auto& p : param_columns) row.set(p, best ? best->get(p, NAN) : NAN);
        out.add(std::move(row));
      }
    }
  }
  return out;
}

}  // namespace fovsim
