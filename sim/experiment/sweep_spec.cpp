#include "sim/experiment/sweep_spec.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "sim/core/error.h"
#include "sim/core/hash.h"
#include "sim/core/rng.h"
#include "sim/cost/budget.h"
#include "sim/experiment/table.h"
#include "sim/foveation/factory.h"
#include "sim/trace/csv_table.h"

namespace fovsim {

namespace fs = std::filesystem;

namespace {

using Row = std::vector<Assignment>;  // one point of a block: the assignments it makes

const std::set<std::string> kBlockKinds = {"grid", "list", "zip", "random", "lhs"};

std::string key_where(const std::string& where, const std::string& key) {
  return where + "." + key;
}

double num_of(const Json& j, const std::string& where, const char* key) {
  if (!j.contains(key)) throw Error(where, std::string("missing \"") + key + "\"");
  const Json& v = j[key];
  if (!v.is_number())
    throw Error(key_where(where, key), "expected a number, got " + describe_json(v));
  double d = v.get<double>();
  if (!std::isfinite(d)) throw Error(key_where(where, key), "expected a finite number");
  return d;
}

void only_keys(const Json& j, const std::string& where, const std::set<std::string>& allowed) {
  for (auto it = j.begin(); it != j.end(); ++it)
    if (!allowed.count(it.key())) {
      std::string names;
      for (auto& a : allowed) names += (names.empty() ? "" : ", ") + a;
      throw Error(key_where(where, it.key()), "unknown key (allowed here: " + names + ")");
    }
}

Json number_json(double v) {
  v = tidy(v);
  if (std::fabs(v) < 9e15 && v == std::floor(v)) return Json(int64_t(v));
  return Json(v);
}

// The values of a range axis are rounded to 12 significant digits (tidy): values closer than
// that would become identical cells, which is an error naming the first two.
void distinct_after_rounding(const std::vector<Json>& values, const std::string& where) {
  for (size_t k = 1; k < values.size(); ++k)
    if (values[k] == values[k - 1])
      throw Error(where, "values " + std::to_string(k - 1) + " and " + std::to_string(k) +
                             " of the range are both " + values[k].dump() +
                             " after rounding to 12 significant digits (identical cells): "
                             "widen the range or use fewer values");
}

// Ordered (path, spec) axes of a grid or zip block: an object (keys in sorted order, as JSON
// objects are read) or an array of one-key objects (order as written).
std::vector<std::pair<std::string, std::pair<Json, std::string>>> ordered_axes(
    const Json& j, const std::string& where) {
  std::vector<std::pair<std::string, std::pair<Json, std::string>>> out;
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it)
      out.push_back({it.key(), {it.value(), key_where(where, it.key())}});
  } else if (j.is_array()) {
    for (size_t i = 0; i < j.size(); ++i) {
      std::string w = where + "[" + std::to_string(i) + "]";
      if (!j[i].is_object() || j[i].size() != 1)
        throw Error(
            w, "expected a one-key object {\"config.path\": values}, got " + describe_json(j[i]));
      out.push_back({j[i].begin().key(), {j[i].begin().value(), key_where(w, j[i].begin().key())}});
    }
  } else {
    throw Error(where,
                "expected an object {\"config.path\": values, ...}, got " + describe_json(j));
  }
  if (out.empty()) throw Error(where, "no axes (expected at least one \"config.path\": values)");
  return out;
}

// Default and largest cap on the number of cells a sweep may expand to (sweep.max_cells).
constexpr double kDefaultMaxCells = 100000, kMaxMaxCells = 10000000;

[[noreturn]] void too_many_cells(const std::string& where, double cells, double cap,
                                 bool at_least = false) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.0f", cells);
  throw Error(where, std::string("expands to ") + (at_least ? "at least " : "") +
                         (cells >= 1e18 ? "more than 1e18" : buf) + " cells, over the limit of " +
                         std::to_string(size_t(cap)) + " (set sweep.max_cells, up to " +
                         std::to_string(size_t(kMaxMaxCells)) + ")");
}

std::vector<Row> grid_rows(const Json& j, const std::string& where, double cap) {
  std::vector<std::pair<std::string, std::pair<std::vector<Json>, std::string>>> axes;
  double product = 1;
  auto specs = ordered_axes(j, where);
  for (auto& [path, sv] : specs) {
    axes.push_back({path, {axis_values(sv.first, sv.second), sv.second}});
    product *= double(axes.back().second.first.size());
    if (product > cap)
      too_many_cells(where, product, cap, axes.size() < specs.size());  // before any row
  }
  std::vector<Row> rows{Row{}};
  for (auto& [path, av] : axes) {
    auto& [vals, w] = av;
    std::vector<Row> next;
    next.reserve(rows.size() * vals.size());
    for (auto& r : rows)
      for (auto& v : vals) {
        Row n = r;
        n.push_back({path, v, w});
        next.push_back(std::move(n));
      }
    rows = std::move(next);
  }
  return rows;
}

std::vector<Row> zip_rows(const Json& j, const std::string& where, double cap) {
  auto axes = ordered_axes(j, where);
  std::vector<std::vector<Json>> vals;
  for (auto& a : axes) vals.push_back(axis_values(a.second.first, a.second.second));
  if (double(vals[0].size()) > cap) too_many_cells(where, double(vals[0].size()), cap);
  for (size_t i = 1; i < axes.size(); ++i)
    if (vals[i].size() != vals[0].size())
      throw Error(where, "zip axes must have equal lengths: \"" + axes[0].first + "\" has " +
                             std::to_string(vals[0].size()) + " values, \"" + axes[i].first +
                             "\" has " + std::to_string(vals[i].size()));
  std::vector<Row> rows(vals[0].size());
  for (size_t k = 0; k < rows.size(); ++k)
    for (size_t i = 0; i < axes.size(); ++i)
      rows[k].push_back({axes[i].first, vals[i][k], axes[i].second.second});
  return rows;
}

