#include "sim/experiment/startup.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/core/error.h"
#include "sim/core/stats.h"

namespace fovsim {

namespace {

bool has(const ResultRow& r, const std::string& c) {
  for (auto& [k, v] : r.num)
    if (k == c) return true;
  return false;
}

std::string frames_word(int n) {
  return std::to_string(n) + (n == 1 ? " frame" : " frames");
}

std::string seconds_text(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f s", s);
  return b;
}

}  // namespace

ResultTable exclude_startup(const ResultTable& frames, const StartupPlan& plan,
                            StartupReport& report) {
  Json methods = Json::object(), metrics = Json::object();
  // Per config, in recorded order.
  std::vector<std::string> order;
  std::map<std::string, std::vector<const ResultRow*>> by_config;
  for (const ResultRow& r : frames.rows()) {
    const std::string* id = r.text_of("config_id");
    const std::string key = id ? *id : "";
    if (!by_config.count(key)) order.push_back(key);
    by_config[key].push_back(&r);
  }
  std::map<std::string, int> dropped_by_label;
  std::map<std::string, std::string> unsettled;
  ResultTable out;
  for (const std::string& key : order) {
    const auto& rows = by_config[key];
    const std::string* lp = rows.front()->text_of("label");
    const std::string label = lp ? *lp : key;
    auto mf = plan.method_frames.find(label);
    const int declared = mf == plan.method_frames.end() ? 0 : mf->second;
    int drop = std::max(0, declared - plan.warmup_rendered);
    if (plan.include || drop >= int(rows.size())) drop = 0;
    report.rows_dropped[key] = drop;
    if (declared > 0) dropped_by_label[label] = drop;
    for (size_t i = size_t(drop); i < rows.size(); ++i) {
      ResultRow r = *rows[i];
      for (const auto& m : plan.metrics) {
        const int settle = std::max(0, m.frames - plan.warmup_rendered);
        if (plan.include || settle == 0 || int(i) >= settle) continue;
        if (int(rows.size()) - settle < int(kCiShortMinSamples)) {
          unsettled[m.name] = "the run's " + frames_word(int(rows.size())) + " leave fewer than " +
                              std::to_string(kCiShortMinSamples) + " after " + m.name +
                              "'s settle time of " + frames_word(settle) + " (" +
                              seconds_text(m.seconds) + "): its mean includes the settling frames";
          continue;
        }
        for (const std::string& c : m.columns)
          if (has(r, c)) r.set(c, NAN);
      }
      out.add(std::move(r));
    }
  }
  for (auto& [label, n] : dropped_by_label) methods[label] = n;
  for (const auto& m : plan.metrics) {
    const int settle = std::max(0, m.frames - plan.warmup_rendered);
    const bool applied = !plan.include && settle > 0 && !unsettled.count(m.name);
    metrics[m.name] = Json{{"settle_frames", m.frames},
                           {"settle_s", m.seconds},
                           {"frames_excluded", applied ? settle : 0}};
    if (unsettled.count(m.name)) {
      metrics[m.name]["why_not"] = unsettled[m.name];
      report.unsettled.emplace_back(m.name, unsettled[m.name]);
    }
  }
  report.manifest = Json{{"excluded", !plan.include},
                         {"key", "frames.include_startup"},
                         {"warmup_rendered", plan.warmup_rendered},
                         {"methods", methods},
                         {"metrics", metrics}};
  // The notes: what was left out, and what could not be.
  if (plan.include) {
    bool any = false;
    for (auto& [l, n] : plan.method_frames) any = any || n > plan.warmup_rendered;
    for (const auto& m : plan.metrics) any = any || m.frames > plan.warmup_rendered;
    if (any)
      report.notes.push_back(
          "frames.include_startup is set: the means include the methods' warm-up and the "
          "metrics' settle frames (docs/intervals.md)");
    return out;
  }
  std::string what;
  for (auto& [label, n] : dropped_by_label)
    if (n > 0)  // labels are user text: control bytes escaped for the terminal
      what +=
          (what.empty() ? "" : ", ") + escape_control(label) + " " + frames_word(n) + " (warm-up)";
  for (const auto& m : plan.metrics) {
    const int settle = std::max(0, m.frames - plan.warmup_rendered);
    if (settle > 0 && !unsettled.count(m.name))
      what += (what.empty() ? "" : ", ") + m.name + " columns " + frames_word(settle) +
              " (settle time " + seconds_text(m.seconds) + ")";
  }
  if (!what.empty())
    report.notes.push_back("start-up frames left out of the means: " + what +
                           "; frames.csv keeps them, frames.include_startup=true keeps them in "
                           "the means (manifest.json startup)");
  // A metric left unsettled is named by interval_notes (its intervals are undefined).
  return out;
}

void mark_startup(ResultTable& summary, const StartupReport& report, const StartupPlan& plan) {
  ResultTable out;
  for (const ResultRow& row : summary.rows()) {
    ResultRow r = row;
    const std::string* id = r.text_of("config_id");
    auto it = report.rows_dropped.find(id ? *id : "");
    r.set("startup_frames", it == report.rows_dropped.end() ? 0.0 : double(it->second));
    for (auto& [name, why] : report.unsettled)
      for (const auto& m : plan.metrics) {
        if (m.name != name) continue;
        std::string cols;
        for (const std::string& c : m.columns) {
          // Only intervals that were defined (a column already missing keeps its reason).
          if (!has(r, c + "_ci95") || std::isnan(r.get(c + "_ci95", NAN))) continue;
          r.set(c + "_ci95", NAN);
          if (has(r, c + "_lo")) r.set(c + "_lo", NAN);
          if (has(r, c + "_hi")) r.set(c + "_hi", NAN);
          cols += (cols.empty() ? "" : " ") + c;
        }
        if (cols.empty()) continue;
        const std::string* prev = r.text_of("ci_missing");
        std::string m2 = prev ? *prev : "";
        m2 += (m2.empty() ? "" : "; ") + cols + ": " + why;
        r.set_text("ci_missing", m2);
      }
    out.add(std::move(r));
  }
  summary = std::move(out);
}

}  // namespace fovsim
