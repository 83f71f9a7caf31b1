#include "sim/experiment/summary.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/stats.h"
#include "sim/experiment/intervals.h"
#include "sim/metrics/registry.h"

namespace fovsim {

namespace {

// Which estimator each interval of a summary row came from, and why the undefined ones are
// undefined: the row's `ci_method` and `ci_missing` text columns.
struct IntervalLog {
  std::vector<std::string> kinds;                            // in first-use order
  std::vector<std::pair<std::string, std::string>> missing;  // (why, columns)
  void add(const std::string& column, const MeanInterval& mi) {
    if (mi.kind != IntervalKind::none) {
      const std::string k = interval_kind_name(mi.kind);
      if (std::find(kinds.begin(), kinds.end(), k) == kinds.end()) kinds.push_back(k);
      return;
    }
    if (mi.n == 0) return;  // no finite value: the column has no mean for this config either
    for (auto& [why, cols] : missing)  // a sequence metric's column is seen twice: once
      if ((" " + cols + " ").find(" " + column + " ") != std::string::npos) return;
    for (auto& [why, cols] : missing)
      if (why == mi.why) {
        cols += " " + column;
        return;
      }
    missing.emplace_back(mi.why, column);
  }
  void write(ResultRow& s) const {
    std::string k, m;
    for (auto& x : kinds) k += (k.empty() ? "" : " ") + x;
    for (auto& [why, cols] : missing) m += (m.empty() ? "" : "; ") + cols + ": " + why;
    s.set_text("ci_method", k);
    s.set_text("ci_missing", m);
  }
};

}  // namespace

ResultTable summarize(const ResultTable& frames, double budget_ms, const FitRule* rule) {
  const FitRule no_intervals;
  const FitRule& fit = rule ? *rule : no_intervals;
  std::vector<std::string> order;
  std::map<std::string, std::vector<const ResultRow*>> groups;
  for (auto& r : frames.rows()) {
    const std::string* id = r.text_of("config_id");
    std::string key = id ? *id : "";
    if (!groups.count(key)) order.push_back(key);
    groups[key].push_back(&r);
  }
  auto cols = frames.numeric_columns();
  ResultTable t;
  for (auto& key : order) {
    auto& rows = groups[key];
    ResultRow s;
    for (auto& kv : rows.front()->text) s.set_text(kv.first, kv.second);
    s.set("frames", double(rows.size()));
    IntervalLog ivlog;
    for (auto& c : cols) {
      if (c == "frame" || c == "t" || c == "gaze_x" || c == "gaze_y") continue;
      // Mean of the finite values; a column that is +inf on every frame (PSNR of an exact
      // match) stays inf rather than becoming nan.
      double sum = 0;
      size_t n = 0, pos_inf = 0;
      std::vector<double> finite;  // frame order, for the batch-means interval
      for (auto* r : rows) {
        double v = r->get(c, NAN);
        if (std::isfinite(v)) {
          sum += v;
          ++n;
          finite.push_back(v);
        } else if (v > 0 && std::isinf(v)) {
          ++pos_inf;
        }
      }
      s.set(c, n ? sum / double(n) : (pos_inf ? INFINITY : NAN));
      // 95% half-width over the same finite values (sim/core/stats.h mean_interval: batch
      // means, the short-run interval below 20 frames; nan when undefined, `ci_missing` says why).
      if (has_interval(c)) {
        const MeanInterval mi = mean_interval(finite);
        s.set(c + "_ci95", mi.half_width);
        if (!(pos_inf && !n)) ivlog.add(c, mi);
      }
    }
    // Sequence-pooled metrics (sim/metrics/registry.h): the pooled value of the whole run and
    // its interval, the batch-means interval of the pooled column's mean mapped through the
    // metric's monotone map (asymmetric: `_lo`, `_hi`; `_ci95` is half the width).
    for (auto& d : metric_registry())
      for (const std::string suffix : {"", kFoveationLossSuffix}) {
        if (d.pooling != Pooling::sequence) continue;
        const std::string name = d.name + suffix;
        std::vector<double> q;
        bool present = false;
        for (auto* r : rows) {
          double v = r->get(d.pooled_column + suffix, NAN);
          present = present || !std::isnan(v);
          if (std::isfinite(v)) q.push_back(v);
        }
        if (!present) continue;
        MeanInterval ci = mean_interval(q);
        ivlog.add(name, ci);
        const double v = q.empty() ? NAN : d.from_mean(ci.mean);
        double a = d.from_mean(ci.lo()), b = d.from_mean(ci.hi());
        if (a > b) std::swap(a, b);
        s.set(name, v);
        s.set(name + "_ci95", 0.5 * (b - a));
        s.set(name + "_lo", a);
        s.set(name + "_hi", b);
      }
    ivlog.write(s);
    std::vector<double> tot;
    for (auto* r : rows) tot.push_back(r->get("est_ms_total", NAN));
    std::sort(tot.begin(), tot.end());
    auto pct = [&](double p) {
      if (tot.empty()) return double(NAN);
      double idx = p * double(tot.size() - 1);
      size_t lo = size_t(std::floor(idx)), hi = size_t(std::ceil(idx));
      return tot[lo] + (tot[hi] - tot[lo]) * (idx - double(lo));
    };
    s.set("est_ms_total_p50", pct(0.5));
    s.set("est_ms_total_p95", pct(0.95));
    s.set("est_ms_total_p99", pct(0.99));
    s.set("budget_ms", budget_ms);
    const std::string* gpu = rows.front()->text_of("gpu");
    const std::string gpu_name = gpu ? *gpu : "";
    const double p95 = pct(0.95);
    if (std::isfinite(p95)) {
      const BudgetDecision bd = fit.decide(gpu_name, p95, budget_ms);
      s.set("p_fit", bd.p_fit);
      s.set("fits_budget", bd.fits ? 1 : 0);
    } else {
      s.set("p_fit", NAN);
      s.set("fits_budget", 0);
    }
    s.set("fit_level", fit.level);
    s.set("fit_threshold_ms", fit_threshold_ms(fit.interval_of(gpu_name), budget_ms, fit.level));
    s.set("headroom_ms", budget_ms - p95);
    t.add(std::move(s));
  }
  return t;
}

}  // namespace fovsim