std::vector<Row> list_rows(const Json& j, const std::string& where) {
  if (!j.is_array())
    throw Error(where,
                "expected an array of {\"config.path\": value} objects, got " + describe_json(j));
  if (j.empty()) throw Error(where, "empty list (no runs)");
  std::vector<Row> rows;
  for (size_t i = 0; i < j.size(); ++i) {
    std::string w = where + "[" + std::to_string(i) + "]";
    if (!j[i].is_object() || j[i].empty())
      throw Error(
          w, "expected a non-empty object {\"config.path\": value}, got " + describe_json(j[i]));
    Row r;
    for (auto it = j[i].begin(); it != j[i].end(); ++it)
      r.push_back({it.key(), it.value(), key_where(w, it.key())});
    rows.push_back(std::move(r));
  }
  return rows;
}

// A dimension of a random/LHS block: continuous range (optionally log, quantized, integer)
// or a choice among listed values.
struct Dim {
  std::string path, where;
  std::vector<Json> choices;
  double lo = 0, hi = 1, step = 0;
  bool log = false, integer = false;
  Json value(double u) const {  // u in [0, 1)
    if (!choices.empty())
      return choices[std::min(choices.size() - 1, size_t(u * double(choices.size())))];
    double v =
        log ? std::exp(std::log(lo) + u * (std::log(hi) - std::log(lo))) : lo + u * (hi - lo);
    if (step > 0) v = std::min(hi, lo + std::round((v - lo) / step) * step);
    // Integers stay inside [from, to]: rounding 0.6 of [0.5, 1.5] up to 1 is fine, rounding
    // 1.4 of [1.3, 3] down to 1 is not (parse_dim checks that an integer exists).
    if (integer) v = std::min(std::floor(hi), std::max(std::ceil(lo), std::round(v)));
    return number_json(v);
  }
};

Dim parse_dim(const std::string& path, const Json& j, const std::string& where) {
  Dim d;
  d.path = path;
  d.where = where;
  if (j.is_array() || (j.is_object() && j.contains("values"))) {
    d.choices = axis_values(j, where);
    return d;
  }
  if (!j.is_object())
    throw Error(
        where, "expected {\"from\": a, \"to\": b} or an array of choices, got " + describe_json(j));
  only_keys(j, where, {"from", "to", "step", "log", "integer"});
  d.lo = num_of(j, where, "from");
  d.hi = num_of(j, where, "to");
  if (!(d.hi > d.lo)) throw Error(where, "empty axis: \"to\" must be greater than \"from\"");
  if (j.contains("step")) {
    d.step = num_of(j, where, "step");
    if (!(d.step > 0)) throw Error(key_where(where, "step"), "must be > 0");
  }
  for (const char* k : {"log", "integer"})
    if (j.contains(k) && !j[k].is_boolean())
      throw Error(key_where(where, k), "expected true or false");
  d.log = j.value("log", false);
  d.integer = j.value("integer", false);
  if (d.log && d.lo <= 0) throw Error(key_where(where, "from"), "a log axis needs from > 0");
  if (d.integer && std::ceil(d.lo) > std::floor(d.hi))
    throw Error(key_where(where, "integer"),
                "no integer in [" + format_number(d.lo) + ", " + format_number(d.hi) + "]");
  return d;
}

std::vector<Row> sampled_rows(const Json& j, const std::string& where, bool lhs, double cap) {
  if (!j.is_object()) throw Error(where, "expected {\"count\": n, \"seed\": s, \"axes\": {...}}");
  only_keys(j, where, {"count", "seed", "axes"});
  double cnt = num_of(j, where, "count");
  if (cnt < 1 || cnt > 1e6 || cnt != std::floor(cnt))
    throw Error(key_where(where, "count"), "expected an integer in [1, 1000000]");
  if (cnt > cap) too_many_cells(key_where(where, "count"), cnt, cap);
  uint64_t seed = 1;
  if (j.contains("seed")) {
    double s = num_of(j, where, "seed");
    if (s < 0 || s != std::floor(s) || s > 9007199254740992.0)
      throw Error(key_where(where, "seed"), "expected an integer in [0, 2^53]");
    seed = uint64_t(s);
  }
  if (!j.contains("axes")) throw Error(where, "missing \"axes\"");
  std::vector<Dim> dims;
  for (auto& [path, sv] : ordered_axes(j["axes"], key_where(where, "axes")))
    dims.push_back(parse_dim(path, sv.first, sv.second));
  size_t n = size_t(cnt);
  std::vector<std::vector<double>> u(n, std::vector<double>(dims.size()));
  if (!lhs) {
    Rng rng(seed, 0x5eed);  // one sequence: sample-major, dimension-minor
    for (size_t i = 0; i < n; ++i)
      for (size_t d = 0; d < dims.size(); ++d) u[i][d] = rng.uniform();
  } else {
    // Latin hypercube (McKay et al. 1979): each dimension's n strata used exactly once, a
    // seeded permutation per dimension, jittered inside the stratum.
    for (size_t d = 0; d < dims.size(); ++d) {
      Rng rng(seed, 0x1a5 + d);
      std::vector<size_t> perm(n);
      for (size_t i = 0; i < n; ++i) perm[i] = i;
      for (size_t i = n; i > 1; --i) std::swap(perm[i - 1], perm[rng.below(uint32_t(i))]);
      for (size_t i = 0; i < n; ++i) u[i][d] = (double(perm[i]) + rng.uniform()) / double(n);
    }
  }
  std::vector<Row> rows(n);
  for (size_t i = 0; i < n; ++i)
    for (size_t d = 0; d < dims.size(); ++d)
      rows[i].push_back({dims[d].path, dims[d].value(u[i][d]), dims[d].where});
  return rows;
}

