#include "sim/experiment/info.h"

#include "sim/core/error.h"
#include "sim/core/version.h"
#include "sim/cost/budget.h"
#include "sim/experiment/code_paths.h"
#include "sim/foveation/factory.h"
#include "sim/metrics/registry.h"

namespace fovsim {

const std::vector<ResultColumnDecl>& result_column_decls() {
  // frames.csv / summary.csv columns written by the run engine (cell_rows.cpp build_rows,
  // summary.cpp summarize) and the latency what-if (results/README.md).
  static const std::vector<ResultColumnDecl> c = {
      {"est_ms_total", "estimated frame time", "ms"},
      {"est_ms_total_lo", "estimated frame time, interval low", "ms"},
      {"est_ms_total_hi", "estimated frame time, interval high", "ms"},
      {"shaded_fraction", "shaded fraction", "of W·H"},
      {"shaded_samples", "shaded samples", "samples"},
      {"prims_submitted", "primitives submitted", "triangles"},
      {"prims_culled", "primitives culled", "triangles"},
      {"latency_ms", "end-to-end latency", "ms"},
      {"gaze_error_deg", "gaze error", "deg"},
      {"gaze_speed_deg_s", "gaze speed", "deg/s"},
      {"gaze_x", "gaze x", "px"},
      {"gaze_y", "gaze y", "px"},
      {"t", "time", "s"},
      {"budget_ms", "frame budget", "ms"},
      {"ref_ms", "reference wall time", "ms"},
      {"sim_ms", "method wall time", "ms"},
  };
  return c;
}

const std::vector<std::string>& budget_default_methods() {
  return method_names();  // every registered method (sim/foveation/method_list.h)
}

const std::vector<std::string>& cost_arg_names() {
  static const std::vector<std::string> n = {"pixels", "eyes", "budget_ms", "hz", "scale"};
  return n;
}

Range cost_arg_range(const std::string& name) {
  if (name == "pixels") return CostArgRanges::pixels();
  if (name == "eyes") return CostArgRanges::eyes();
  if (name == "budget_ms") return CostArgRanges::budget_ms();
  if (name == "hz") return CostArgRanges::hz();
  FOVSIM_CHECK(name == "scale", "unknown cost argument \"" + name + "\"");
  return CostArgRanges::scale();
}

namespace {

Json range_json(const Range& r) {
  return Json{{"lo", r.lo}, {"hi", r.hi}, {"lo_open", r.lo_open}, {"hi_open", r.hi_open}};
}

}  // namespace

Json info_json() {
  Json j = code_paths_info();
  j["version"] = version_string();
  j["git_commit"] = git_commit();
  j["metrics"] = metric_registry_json();  // the metric registry (sim/metrics/registry.h)
  j["methods"] = Json::array();
  for (const auto& e : method_table()) j["methods"].push_back(e.name);
  j["columns"] = Json::object();
  for (const auto& c : result_column_decls())
    j["columns"][c.name] = Json{{"label", c.label}, {"unit", c.unit}};
  // `fovsim predict` / `budget` flag ranges (CostArgRanges), checked the same way in Python.
  j["budget_default_methods"] = budget_default_methods();
  j["cost_arg_ranges"] = Json::object();
  for (const auto& n : cost_arg_names()) j["cost_arg_ranges"][n] = range_json(cost_arg_range(n));
  return j;
}

}  // namespace fovsim
