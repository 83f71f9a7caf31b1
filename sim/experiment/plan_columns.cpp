// The columns a sweep's summary can have, known before any cell runs (results/README.md
// "Column names"): the sweep's objectives, pareto.group_by, iso_budget and search name columns,
// and a name no cell can produce is refused when the sweep is parsed rather than after every
// cell has run. The vocabulary is a superset of what one configuration writes (a metric that
// is off, a pass the scene has not, a latency column without a latency block all count as
// possible): check_plan_columns still checks the first cell's actual summary.
#include <algorithm>
#include <set>

#include "sim/core/counter_list.h"
#include "sim/core/error.h"
#include "sim/cost/passes.h"
#include "sim/experiment/sweep_spec.h"
#include "sim/foveation/factory.h"
#include "sim/foveation/lighting.h"
#include "sim/metrics/registry.h"
#include "sim/trace/csv_table.h"

namespace fovsim {

namespace {

bool ends_with(const std::string& s, const std::string& suf) {
  return s.size() > suf.size() && s.compare(s.size() - suf.size(), suf.size(), suf) == 0;
}

// The phases of the latency what-if and the tracking states: `<col>_<P>`, `frames_<P>`.
const std::vector<std::string>& split_suffixes() {
  static const std::vector<std::string> s{"saccade", "suppression", "fixation",
                                          "valid",   "held",        "lost"};
  return s;
}

struct ColumnVocabulary {
  std::set<std::string> numeric, text;  // base names (no interval or split suffix)