std::vector<Row> block_rows(const Json& block, const std::string& where, double cap) {
  if (!block.is_object() || block.size() != 1 || !kBlockKinds.count(block.begin().key()))
    throw Error(where,
                "expected one of {\"grid\": ...}, {\"list\": ...}, {\"zip\": ...}, {\"random\": "
                "...}, {\"lhs\": ...}");
  const std::string kind = block.begin().key();
  const Json& j = block.begin().value();
  std::string w = key_where(where, kind);
  if (kind == "grid") return grid_rows(j, w, cap);
  if (kind == "zip") return zip_rows(j, w, cap);
  if (kind == "list") {
    if (j.is_array() && double(j.size()) > cap) too_many_cells(w, double(j.size()), cap);
    return list_rows(j, w);
  }
  std::vector<Row> rows = sampled_rows(j, w, kind == "lhs", cap);
  return rows;
}

// One path component: a key, or an index/label in brackets.
struct PathPart {
  std::string key;
  bool bracket = false;
};

std::vector<PathPart> split_path(const std::string& path, const std::string& where) {
  if (json_path_depth(path) > size_t(kMaxJsonDepth))
    throw Error(where, "path nested deeper than " + std::to_string(kMaxJsonDepth) +
                           " levels (the limit for any fovsim input)");
  std::vector<PathPart> parts;
  size_t i = 0;
  while (i < path.size()) {
    if (path[i] == '[') {
      size_t close = path.find(']', i);
      if (close == std::string::npos || close == i + 1)
        throw Error(where, "bad path \"" + path + "\": missing or empty [...]");
      parts.push_back({path.substr(i + 1, close - i - 1), true});
      i = close + 1;
      if (i < path.size() && path[i] == '.') ++i;
    } else {
      size_t j = path.find_first_of(".[", i);
      std::string k = path.substr(i, j == std::string::npos ? std::string::npos : j - i);
      if (k.empty()) throw Error(where, "bad path \"" + path + "\": empty key");
      parts.push_back({k, false});
      if (j == std::string::npos) break;
      i = path[j] == '.' ? j + 1 : j;
      if (path[j] == '.' && i == path.size())
        throw Error(where, "bad path \"" + path + "\": trailing '.'");
    }
  }
  if (parts.empty()) throw Error(where, "empty config path");
  return parts;
}

bool all_digits(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

}  // namespace

void check_plan_columns(const SweepPlan& plan, const ResultTable& summary, bool search_only) {
  if (summary.rows().empty()) return;
  const std::vector<std::string> num = summary.numeric_columns(), text = summary.text_columns();
  const std::set<std::string> nums(num.begin(), num.end()), texts(text.begin(), text.end());
  const std::string W = plan.file.empty() ? "sweep" : plan.file + ": sweep";
  auto list = [](const std::vector<std::string>& cols) {
    std::string l;
    for (auto& c : cols) l += (l.empty() ? "" : ", ") + c;
    return l;
  };
  // A number to optimise or bound: a numeric column.
  auto numeric = [&](const std::string& col, const std::string& where) {
    if (nums.count(col)) return;
    throw Error(where, "no numeric column \"" + printable(col) +
                           "\" in the cells' summary (columns: " + list(num) +
                           "; results/README.md; is the metric enabled?)");
  };
  // A grouping: any column.
  auto any = [&](const std::string& col, const std::string& where) {
    if (nums.count(col) || texts.count(col)) return;
    std::vector<std::string> all = text;
    all.insert(all.end(), num.begin(), num.end());
    throw Error(where, "no column \"" + printable(col) +
                           "\" in the cells' summary (columns: " + list(all) + ")");
  };
  if (!search_only) {
    for (size_t i = 0; i < plan.objectives.size(); ++i)
      numeric(plan.objectives[i].column, W + ".objectives[" + std::to_string(i) + "]");
    // group_by's default ["gpu"] is not checked (a run costed for no GPU has no gpu column).
    const std::vector<std::string> def_group{"gpu"};
    if (plan.pareto_group_by != def_group)
      for (auto& g : plan.pareto_group_by) any(g, W + ".pareto.group_by");
    if (plan.iso.enabled()) {
      numeric(plan.iso.column, W + ".iso_budget.column");
      if (plan.iso.quality_given)
        for (auto& q : plan.iso.quality) numeric(q, W + ".iso_budget.quality");
      if (plan.iso.group_by != def_group)
        for (auto& g : plan.iso.group_by) any(g, W + ".iso_budget.group_by");
    }
  }
  if (plan.search.enabled()) {
    const SearchSpec& sp = plan.search;
    numeric(sp.objective.column,
            W + ".search." + (sp.objective.maximize ? "maximize" : "minimize"));
    for (const SearchConstraint& c : sp.constraints)
      numeric(c.column, W + ".search.subject_to." + c.column);
  }
}

double tidy(double v) {
  if (!std::isfinite(v) || v == 0) return v;
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return std::strtod(buf, nullptr);
}

std::string SweepCell::id() const {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%04d", index);
  return std::string(buf) + "-" + hash;
}