namespace fovsim {

std::vector<std::string> interval_notes(const ResultTable& summary) {
  // why -> (headline columns, config labels), in first-seen order
  std::vector<std::pair<std::string, std::pair<std::vector<std::string>, std::vector<std::string>>>>
      missing;
  std::vector<std::string> short_labels;
  auto add_unique = [](std::vector<std::string>& v, const std::string& x) {
    if (std::find(v.begin(), v.end(), x) == v.end()) v.push_back(x);
  };
  const std::vector<std::string>& shown = headline_metrics();
  for (const ResultRow& r : summary.rows()) {
    const std::string* id = r.text_of("label");
    if (!id) id = r.text_of("config_id");
    // Labels are user text: control bytes escaped before they reach a terminal.
    const std::string label = id ? escape_control(*id) : "?";
    const std::string* kinds = r.text_of("ci_method");
    if (kinds && kinds->find("short_run") != std::string::npos) add_unique(short_labels, label);
    const std::string* m = r.text_of("ci_missing");
    if (!m || m->empty()) continue;
    // "col col: why; col: why" (summarize's IntervalLog)
    size_t pos = 0;
    while (pos < m->size()) {
      size_t end = m->find("; ", pos);
      if (end == std::string::npos) end = m->size();
      const std::string seg = m->substr(pos, end - pos);
      pos = end + 2;
      const size_t colon = seg.find(": ");
      if (colon == std::string::npos) continue;
      const std::string why = seg.substr(colon + 2);
      std::vector<std::string> cols;
      size_t c0 = 0;
      const std::string list = seg.substr(0, colon);
      while (c0 <= list.size()) {
        size_t c1 = list.find(' ', c0);
        if (c1 == std::string::npos) c1 = list.size();
        const std::string c = list.substr(c0, c1 - c0);
        if (std::find(shown.begin(), shown.end(), c) != shown.end()) cols.push_back(c);
        c0 = c1 + 1;
      }
      if (cols.empty()) continue;
      auto it = std::find_if(missing.begin(), missing.end(),
                             [&](const auto& e) { return e.first == why; });
      if (it == missing.end()) {
        missing.push_back({why, {}});
        it = missing.end() - 1;
      }
      for (auto& c : cols) add_unique(it->second.first, c);
      add_unique(it->second.second, label);
    }
  }
  auto join = [](const std::vector<std::string>& v, size_t most) {
    std::string s;
    for (size_t i = 0; i < v.size() && i < most; ++i) s += (i ? ", " : "") + v[i];
    if (v.size() > most) s += ", ... (" + std::to_string(v.size()) + " in all)";
    return s;
  };
  std::vector<std::string> notes;
  for (auto& [why, e] : missing)
    notes.push_back("no 95% interval for " + join(e.first, 8) + " (" + join(e.second, 3) +
                    "): " + why + " (summary.csv ci_missing; docs/intervals.md)");
  if (!short_labels.empty())
    notes.push_back(
        "intervals over fewer than 20 frames are short-run t-intervals with an AR(1) effective "
        "sample size (" +
        join(short_labels, 3) +
        "; summary.csv ci_method short_run): indicative only, they undercover strongly "
        "correlated frames (docs/intervals.md)");
  return notes;
}

void mark_reference_floor(ResultTable& summary, const ResultTable& frames,
                          const std::function<const FloorValues*(const std::string&)>& floor_of) {
  std::map<std::string, std::vector<const ResultRow*>> by_config;
  for (auto& r : frames.rows()) {
    const std::string* id = r.text_of("config_id");
    by_config[id ? *id : ""].push_back(&r);
  }
  ResultTable out;
  for (const ResultRow& row : summary.rows()) {
    const std::string* id = row.text_of("config_id");
    const auto& rows = by_config[id ? *id : ""];
    std::string names;
    const std::string* label = row.text_of("label");
    const FloorValues* fp = floor_of(label ? *label : std::string());
    if (!fp) {
      out.add(ResultRow(row));
      continue;
    }
    const FloorValues& floor = *fp;
    for (auto& d : metric_registry()) {
      if (d.family) continue;
      const std::string col = d.pooling == Pooling::sequence ? d.pooled_column : d.name;
      auto f = floor.find(col);
      if (f == floor.end()) continue;
      std::vector<double> diff;
      bool exact = true;
      for (const ResultRow* r : rows) {
        auto it = f->second.find(int(r->get("frame", -1)));
        const double v = r->get(col, NAN);
        if (it == f->second.end() || !std::isfinite(v) || !std::isfinite(it->second)) continue;
        diff.push_back(v - it->second);
        exact = exact && std::fabs(v - it->second) <= 1e-9 * (1 + std::fabs(it->second));
      }
      if (diff.empty()) continue;
      const MeanInterval mi = batch_means_interval(diff);
      const bool at = std::isfinite(mi.half_width) ? std::fabs(mi.mean) <= mi.half_width : exact;
      if (at) names += (names.empty() ? "" : " ") + d.name;
    }
    ResultRow r = row;
    r.set_text("at_floor", names);
    out.add(std::move(r));
  }
  summary = std::move(out);
}

}  // namespace fovsim
