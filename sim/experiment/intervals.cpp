#include "sim/experiment/intervals.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>

#include "sim/core/error.h"
#include "sim/core/rng.h"
#include "sim/core/stats.h"
#include "sim/experiment/jod_fidelity.h"
#include "sim/foveation/factory.h"
#include "sim/metrics/registry.h"

namespace fovsim {

bool has_interval(const std::string& column) {
  static const std::set<std::string> skip = [] {
    std::set<std::string> s = {"frame", "t", "gaze_x", "gaze_y", "ref_ms", "sim_ms"};
    for (auto& e : method_table())
      for (auto& p : e.params()) s.insert(p.name);
    return s;
  }();
  return !skip.count(column);
}

const std::vector<std::string>& headline_metrics() {
  static const std::vector<std::string> m = [] {
    std::vector<std::string> v = {"est_ms_total", "shaded_fraction"};
    // The metric registry's headline metrics and their shown foveation-loss columns.
    for (auto& n : headline_metric_names(true)) v.push_back(n);
    return v;
  }();
  return m;
}

const std::vector<std::string>& paired_metrics() {
  static const std::vector<std::string> m = [] {
    std::vector<std::string> v = {"est_ms_total", "shaded_fraction"};
    for (auto& n : paired_metric_names()) v.push_back(n);  // the metric registry
    return v;
  }();
  return m;
}

namespace {

// A paired difference of a sequence-pooled metric (sim/metrics/registry.h): the difference of
// the two pooled values, with a batch-means interval over the per-batch differences of the
// pooled values (the batches of sim/core/stats.h, over the paired frames in frame order).
MeanInterval pooled_difference(const MetricDecl& d, const std::vector<double>& qa,
                               const std::vector<double>& qb, double& mean_a, double& mean_b) {
  auto pooled = [&](const std::vector<double>& q, size_t b, size_t e) {
    double s = 0;
    for (size_t i = b; i < e; ++i) s += q[i];
    return e > b ? d.from_mean(s / double(e - b)) : double(NAN);
  };
  const size_t n = qa.size();
  mean_a = pooled(qa, 0, n);
  mean_b = pooled(qb, 0, n);
  MeanInterval out;
  out.n = n;
  out.mean = n ? mean_a - mean_b : NAN;
  out.half_width = NAN;
  if (n < kCiMinSamples) return out;
  const size_t m = n / kCiBatches;
  std::vector<double> diffs;
  for (size_t k = 0; k < kCiBatches; ++k)
    diffs.push_back(pooled(qa, k * m, (k + 1) * m) - pooled(qb, k * m, (k + 1) * m));
  MeanInterval b = interval_of_batch_values(diffs);
  out.half_width = b.half_width;
  out.batch_size = m;
  return out;
}

}  // namespace

std::string paired_source_column(const std::string& m) {
  const MetricDecl* decl = find_metric(m);
  if (decl && decl->pooling == Pooling::sequence)
    return decl->pooled_column + (is_foveation_loss_column(m) ? kFoveationLossSuffix : "");
  return m;
}

void paired_columns(const std::vector<const ResultRow*>& a,
                    const std::map<double, const ResultRow*>& b_by_frame, const std::string& m,
                    ResultRow& row) {
  const MetricDecl* decl = find_metric(m);
  const bool seq = decl && decl->pooling == Pooling::sequence;
  const std::string col = paired_source_column(m);
  std::vector<double> va, vb, d;  // frame order of config a
  for (auto* ra : a) {
    auto it = b_by_frame.find(ra->get("frame", NAN));
    if (it == b_by_frame.end()) continue;
    double x = ra->get(col, NAN), y = it->second->get(col, NAN);
    if (!std::isfinite(x) || !std::isfinite(y)) continue;
    va.push_back(x);
    vb.push_back(y);
    d.push_back(x - y);
  }
  double mean_a = NAN, mean_b = NAN;
  MeanInterval ci;
  if (seq) {
    ci = pooled_difference(*decl, va, vb, mean_a, mean_b);
  } else {
    ci = batch_means_interval(d);
    mean_a = batch_means_interval(va).mean;
    mean_b = batch_means_interval(vb).mean;
  }
  row.set("frames", double(d.size()));
  row.set("mean_a", mean_a);
  row.set("mean_b", mean_b);
  row.set("diff", ci.mean);
  row.set("diff_ci95", ci.half_width);
  row.set("diff_lo", ci.lo());
  row.set("diff_hi", ci.hi());
  row.set("differs", std::isnan(ci.half_width) ? NAN : (ci.lo() > 0 || ci.hi() < 0) ? 1 : 0);
}

ResultTable paired_differences(const ResultTable& frames) {
  // Per config, in first-seen order: its rows by frame index.
  std::vector<std::string> order;
  std::map<std::string, std::string> gpu_of;
  std::map<std::string, std::vector<const ResultRow*>> rows;
  for (auto& r : frames.rows()) {
    const std::string* id = r.text_of("config_id");
    std::string key = id ? *id : "";
    if (!rows.count(key)) {
      order.push_back(key);
      const std::string* g = r.text_of("gpu");
      gpu_of[key] = g ? *g : "";
    }
    rows[key].push_back(&r);
  }
  auto cols = frames.numeric_columns();
  std::set<std::string> present(cols.begin(), cols.end());
  ResultTable out;
  for (size_t i = 0; i < order.size(); ++i) {
    for (size_t j = i + 1; j < order.size(); ++j) {
      const std::string &a = order[i], &b = order[j];
      if (gpu_of[a] != gpu_of[b]) continue;
      std::map<double, const ResultRow*> b_by_frame;
      for (auto* r : rows[b]) b_by_frame[r->get("frame", NAN)] = r;
      for (auto& m : paired_metrics()) {
        if (!present.count(paired_source_column(m))) continue;
        ResultRow row;
        row.set_text("config_a", a);
        row.set_text("config_b", b);
        row.set_text("gpu", gpu_of[a]);
        row.set_text("metric", m);
        paired_columns(rows[a], b_by_frame, m, row);
        out.add(std::move(row));
      }
    }
  }
  return out;
}

double fidelity_bias(const Json& fidelity, const std::string& metric, double mean_a,
                     double mean_b) {
  if (!jod_metric_of(metric).empty())  // JOD: against native resolution (jod_fidelity.h)
    return fidelity.is_object() && fidelity.contains("jod") ? jod_bias_of(fidelity["jod"], metric)
                                                            : double(NAN);
  if (!fidelity.is_object() || !fidelity.contains("known_bias")) return NAN;
  const Json& b = fidelity["known_bias"];
  if (!b.is_object()) return NAN;
  auto num = [&](const char* k) {
    return b.contains(k) && b[k].is_number() ? b[k].get<double>() : double(NAN);
  };
  if (metric == "psnr") return num("psnr_db");
  if (metric == "fpsnr") return num("fpsnr_db");
  if (metric == "shaded_fraction") return num("shaded_fraction");
  if (metric == "est_ms_total")
    return num("est_ms_total_percent") / 100.0 * std::max(std::fabs(mean_a), std::fabs(mean_b));
  return NAN;
}

ResultTable with_fidelity_bias(const ResultTable& paired, const Json& fidelity,
                               size_t* n_real_but_below) {
  size_t n = 0;
  ResultTable out;
  for (ResultRow r : paired.rows()) {
    const std::string* m = r.text_of("metric");
    const double bias =
        m ? fidelity_bias(fidelity, *m, r.get("mean_a", NAN), r.get("mean_b", NAN)) : NAN;
    const double d = r.get("diff", NAN);
    const double below =
        std::isfinite(bias) && std::isfinite(d) ? (std::fabs(d) < bias ? 1.0 : 0.0) : NAN;
    r.set("fidelity_bias", bias);
    r.set("below_fidelity_bias", below);
    if (below == 1.0 && r.get("differs", NAN) == 1.0) ++n;
    out.add(std::move(r));
  }
  if (n_real_but_below) *n_real_but_below = n;
  return out;
}

IntervalTarget parse_target(const std::string& spec) {
  const std::string where = "--target " + spec;
  const std::string form =
      "expected COLUMN:VALUE[%|dB|ms] or ranking[:COLUMN], e.g. est_ms_total:1%, fpsnr:0.2dB or "
      "ranking:psnr";
  IntervalTarget t;
  t.spec = spec;
  if (spec == "ranking" || spec.rfind("ranking:", 0) == 0) {
    t.ranking = true;
    t.column = spec == "ranking" ? kDefaultRankingColumn : spec.substr(8);
    if (t.column.empty()) throw Error(where, form);
    if (!has_interval(t.column))
      throw Error(where, "column \"" + t.column + "\" has no interval, so it cannot be ranked");
    return t;
  }
  size_t colon = spec.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 >= spec.size())
    throw Error(where, form);
  t.column = spec.substr(0, colon);
  if (!has_interval(t.column))
    throw Error(where,
                "column \"" + t.column +
                    "\" has no interval (frame, t, gaze_x, gaze_y, ref_ms, sim_ms and method "
                    "parameters have none)");
  std::string v = spec.substr(colon + 1);
  const char* b = v.c_str();
  char* end = nullptr;
  t.value = std::strtod(b, &end);
  std::string unit = end ? std::string(end) : "";
  if (end == b) throw Error(where, form);
  if (unit == "%") {
    t.relative = true;
  } else if (!unit.empty() && unit != "dB" && unit != "ms") {
    throw Error(where, "unknown unit \"" + unit + "\"; " + form);
  }
  if (!std::isfinite(t.value) || t.value <= 0)
    throw Error(where, "the target half-width must be finite and > 0, got " + v);
  if (t.relative && t.value >= 100)
    throw Error(where, "a relative target must be in (0, 100)%, got " + v);
  return t;
}