std::vector<Json> axis_values(const Json& spec, const std::string& where) {
  std::vector<Json> out;
  if (spec.is_array()) {
    for (auto& v : spec) out.push_back(v.is_number_float() ? number_json(v.get<double>()) : v);
  } else if (spec.is_object() && spec.contains("values")) {
    only_keys(spec, where, {"values"});
    return axis_values(spec["values"], key_where(where, "values"));
  } else if (spec.is_object()) {
    only_keys(spec, where, {"from", "to", "step", "count"});
    double a = num_of(spec, where, "from"), b = num_of(spec, where, "to");
    if (spec.contains("step") == spec.contains("count"))
      throw Error(where,
                  "a range needs exactly one of \"step\" or \"count\": {\"from\": a, \"to\": b, "
                  "\"step\": s}");
    if (spec.contains("step")) {
      double s = num_of(spec, where, "step");
      if (s == 0 || (b - a) * s < 0)
        throw Error(key_where(where, "step"),
                    "step " + std::to_string(s) + " never reaches \"to\" from \"from\"");
      double n = std::floor((b - a) / s + 1e-9);
      if (n > 1e6) throw Error(where, "range has more than a million values");
      for (int64_t k = 0; k <= int64_t(n); ++k) out.push_back(number_json(a + double(k) * s));
      distinct_after_rounding(out, where);
    } else {
      double c = num_of(spec, where, "count");
      if (c < 1 || c != std::floor(c) || c > 1e6)
        throw Error(key_where(where, "count"), "expected an integer >= 1");
      int n = int(c);
      for (int k = 0; k < n; ++k)
        out.push_back(number_json(n == 1 ? a : a + (b - a) * double(k) / double(n - 1)));
      distinct_after_rounding(out, where);
    }
  } else {
    throw Error(
        where,
        "expected an array of values or a range {\"from\": a, \"to\": b, \"step\": s}, got " +
            describe_json(spec));
  }
  if (out.empty()) throw Error(where, "empty axis (no values)");
  return out;
}

std::string apply_assignment(Json& doc, const std::string& path, const Json& value,
                             const std::string& where) {
  auto parts = split_path(path, where);
  Json* node = &doc;
  std::string concrete;
  for (size_t i = 0; i < parts.size(); ++i) {
    auto& p = parts[i];
    if (!p.bracket) {
      if (!node->is_object() && !node->is_null())
        throw Error(where, "\"" + concrete + "\" is not an object, cannot set \"" + path + "\"");
      concrete += (concrete.empty() ? "" : ".") + p.key;
      node = &(*node)[p.key];
      continue;
    }
    if (!node->is_array())
      throw Error(where, "\"" + concrete + "\" is not an array, cannot set \"" + path + "\"");
    size_t idx = 0;
    if (all_digits(p.key)) {
      // Compared as text first: an index with more digits than any size_t is simply absent.
      idx = p.key.size() > 9 ? size_t(-1) : size_t(std::stoul(p.key));
      if (idx >= node->size())
        throw Error(where, "\"" + concrete + "\" has no element [" + p.key + "] (it has " +
                               std::to_string(node->size()) + ")");
    } else {
      // Method-scoped form: the element whose "label" (or, without a label, "method") matches.
      std::vector<size_t> hits;
      std::string names;
      for (size_t k = 0; k < node->size(); ++k) {
        const Json& e = (*node)[k];
        if (!e.is_object()) continue;
        std::string lab =
            e.contains("label") && e["label"].is_string()     ? e["label"].get<std::string>()
            : e.contains("method") && e["method"].is_string() ? e["method"].get<std::string>()
                                                              : "";
        names += (names.empty() ? "" : ", ") + lab;
        if (lab == p.key) hits.push_back(k);
      }
      if (hits.empty())
        throw Error(where, "no entry of \"" + concrete + "\" has label \"" + p.key +
                               "\" (labels: " + names + ")");
      if (hits.size() > 1)
        throw Error(where, "several entries of \"" + concrete + "\" are called \"" + p.key +
                               "\"; give them labels");
      idx = hits[0];
    }
    concrete += "[" + std::to_string(idx) + "]";
    node = &(*node)[idx];
  }
  *node = value;
  return concrete;
}

std::string SearchConstraint::describe() const {
  if (std::isfinite(min) && std::isfinite(max))
    return format_number(min) + " <= " + column + " <= " + format_number(max);
  if (std::isfinite(min)) return column + " >= " + format_number(min);
  return column + " <= " + format_number(max);
}

std::vector<SearchSpec> SearchSpec::per_method() const {
  if (methods.empty()) return {*this};
  std::vector<SearchSpec> out;
  for (size_t i = 0; i < methods.size(); ++i) {
    SearchSpec s = *this;
    s.methods.clear();
    s.space = methods[i].space;
    s.select_label = methods[i].label;
    s.seed = seed + 1000003 * uint64_t(i);
    out.push_back(std::move(s));
  }
  return out;
}

double SearchSpec::violation(const std::vector<double>& values) const {
  return violation(values, {});
}

double SearchSpec::violation(const std::vector<double>& values,
                             const std::vector<double>& margins) const {
  double v = 0;
  for (size_t i = 0; i < constraints.size(); ++i) {
    const double x = i < values.size() ? values[i] : NAN;
    const double m = i < margins.size() ? margins[i] : 0.0;
    if (std::isnan(x)) return INFINITY;
    v += std::max(0.0, x + m - constraints[i].max) + std::max(0.0, constraints[i].min - (x - m));
  }
  return v;
}