  bool base(const std::string& c, bool numeric_only) const {
    if (numeric.count(c) || (!numeric_only && text.count(c))) return true;
    if (find_metric(c) || find_counter(c)) return true;
    if (c.rfind("est_ms_", 0) == 0 && is_known_pass(c.substr(7))) return true;
    return false;
  }
  // A base name, or one followed by the suffixes the summary adds (results/README.md):
  // `_ci95`, `_lo`/`_hi`, `_p50`/`_p95`/`_p99` (est_ms_total), `_<phase>`, `_<state>`, and
  // `frames_<phase|state>`. Depth-bounded: at most three suffixes are stripped.
  bool possible(const std::string& c, bool numeric_only, int depth = 0) const {
    if (base(c, numeric_only)) return true;
    if (depth >= 3) return false;
    static const std::vector<std::string> suffixes{"_ci95", "_lo", "_hi", "_p50", "_p95", "_p99"};
    for (auto& s : suffixes)
      if (ends_with(c, s) && possible(c.substr(0, c.size() - s.size()), true, depth + 1))
        return true;
    for (auto& p : split_suffixes()) {
      if (c == "frames_" + p) return true;
      if (ends_with(c, "_" + p) && possible(c.substr(0, c.size() - p.size() - 1), true, depth + 1))
        return true;
    }
    return false;
  }
  // The names listed in an error: every base name, then the families and the suffixes.
  std::string listing(bool numeric_only) const {
    std::vector<std::string> all(numeric.begin(), numeric.end());
    if (!numeric_only) all.insert(all.end(), text.begin(), text.end());
    for (int c = 0; c < kCounterCount; ++c)
      if (!counter_indexed(Counter(c))) all.push_back(counter_name(Counter(c)));
    for (auto& p : known_passes()) all.push_back("est_ms_" + p);
    for (auto& d : metric_registry()) {
      if (d.family) continue;
      all.push_back(d.name);
      all.push_back(d.name + kFoveationLossSuffix);
      if (d.pooling == Pooling::sequence) all.push_back(d.pooled_column);
    }
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    std::string l;
    for (auto& c : all) l += (l.empty() ? "" : ", ") + c;
    std::string fam;
    for (int c = 0; c < kCounterCount; ++c)
      if (counter_indexed(Counter(c))) fam += std::string(", ") + counter_name(Counter(c)) + "<n>";
    for (auto& d : metric_registry())
      if (d.family) fam += ", " + d.name + "<a>_<b>";
    return l + fam +
           "; each may be followed by _ci95, _lo, _hi, _p50/_p95/_p99, _<phase> or _<state>";
  }
  std::vector<std::string> names(bool numeric_only) const {
    std::vector<std::string> v(numeric.begin(), numeric.end());
    if (!numeric_only) v.insert(v.end(), text.begin(), text.end());
    for (int c = 0; c < kCounterCount; ++c) v.push_back(counter_name(Counter(c)));
    for (auto& p : known_passes()) v.push_back("est_ms_" + p);
    for (auto& d : metric_registry()) v.push_back(d.name), v.push_back(d.name + "_fl");
    return v;
  }
};

// The part that does not depend on the plan, built once.
ColumnVocabulary fixed_vocabulary() {
  ColumnVocabulary v;
  // Written by the row builders and the summary (sim/experiment/cell_rows.cpp build_rows,
  // summary.cpp summarize, latency.cpp, tracking_summary.cpp, startup.cpp, sweep_runner.cpp).
  v.numeric = {"cell",
               "frames",
               "startup_frames",
               "budget_ms",
               "fits_budget",
               "p_fit",
               "fit_level",
               "fit_threshold_ms",
               "headroom_ms",
               "frame",
               "t",
               "gaze_x",
               "gaze_y",
               "gaze_valid",
               "shaded_samples",
               "shaded_fraction",
               "prims_submitted",
               "prims_culled",
               "est_ms_total",
               "ref_ms",
               "sim_ms",
               "latency_ms",
               "gaze_est_x",
               "gaze_est_y",
               "gaze_error_deg",
               "gaze_speed_deg_s"};
  v.text = {"config_id", "cell_id", "method",    "label",      "gpu",      "lighting",
            "tracking",  "phase",   "ci_method", "ci_missing", "at_floor", "missing_counters"};
  // Every method's and lighting strategy's parameter columns: the declared keys and the
  // columns a default instance writes (a column may be named apart from its key).
  for (auto& e : method_table()) {
    for (auto& p : e.params()) v.numeric.insert(p.name);
    try {
      Params none(Json::object());
      auto m = make_method(e.name, none);
      for (auto& [c, x] : m->param_columns()) v.numeric.insert(c);
      for (auto& [c, x] : m->text_param_columns()) v.text.insert(c);
    } catch (const Error&) {
      continue;  // a method without a default instance: its declared keys above
    }
  }
  for (auto& e : lighting_table()) {
    for (auto& p : e.params()) v.numeric.insert(p.name);
    try {
      Params lp(Json{{"method", e.name}});
      auto l = make_lighting(lp);
      for (auto& [c, x] : l->param_columns()) v.numeric.insert(c);
    } catch (const Error&) {
      continue;  // a strategy without a default instance: its declared keys above
    }
  }
  v.numeric.erase("method");
  v.numeric.erase("label");
  return v;
}

ColumnVocabulary vocabulary(const SweepPlan& plan) {
  static const ColumnVocabulary fixed = fixed_vocabulary();
  ColumnVocabulary v = fixed;
  for (auto& a : plan.axis_paths) v.numeric.insert(a), v.text.insert(a);
  return v;
}

}  // namespace

void check_plan_column_names(const SweepPlan& plan) {
  const bool any_named = !plan.objectives.empty() || plan.iso.enabled() || plan.search.enabled() ||
                         plan.pareto_group_by != std::vector<std::string>{"gpu"};
  if (!any_named) return;
  const ColumnVocabulary v = vocabulary(plan);
  const std::string W = plan.file.empty() ? "sweep" : plan.file + ": sweep";
  auto check = [&](const std::string& col, const std::string& where, bool numeric_only) {
    if (v.possible(col, numeric_only)) return;
    const std::string hint = closest_name(col, v.names(numeric_only));
    throw Error(where, std::string("no ") + (numeric_only ? "numeric " : "") + "column \"" +
                           printable(col) + "\" can be in a cell's summary" +
                           (hint.empty() ? "" : " (did you mean \"" + hint + "\"?)") +
                           "; checked before any cell runs (columns: " + v.listing(numeric_only) +
                           "; results/README.md)");
  };
  for (size_t i = 0; i < plan.objectives.size(); ++i)
    check(plan.objectives[i].column, W + ".objectives[" + std::to_string(i) + "]", true);
  for (auto& g : plan.pareto_group_by) check(g, W + ".pareto.group_by", false);
  if (plan.iso.enabled()) {
    check(plan.iso.column, W + ".iso_budget.column", true);
    if (plan.iso.quality_given)
      for (auto& q : plan.iso.quality) check(q, W + ".iso_budget.quality", true);
    for (auto& g : plan.iso.group_by) check(g, W + ".iso_budget.group_by", false);
  }
  if (plan.search.enabled()) {
    const SearchSpec& sp = plan.search;
    check(sp.objective.column, W + ".search." + (sp.objective.maximize ? "maximize" : "minimize"),
          true);
    for (const SearchConstraint& c : sp.constraints)
      check(c.column, W + ".search.subject_to." + c.column, true);
  }
}

}  // namespace fovsim