std::vector<int> sampling_order(int units, uint64_t seed) {
  std::vector<int> order;
  for (int i = 0; i < units; ++i) order.push_back(i);
  Rng rng(seed, 0x7a72676574ull);  // own stream: independent of every other use of the seed
  for (int i = units - 1; i > 0; --i)
    std::swap(order[size_t(i)], order[rng.below(uint32_t(i + 1))]);
  return order;
}

namespace {

// The ranking target (intervals.h): per GPU, configs with a finite mean of `column` sorted by
// it (descending, ties by id); every neighbour pair's paired interval must exclude 0.
bool ranking_settled(const std::string& column, const std::vector<std::string>& order,
                     std::map<std::string, std::vector<const ResultRow*>>& rows, Json* rec) {
  // Per GPU: the configs with a finite value on some frame (an exact config is not ranked).
  std::vector<std::string> gpus;
  std::map<std::string, std::vector<std::string>> ids_of;
  std::map<std::string, std::map<double, double>> by_frame;
  for (auto& id : order) {
    bool any = false;
    for (auto* r : rows[id]) {
      double x = r->get(column, NAN);
      by_frame[id][r->get("frame", NAN)] = x;
      any = any || std::isfinite(x);
    }
    if (!any) continue;
    const std::string* g = rows[id].front()->text_of("gpu");
    std::string gpu = g ? *g : "";
    if (!ids_of.count(gpu)) gpus.push_back(gpu);
    ids_of[gpu].push_back(id);
  }
  bool met = true;
  Json ord = Json::object(), pairs = Json::array();
  for (auto& gpu : gpus) {
    auto& ids = ids_of[gpu];
    // The frames where every ranked config is finite, in evaluation order (so the batches of a
    // --target run are random units): the order and the paired differences use the same frames.
    std::vector<double> frames;
    for (auto* r : rows[ids.front()]) {
      double f = r->get("frame", NAN);
      bool all = true;
      for (auto& id : ids) {
        auto it = by_frame[id].find(f);
        all = all && it != by_frame[id].end() && std::isfinite(it->second);
      }
      if (all) frames.push_back(f);
    }
    std::vector<std::pair<double, std::string>> v;
    for (auto& id : ids) {
      double sum = 0;
      for (double f : frames) sum += by_frame[id][f];
      v.push_back({frames.empty() ? NAN : sum / double(frames.size()), id});
    }
    std::sort(v.begin(), v.end(), [](auto& a, auto& b) {
      return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    Json idj = Json::array();
    for (auto& p : v) idj.push_back(p.second);
    ord[gpu] = idj;
    for (size_t i = 0; i + 1 < v.size(); ++i) {
      const std::string &a = v[i].second, &b = v[i + 1].second;
      std::vector<double> d;
      bool all_zero = true;
      for (double f : frames) {
        d.push_back(by_frame[a][f] - by_frame[b][f]);
        all_zero = all_zero && d.back() == 0;
      }
      MeanInterval ci = batch_means_interval(d);
      bool settled = (!d.empty() && all_zero && d.size() >= kCiMinSamples) ||
                     (std::isfinite(ci.half_width) && (ci.lo() > 0 || ci.hi() < 0));
      met = met && settled;
      if (rec) {
        auto num = [](double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); };
        pairs.push_back({{"a", a},
                         {"b", b},
                         {"gpu", gpu},
                         {"diff", num(ci.mean)},
                         {"ci95", num(ci.half_width)},
                         {"frames", d.size()},
                         {"settled", settled}});
      }
    }
  }
  if (rec) *rec = {{"met", met}, {"order", ord}, {"pairs", pairs}};
  return met;
}

}  // namespace

bool targets_met(const std::vector<IntervalTarget>& targets, const ResultTable& frames,
                 Json* achieved) {
  std::vector<std::string> order;
  std::map<std::string, std::vector<const ResultRow*>> rows;
  for (auto& r : frames.rows()) {
    const std::string* id = r.text_of("config_id");
    std::string key = id ? *id : "";
    if (!rows.count(key)) order.push_back(key);
    rows[key].push_back(&r);
  }
  auto cols = frames.numeric_columns();
  std::set<std::string> present(cols.begin(), cols.end());
  bool all = true;
  if (achieved) *achieved = Json::object();
  for (auto& t : targets) {
    if (!frames.rows().empty() && !present.count(t.column))
      throw Error("--target " + t.spec, "no column \"" + t.column +
                                            "\" in this run's frames (see results/README.md; is "
                                            "the metric enabled?)");
    if (t.ranking) {
      Json rec;
      bool met = ranking_settled(t.column, order, rows, achieved ? &rec : nullptr);
      all = all && met;
      if (achieved) (*achieved)["ranking:" + t.column] = rec;
      continue;
    }
    for (auto& id : order) {
      std::vector<double> v;
      for (auto* r : rows[id]) {
        double x = r->get(t.column, NAN);
        if (std::isfinite(x)) v.push_back(x);
      }
      MeanInterval ci = batch_means_interval(v);
      double limit = t.relative ? t.value / 100.0 * std::fabs(ci.mean) : t.value;
      bool met = v.empty() || ci.half_width <= limit;  // nan half-width: not met
      all = all && met;
      if (achieved) {
        auto num = [](double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); };
        (*achieved)[id][t.column] = {{"mean", num(ci.mean)},
                                     {"ci95", num(ci.half_width)},
                                     {"target", num(limit)},
                                     {"frames", v.size()},
                                     {"met", met}};
      }
    }
  }
  return all;
}

}  // namespace fovsim