namespace {

// Stages of expand_sweep: the sweep's blocks, objectives, pareto, iso_budget and search, then
// the cells (the blocks' cartesian product applied to the base config).

std::vector<std::vector<Row>> parse_blocks(const Json& sw, const std::string& W, double cap) {
  std::vector<std::vector<Row>> blocks;
  int direct = 0;
  for (auto& k : kBlockKinds)
    if (sw.contains(k)) {
      ++direct;
      blocks.push_back(block_rows(Json{{k, sw[k]}}, W, cap));
    }
  if (direct > 1 || (direct && sw.contains("axes")))
    throw Error(W,
                "give one block directly, or several under \"axes\": [...] (their order is the "
                "loop order)");
  if (sw.contains("axes")) {
    const Json& ax = sw["axes"];
    if (!ax.is_array() || ax.empty())
      throw Error(W + ".axes", "expected a non-empty array of blocks");
    for (size_t i = 0; i < ax.size(); ++i)
      blocks.push_back(block_rows(ax[i], W + ".axes[" + std::to_string(i) + "]", cap));
  }
  return blocks;
}

// Objectives: [{"minimize": "est_ms_total"}, {"maximize": "fpsnr"}].
std::vector<Objective> parse_objectives(const Json& ob, const std::string& w) {
  if (!ob.is_array())
    throw Error(
        w, "expected an array like [{\"minimize\": \"est_ms_total\"}, {\"maximize\": \"fpsnr\"}]");
  std::vector<Objective> out;
  for (size_t i = 0; i < ob.size(); ++i) {
    std::string wi = w + "[" + std::to_string(i) + "]";
    if (!ob[i].is_object() || ob[i].size() != 1 || !ob[i].begin().value().is_string() ||
        (ob[i].begin().key() != "minimize" && ob[i].begin().key() != "maximize"))
      throw Error(wi, "expected {\"minimize\": \"column\"} or {\"maximize\": \"column\"}");
    out.push_back({ob[i].begin().value().get<std::string>(), ob[i].begin().key() == "maximize"});
  }
  return out;
}

// An array of column names (pareto.group_by, iso_budget.quality and .group_by).
std::vector<std::string> column_names(const Json& j, const std::string& w, bool non_empty) {
  if (!j.is_array() || (non_empty && j.empty()))
    throw Error(w, non_empty ? "expected a non-empty array of column names"
                             : "expected an array of column names");
  std::vector<std::string> out;
  for (auto& c : j) {
    if (!c.is_string()) throw Error(w, "expected column names (strings)");
    out.push_back(c.get<std::string>());
  }
  return out;
}

std::vector<std::string> parse_pareto(const Json& p, const std::string& w) {
  if (!p.is_object()) throw Error(w, "expected an object {\"group_by\": [...]}");
  only_keys(p, w, {"group_by"});
  if (!p.contains("group_by")) return {"gpu"};
  return column_names(p["group_by"], w + ".group_by", false);
}

IsoBudgetSpec parse_iso_budget(Params& ip, const std::string& w) {
  const Json& ib = ip.json();
  if (!ib.is_object()) throw Error(w, "expected an object");
  only_keys(ib, w, {"column", "budgets", "tolerance", "quality", "group_by"});
  IsoBudgetSpec iso = iso_budget_table().read(ip);
  if (!ib.contains("budgets")) throw Error(w, "missing \"budgets\"");
  for (auto& v : axis_values(ib["budgets"], w + ".budgets")) {
    if (!v.is_number()) throw Error(w + ".budgets", "budgets must be numbers");
    iso.budgets.push_back(v.get<double>());
  }
  iso.quality = {"fpsnr", "ssim", "psnr"};
  if (ib.contains("quality")) {
    iso.quality_given = true;
    iso.quality = column_names(ib["quality"], w + ".quality", true);
  }
  iso.group_by = {"gpu"};
  if (ib.contains("group_by")) iso.group_by = column_names(ib["group_by"], w + ".group_by", false);
  return iso;
}

// subject_to: {"column": {"min": value, "max": value}, ...}, in column-name order.
std::vector<SearchConstraint> parse_constraints(const Json& c, const std::string& cw) {
  const char* eg =
      "expected {\"column\": {\"min\": value, \"max\": value}, ...}, e.g. "
      "{\"fvvdp_jod_fl\": {\"min\": 9.5}, \"headroom_ms\": {\"min\": 0}}";
  if (!c.is_object() || c.empty()) throw Error(cw, eg);
  std::vector<SearchConstraint> out;
  for (auto it = c.begin(); it != c.end(); ++it) {
    const std::string kw = cw + "." + it.key();
    if (!it.value().is_object() || (!it.value().contains("max") && !it.value().contains("min")))
      throw Error(kw, eg);
    only_keys(it.value(), kw, {"min", "max"});
    SearchConstraint k;
    k.column = it.key();
    if (it.value().contains("min")) k.min = num_of(it.value(), kw, "min");
    if (it.value().contains("max")) k.max = num_of(it.value(), kw, "max");
    if (k.min > k.max)
      throw Error(kw, "min " + format_number(k.min) + " is above max " + format_number(k.max));
    out.push_back(k);
  }
  return out;
}

SearchSpec parse_search(Params& sp, const std::string& w) {
  const Json& s = sp.json();
  if (!s.is_object()) throw Error(w, "expected an object");
  only_keys(s, w,
            {"space", "methods", "maximize", "minimize", "subject_to", "label", "evaluations",
             "batch", "seed", "p_fit"});
  SearchSpec out;
  auto parse_space = [&](const Json& space, const std::string& sw) {
    std::vector<SearchDim> dims;
    for (auto& [path, sv] : ordered_axes(space, sw)) {
      Dim d = parse_dim(path, sv.first, sv.second);
      if (!d.choices.empty())
        throw Error(sv.second, "a search dimension must be a range {\"from\": a, \"to\": b}");
      dims.push_back({path, d.lo, d.hi, d.step, d.log, d.integer, d.where});
    }
    return dims;
  };
  if (s.contains("methods")) {  // a method axis: {"label": {"space": {...}}, ...}
    const char* eg =
        "expected {\"label\": {\"space\": {\"config.path\": {\"from\": a, \"to\": b}}}, ...}, "
        "one entry per method entry to search";
    if (s.contains("space") || s.contains("label"))
      throw Error(w + ".methods",
                  "give either \"methods\" (one space per method entry) or \"space\" and "
                  "\"label\"");
    const Json& ms = s["methods"];
    if (!ms.is_object() || ms.size() < 2)
      throw Error(w + ".methods", std::string(eg) + " (at least two: one method needs no axis)");
    for (auto it = ms.begin(); it != ms.end(); ++it) {
      const std::string mw = w + ".methods." + it.key();
      if (it.key().empty()) throw Error(mw, "an empty label");
      if (!it.value().is_object() || !it.value().contains("space")) throw Error(mw, eg);
      only_keys(it.value(), mw, {"space"});
      out.methods.push_back({it.key(), parse_space(it.value()["space"], mw + ".space")});
    }
  } else {
    if (!s.contains("space"))
      throw Error(w, "missing \"space\": {\"config.path\": {\"from\": a, \"to\": b}, ...}");
    out.space = parse_space(s["space"], w + ".space");
  }
  if (s.contains("maximize") == s.contains("minimize"))
    throw Error(w, "give exactly one of \"maximize\" or \"minimize\": \"column\"");
  const Json& oc = s.contains("maximize") ? s["maximize"] : s["minimize"];
  if (!oc.is_string()) throw Error(w, "the objective must be a column name");
  out.objective = {oc.get<std::string>(), s.contains("maximize")};
  if (s.contains("subject_to"))
    out.constraints = parse_constraints(s["subject_to"], w + ".subject_to");
  search_table().read_into(sp, out);  // label, evaluations, batch, seed, p_fit
  if (out.fit_level > 0) {            // the budget decision at a stated level (sim/cost/budget.h)
    for (const SearchConstraint& k : out.constraints)
      if (k.column == "p_fit")
        throw Error(w + ".subject_to.p_fit",
                    "give the level once: as \"p_fit\": " + format_number(out.fit_level) +
                        " or as this constraint");
    SearchConstraint k;
    k.column = "p_fit";
    k.min = out.fit_level;
    out.constraints.push_back(k);
  }
  return out;
}

// The cells: the blocks' cartesian product (first block slowest), each applied to the base
// config and hashed.
void expand_cells(SweepPlan& plan, const std::vector<std::vector<Row>>& blocks, double cap,
                  const std::string& W) {
  std::vector<Row> rows{Row{}};
  for (auto& b : blocks) {
    if (double(rows.size()) * double(b.size()) > cap)
      too_many_cells(W, double(rows.size()) * double(b.size()), cap);
    std::vector<Row> next;
    next.reserve(rows.size() * b.size());
    for (auto& r : rows)
      for (auto& br : b) {
        Row n = r;
        n.insert(n.end(), br.begin(), br.end());
        next.push_back(std::move(n));
      }
    rows = std::move(next);
  }
  std::set<std::string> seen_paths;
  std::string all;
  for (size_t i = 0; i < rows.size(); ++i) {
    SweepCell c;
    c.index = int(i);
    c.assign = rows[i];
    c.doc = plan.base;
    std::set<std::string> set_here;
    for (auto& a : c.assign) {
      std::string concrete = apply_assignment(c.doc, a.path, a.value, a.where);
      if (!set_here.insert(concrete).second)
        throw Error(a.where, "\"" + a.path + "\" is set by two axes of the same sweep (it is " +
                                 concrete + ")");
      if (seen_paths.insert(a.path).second) plan.axis_paths.push_back(a.path);
    }
    // The reference cache's settings (`cache`) change where references are kept, not a
    // cell's results: they are not part of its hash, so changing them resumes a sweep.
    Json hashed = c.doc;
    if (hashed.is_object()) hashed.erase("cache");
    c.hash = short_hash(hashed.dump());
    all += c.hash;
    plan.cells.push_back(std::move(c));
  }
  plan.hash = short_hash(all);
}

}  // namespace

SweepPlan expand_sweep(const LoadedConfig& cfg) {
  SweepPlan plan;
  plan.file = cfg.file;
  plan.base_dir = cfg.base_dir;
  if (!cfg.doc.is_object())
    throw Error(cfg.file.empty() ? "sweep" : cfg.file,
                "a config must be a JSON object, got " + describe_json(cfg.doc));
  plan.base = cfg.doc;
  plan.base.erase("sweep");
  plan.name = plan.base.contains("name") && plan.base["name"].is_string()
                  ? plan.base["name"].get<std::string>()
                  : fs::path(cfg.file).stem().string();
  const std::string W = cfg.file.empty() ? "sweep" : cfg.file + ": sweep";
  std::vector<std::vector<Row>> blocks;
  double cap = kDefaultMaxCells;
  plan.pareto_group_by = {"gpu"};
  if (cfg.doc.contains("sweep")) {
    const Json& sw = cfg.doc["sweep"];
    if (!sw.is_object()) throw Error(W, "expected an object, got " + describe_json(sw));
    only_keys(sw, W,
              {"axes", "grid", "list", "zip", "random", "lhs", "objectives", "pareto", "iso_budget",
               "search", "comment", "max_cells"});
    Params sp(sw, cfg.file, "sweep");
    cap = sweep_table().read(sp).max_cells;
    blocks = parse_blocks(sw, W, cap);
    if (sw.contains("objectives"))
      plan.objectives = parse_objectives(sw["objectives"], W + ".objectives");
    if (sw.contains("pareto")) plan.pareto_group_by = parse_pareto(sw["pareto"], W + ".pareto");
    if (sw.contains("iso_budget")) {
      Params ip = sp.child("iso_budget");
      plan.iso = parse_iso_budget(ip, W + ".iso_budget");
    }
    if (sw.contains("search")) {
      Params ss = sp.child("search");
      plan.search = parse_search(ss, W + ".search");
      // The cells decide fits_budget at the search's level too (one rule per search); a base
      // that states another budget.p_fit is a contradiction.
      if (plan.search.fit_level > 0) {
        Json& b = plan.base["budget"];
        if (b.is_object() && b.contains("p_fit") && b["p_fit"] != Json(plan.search.fit_level))
          throw Error(W + ".search.p_fit", format_number(plan.search.fit_level) +
                                               " differs from the config's "
                                               "budget.p_fit " +
                                               b["p_fit"].dump() + ": give the level once");
        if (b.is_null()) b = Json::object();
        if (b.is_object()) b["p_fit"] = plan.search.fit_level;
      }
    }
  }
  expand_cells(plan, blocks, cap, W);
  check_plan_column_names(plan);  // before any cell runs (plan_columns.cpp)
  return plan;
}

const ParamTable<SweepKeys>& sweep_table() {
  using K = SweepKeys;
  static const auto t =
      ParamTable<K>()
          .documented(
              "grid", "object", "", "", "",
              "`{\"config.path\": values, ...}`: every combination (cartesian product, "
              "first axis slowest); values: an array, `{\"values\": [...]}`, "
              "`{\"from\", \"to\", \"step\"}` (inclusive) or `{\"from\", \"to\", \"count\"}`")
          .documented("list", "array of objects", "", "", "",
                      "explicit cells, each an object of assignments")
          .documented("zip", "object", "", "", "", "axes of equal length advancing together")
          .documented(
              "random", "object", "", "", "",
              "`{\"count\": n, \"seed\": s, \"axes\": {\"path\": {\"from\", \"to\"[, \"step\", "
              "\"log\", \"integer\"]} or choices}}`: n uniform samples (seed an integer in "
              "[0, 2^53], default 1)")
          .documented("lhs", "object", "", "", "",
                      "as `random`, a Latin hypercube (McKay et al. 1979): each axis's n strata "
                      "used once")
          .documented("axes", "array of blocks", "", "", "",
                      "several of the blocks above, combined as a cartesian product (first "
                      "block slowest); one block may also be given directly")
          .documented("objectives", "array", "", "", "",
                      "`[{\"minimize\": \"est_ms_total\"}, {\"maximize\": \"fpsnr\"}]`: the "
                      "summary columns of the Pareto front")
          .documented("pareto", "object", "", "", "",
                      "`{\"group_by\": [columns]}`: one front per group (default `[\"gpu\"]`)")
          .documented("iso_budget", "object", "", "", "",
                      "best cell per method within each budget: `sweep.iso_budget` below")
          .documented("search", "object", "", "", "",
                      "per-context ask/tell search: `sweep.search` below")
          .documented("comment", "any", "", "", "", "ignored")
          .integer("max_cells", int(kDefaultMaxCells), Range::closed(1, kMaxMaxCells),
                   &K::max_cells)
          .doc("",
               "most cells the sweep may expand to, counted before any cell is built (each "
               "block's size and their product)");
  return t;
}

const ParamTable<IsoBudgetSpec>& iso_budget_table() {
  using K = IsoBudgetSpec;
  static const auto t =
      ParamTable<K>()
          .text("column", nullptr, {}, &K::column)
          .required()
          .doc("Ye et al. 2022 §5.1",
               "the budgeted summary column, e.g. `shaded_fraction` or `est_ms_total`")
          .documented("budgets", "array or range", "required", "", "",
                      "the budgets: an array, `{\"values\": [...]}`, `{\"from\", \"to\", "
                      "\"step\"}` or `{\"from\", \"to\", \"count\"}`")
          .number("tolerance", 0.0, Range::any(), &K::tolerance)
          .doc("",
               "relative slack: a cell is within a budget when value <= budget x (1 + tolerance)")
          .documented("quality", "array of strings", "`[\"fpsnr\", \"ssim\", \"psnr\"]`", "", "",
                      "quality columns reported; the first ranks (columns absent from the "
                      "default list are skipped)")
          .documented("group_by", "array of strings", "`[\"gpu\"]`", "", "",
                      "one comparison per group");
  return t;
}

const ParamTable<SearchSpec>& search_table() {
  using K = SearchSpec;
  static const auto t =
      ParamTable<K>()
          .documented("space", "object", "required (or `methods`)", "", "",
                      "`{\"config.path\": {\"from\": a, \"to\": b[, \"step\", \"log\", "
                      "\"integer\"]}, ...}`: the searched dimensions (ranges only)")
          .documented("methods", "object", "", "", "",
                      "a method axis instead of `space` and `label`: `{\"label\": {\"space\": "
                      "{...}}, ...}`, two or more method entries each searched in its own space "
                      "(`evaluations` each), then the methods' winners compared (docs/sweeps.md "
                      "\"Searching across methods\")")
          .documented("maximize", "string", "", "", "",
                      "the summary column to maximize (exactly one of `maximize` / `minimize`)")
          .documented("minimize", "string", "", "", "", "the summary column to minimize")
          .documented("subject_to", "object", "", "", "",
                      "`{\"column\": {\"min\": a, \"max\": b}, ...}`: constraints on summary "
                      "columns, all of which must hold")
          .text("label", nullptr, {}, &K::select_label)
          .optional()
          .doc("", "the method label whose summary row is scored (default: the first row)")
          .integer("evaluations", 32, Range::closed(1, 100000), &K::evaluations)
          .doc("", "cells evaluated per context")
          .integer("batch", 8, Range::closed(1, 1024), &K::batch)
          .doc("", "cells proposed at once (run side by side)")
          .number("p_fit", 0, fit_level_range(), &K::fit_level)
          .optional()
          .shown("absent")
          .doc("",
               "feasible only where the probability that the p95 frame fits the budget "
               "(`p_fit`, docs/cost_model.md \"Budget decisions\") reaches this level: the "
               "constraint `p_fit >= level`, and the cells' `budget.p_fit` (so `fits_budget` "
               "agrees). The budget decision to use instead of `headroom_ms >= 0`, which is "
               "the point estimate's")
          .number("seed", 1, Range::closed(0, 9007199254740992.0), &K::seed)
          .shown("1", "[0, 2^53], an integer")
          .doc("", "seed of the searcher")
          .validate([](const K&, Params& p) {
            if (p.has("seed"))
              check_integer(p.where("seed"), p.json()["seed"].get<double>(),
                            Range::closed(0, 9007199254740992.0));
          });
  return t;
}

namespace {

// The search's dimensions and label, checked on every context before any evaluation as the
// sweep's axes are (validate_cells): each dimension applied at its two ends (an unknown
// parameter, a label no method entry has, or an end out of the parameter's range fails with
// the dimension's location), and search.label must name a method entry of every context.
void validate_search(const SweepPlan& plan) {
  if (!plan.search.enabled()) return;
  for (const SearchSpec& sp : plan.search.per_method()) {
    SweepPlan probe;
    probe.file = plan.file;
    for (auto& ctx : plan.cells) {
      for (double end : {0.0, 1.0}) {
        SweepCell c = ctx;
        for (auto& d : sp.space) {
          double v = end == 0.0 ? d.lo : d.hi;
          if (d.integer) v = std::round(v);
          const Json value = d.integer ? Json(std::llround(v)) : Json(v);
          apply_assignment(c.doc, d.path, value, d.where);
          c.assign.push_back({d.path, value, d.where});
        }
        probe.cells.push_back(std::move(c));
      }
      if (sp.select_label.empty()) continue;
      std::string labels;
      bool found = false;
      if (ctx.doc.contains("methods") && ctx.doc["methods"].is_array())
        for (auto& m : ctx.doc["methods"]) {
          if (!m.is_object()) continue;
          const std::string l =
              m.contains("label") && m["label"].is_string()     ? m["label"].get<std::string>()
              : m.contains("method") && m["method"].is_string() ? m["method"].get<std::string>()
                                                                : "";
          found = found || l == sp.select_label;
          labels += (labels.empty() ? "" : ", ") + l;
        }
      if (!found)
        throw Error((plan.file.empty() ? "" : plan.file + ": ") +
                        (plan.search.methods.empty() ? "sweep.search.label"
                                                     : "sweep.search.methods." + sp.select_label),
                    "no method entry has label \"" + printable(sp.select_label) + "\"" +
                        (plan.cells.size() > 1 ? " in context " + ctx.id() : std::string()) +
                        " (labels: " + (labels.empty() ? "none" : labels) + ")");
    }
    validate_cells(probe);
  }
}

}  // namespace

void validate_cells(const SweepPlan& plan) {
  validate_search(plan);
  std::map<std::string, std::vector<std::string>> known;  // method -> parameter names
  for (auto& e : method_table()) {
    auto& v = known[e.name];
    for (auto& p : e.params()) v.push_back(p.name);
  }
  std::set<std::string> built;
  for (auto& c : plan.cells) {
    // An axis that targets a method parameter must name one the method declares.
    for (auto& a : c.assign) {
      Json probe = c.doc;
      std::string concrete = apply_assignment(probe, a.path, a.value, a.where);
      if (concrete.rfind("methods[", 0) != 0) continue;
      size_t close = concrete.find(']');
      if (close + 1 >= concrete.size() || concrete[close + 1] != '.') continue;
      size_t mi = std::stoul(concrete.substr(8, close - 8));
      std::string key = concrete.substr(close + 2);
      key = key.substr(0, key.find_first_of(".["));
      // `lighting.<key>` (docs/methods.md): checked by make_method below with its full path.
      if (key == "method" || key == "label" || key == "lighting") continue;
      const Json& m = c.doc["methods"][mi];
      std::string mname =
          m.contains("method") && m["method"].is_string() ? m["method"].get<std::string>() : "";
      auto it = known.find(mname);
      if (it == known.end()) continue;  // make_method below reports the unknown method
      if (std::find(it->second.begin(), it->second.end(), key) == it->second.end()) {
        std::string names;
        for (auto& n : it->second) names += (names.empty() ? "" : ", ") + n;
        throw Error(a.where, "unknown parameter \"" + key + "\" for method \"" + mname +
                                 "\" (parameters: " + (names.empty() ? "none" : names) + ")");
      }
    }
    // Construct each distinct method block once: range and type errors surface now.
    if (!c.doc.contains("methods") || !c.doc["methods"].is_array()) continue;
    const Json& ms = c.doc["methods"];
    for (size_t i = 0; i < ms.size(); ++i) {
      std::string key = ms[i].dump();
      if (!built.insert(key).second || !ms[i].is_object()) continue;
      Json mj = ms[i];
      std::string mname =
          mj.contains("method") && mj["method"].is_string() ? mj["method"].get<std::string>() : "";
      mj.erase("method");
      mj.erase("label");
      try {
        Params mp(mj, plan.file, "methods[" + std::to_string(i) + "]");
        make_method(mname, mp);
      } catch (const Error& e) {
        std::string how;
        for (auto& a : c.assign) how += (how.empty() ? "" : ", ") + a.path + "=" + a.value.dump();
        throw Error(e.where(), e.message() + " (in sweep cell " + std::to_string(c.index) +
                                   (how.empty() ? "" : ": " + how) + ")");
      }
    }
  }
}

}  // namespace fovsim
