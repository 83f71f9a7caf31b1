#include "sim/cost/validate.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "sim/core/error.h"
#include "sim/cost/passes.h"

namespace fovsim {

namespace {

// The entry's modelled ms and the ms of each pass it sums (every pass of the frame for a total).
double predict_parts(const CostFit& fit, const CalData& data, const CalEntry& e,
                     std::vector<PassCost>* parts) {
  FrameCost fc;
  const double ms =
      entry_ms(profile_from_fit(fit, e.gpu, data), entry_workload(fit, data, e), e, &fc);
  parts->clear();
  for (auto& pc : fc.passes)
    if ((e.passes.empty() ||
         std::find(e.passes.begin(), e.passes.end(), pc.pass) != e.passes.end()) &&
        std::find(e.except.begin(), e.except.end(), pc.pass) == e.except.end())
      parts->push_back({pc.pass, pc.ms, pc.ms, pc.ms});
  return ms;
}

// Sum of a config's modelled frame (all passes) for a table/workload.
double config_total(const CostFit& fit, const CalData& data, const CalTable& t,
                    const std::string& workload, const std::string& config, const Json& disp_over,
                    const Json& params_over, std::vector<PassCost>* parts) {
  for (auto& e : t.entries) {
    if (e.config != config) continue;
    CalEntry c = e;  // the config's first entry; the workload may be one without table rows
    c.workload = workload;
    c.passes.clear();
    if (disp_over.is_object()) {
      if (disp_over.contains("width")) c.display.width = disp_over.at("width").get<int>();
      if (disp_over.contains("height")) c.display.height = disp_over.at("height").get<int>();
    }
    if (params_over.is_object() && !c.baseline) c.params.merge_patch(params_over);
    return predict_parts(fit, data, c, parts);
  }
  throw Error(t.file, "no entry for config '" + config + "' and workload '" + workload + "'");
}

struct Unit {
  std::string name;
  std::set<std::string> fit_tables;  // tables in the fit (empty set + excluded workload: all)
  std::string exclude_workload;      // rows of this workload are left out of the fit
  std::string target_table, target_workload;  // what is predicted ("" workload: all of the table)
};

// 1. Calibration entries with the full fit.
void add_calibration_rows(ValidationReport& rep, const CalData& data, const CostFit& fit) {
  for (auto& t : data.tables)
    for (auto& e : t.entries) {
      ValidationRow r{"calibration",  e.id,     t.id,  e.gpu,
                      e.workload,     e.config, e.row, e.fit ? "fitted" : "check",
                      e.published_ms, 0.0,      {}};
      r.model_ms = predict_parts(fit, data, e, &r.parts);
      rep.rows.push_back(r);
    }
}

// 2. Withheld figures: predictions only (the seeds' copies withhold the published values).
void add_withheld_rows(ValidationReport& rep, const CalData& data, const CostFit& fit) {
  for (auto& t : data.tables) {
    if (!t.json.contains("withheld")) continue;
    for (auto& w : t.json.at("withheld")) {
      std::string id = w.at("id").get<std::string>();
      Json disp = w.value("display", Json::object());
      Json params = w.value("params", Json::object());
      std::vector<std::string> wls;  // the figure's scenes, else the table's (sorted)
      if (w.contains("workloads")) {
        for (auto& v : w.at("workloads")) wls.push_back(v.get<std::string>());
      } else {
        std::set<std::string> ts;
        for (auto& e : t.entries) ts.insert(e.workload);
        wls.assign(ts.begin(), ts.end());
      }
      for (auto& wl : wls)
        for (auto& cfg : w.at("configs")) {
          std::string c = cfg.get<std::string>();
          ValidationRow r{"withheld", id, t.id, t.gpu, wl, c, "total", "withheld", -1, 0.0, {}};
          r.model_ms = config_total(fit, data, t, wl, c, disp, params, &r.parts);
          rep.rows.push_back(r);
        }
    }
  }
}

// 3. The cross-prediction units: kfr <-> rmfr, each table from the others, each workload of a
// table with several from the rest. `all`: every table's id.
std::vector<Unit> cross_units(const CalData& data, const std::set<std::string>& all) {
  std::vector<Unit> units;
  auto has = [&](const std::string& id) { return all.count(id) > 0; };
  if (has("kfr") && has("rmfr")) {
    units.push_back({"fit kfr -> predict rmfr", {"kfr"}, "", "rmfr", ""});
    units.push_back({"fit rmfr -> predict kfr", {"rmfr"}, "", "kfr", ""});
  }
  for (auto& t : data.tables) {
    std::set<std::string> others = all;
    others.erase(t.id);
    units.push_back({"fit all but " + t.id + " -> predict " + t.id, others, "", t.id, ""});
  }
  for (auto& t : data.tables) {
    std::set<std::string> wls;
    for (auto& e : t.entries) wls.insert(e.workload);
    if (wls.size() < 2) continue;
    for (auto& wl : wls)
      units.push_back({"fit all but " + wl + " -> predict " + wl, all, wl, t.id, wl});
  }
  return units;
}

// A leave-one-paper-out refit's parameters and priors (the report's jackknife and priors).
void record_leave_one_paper_out(ValidationReport& rep, const CostFit& f,
                                const std::string& left_out) {
  for (auto& [k, v] : f.theta)
    if (k.rfind("geo:", 0) != 0) rep.lopo_theta[k].push_back(v);
  for (auto& [r, v] : f.efficiency) {
    rep.lopo_theta[std::string("efficiency.") + resource_name(r)].push_back(v);
    rep.lopo_priors[left_out][std::string("efficiency.") + resource_name(r)] = v;
  }
  rep.lopo_theta["prior.overhead_ms"].push_back(f.prior_overhead_ms);
  rep.lopo_priors[left_out]["prior.overhead_ms"] = f.prior_overhead_ms;
}

// One cross-prediction: fit without the target's rows, refit the target's shading and triangle
// costs from its baseline rows, predict and score the rest.
void cross_predict(ValidationReport& rep, const CalData& data, const FitOptions& opt, const Unit& u,
                   const std::set<std::string>& all) {
  CrossPrediction cp;
  cp.name = u.name;
  cp.target = u.target_workload.empty() ? u.target_table : u.target_workload;
  for (auto& s : u.fit_tables) cp.fit_on += (cp.fit_on.empty() ? "" : "+") + s;
  if (!u.exclude_workload.empty()) cp.fit_on += " minus " + u.exclude_workload;
  // Fit without the target rows.
  CalData d2 = data;
  for (auto& t : d2.tables) {
    std::vector<CalEntry> keep;
    for (auto& e : t.entries)
      if (u.exclude_workload.empty() || e.workload != u.exclude_workload) keep.push_back(e);
    t.entries = keep;
  }
  FitOptions o = opt;
  o.tables = u.fit_tables;
  CostFit f = fit_cost_model(d2, o);
  // A leave-one-paper-out refit: its parameters and priors for the report.
  if (u.exclude_workload.empty() && u.fit_tables.size() + 1 == all.size() &&
      !u.fit_tables.count(u.target_table))
    record_leave_one_paper_out(rep, f, u.target_table);
  const CalTable* target = nullptr;
  for (auto& t : data.tables)
    if (t.id == u.target_table) target = &t;
  if (!target) return;
  // Rows with passes never seen by the fit cannot be predicted: they are listed, not scored.
  std::set<std::string> unseen;
  auto row_seen = [&](const CalEntry& e) {
    if (e.passes.empty()) return false;  // totals include unseen passes of the target
    for (auto& p : e.passes)
      if (!f.seen_passes.count(p)) return false;
    return true;
  };
  int predictable = 0;
  for (auto& e : target->entries)
    if (u.target_workload.empty() || e.workload == u.target_workload) {
      for (auto& p : e.passes)
        if (!f.seen_passes.count(p)) unseen.insert(p);
      predictable += row_seen(e);
    }
  for (auto& p : unseen)
    cp.why += (cp.why.empty() ? "passes the refit never measured: " : ", ") + p;
  if (predictable == 0) {
    cp.possible = false;
    rep.cross.push_back(cp);
    return;
  }
  // Shading cost and triangle cost of each target workload from its baseline lighting and
  // G-buffer rows (or, with no baseline config, from all its lighting and G-buffer rows):
  // the scene-specific inputs a user supplies (a render of the scene without foveation).
  std::set<std::string> wls;
  for (auto& e : target->entries)
    if (u.target_workload.empty() || e.workload == u.target_workload) wls.insert(e.workload);
  std::set<std::string> refit_ids;
  for (auto& wl : wls) {
    std::vector<const CalEntry*> rows;
    bool any_baseline = false;
    for (auto& e : target->entries) any_baseline |= e.workload == wl && e.baseline;
    for (auto& e : target->entries)
      if (e.workload == wl && e.fit && e.passes.size() == 1 &&
          (e.passes[0] == "lighting" || e.passes[0] == "gbuffer") && (e.baseline || !any_baseline))
        rows.push_back(&e), refit_ids.insert(e.id);
    refit_workload(f, data, wl, rows);
  }
  double sum = 0;
  std::map<std::string, double> pub_cfg, mod_cfg;  // over predictable rows, first workload
  const std::string wl0 = *wls.begin();
  for (auto& e : target->entries) {
    if (!(u.target_workload.empty() || e.workload == u.target_workload)) continue;
    ValidationRow r{"cross:" + u.name, e.id,     target->id, e.gpu,
                    e.workload,        e.config, e.row,      "unseen",
                    e.published_ms,    0.0,      {}};
    if (!row_seen(e)) {
      // A frame total whose passes the refit all saw is a held-out total: scored for the
      // coverage of the combined interval, not for the per-pass error statistics. A total
      // or pass row with passes the refit never measured is predicted from their nominal
      // work (prior_theta): "total_prior" / "prior", the transfer to a new paper's pipeline.
      std::vector<PassCost> parts;
      const double ms = predict_parts(f, data, e, &parts);
      if (e.passes.empty()) {
        bool all_seen = !parts.empty();
        for (auto& pc : parts) all_seen &= f.seen_passes.count(pc.pass) > 0;
        r.kind = all_seen ? "total" : "total_prior";
      } else {
        r.kind = "prior";
      }
      r.model_ms = ms, r.parts = parts;
      rep.rows.push_back(r);
      continue;
    }
    double ms = predict_parts(f, data, e, &r.parts);
    std::string kind = refit_ids.count(e.id) ? "refit" : "predicted";
    r.kind = kind;
    r.model_ms = ms;
    rep.rows.push_back(r);
    if (e.workload == wl0) pub_cfg[e.config] += e.published_ms, mod_cfg[e.config] += ms;
    if (kind == "predicted" && e.published_ms > 0) {
      sum += std::fabs(ms - e.published_ms) / e.published_ms;
      ++cp.n;
    }
  }
  cp.mean_abs_rel_err = cp.n ? sum / cp.n : 0;
  // Speedup over the predictable rows: first baseline config vs first foveated config.
  // Rows present in only one config (pass 2) count as they are: that pass is the method's cost.
  std::string base, fov;
  for (auto& e : target->entries) {
    if (e.baseline && base.empty()) base = e.config;
    if (!e.baseline && fov.empty()) fov = e.config;
  }
  if (!base.empty() && !fov.empty() && pub_cfg[fov] > 0 && mod_cfg[fov] > 0) {
    cp.speedup_published = pub_cfg[base] / pub_cfg[fov];
    cp.speedup_model = mod_cfg[base] / mod_cfg[fov];
  }
  rep.cross.push_back(cp);
}

}  // namespace

ValidationReport validate_cost(const CalData& data, const CostFit& fit, const FitOptions& opt) {
  ValidationReport rep;
  add_calibration_rows(rep, data, fit);
  add_withheld_rows(rep, data, fit);
  std::set<std::string> all;
  for (auto& t : data.tables) all.insert(t.id);
  for (const Unit& u : cross_units(data, all)) cross_predict(rep, data, opt, u, all);
  return rep;
}

namespace {

bool held_out(const ValidationRow& r) {
  return r.experiment.rfind("cross:", 0) == 0 && r.kind == "predicted" && r.published_ms > 0 &&
         r.model_ms > 0;
}

// Every frame total a refit predicted for a paper or scene it left out: with passes it
// measured ("total") or passes costed from their nominal work ("total_prior").
bool held_out_total(const ValidationRow& r) {
  return (r.kind == "total" || r.kind == "total_prior") && r.published_ms > 0 && r.model_ms > 0;
}

}  // namespace

namespace {
std::string lopo_experiment(const std::string& table) {
  return "cross:fit all but " + table + " -> predict " + table;
}
}  // namespace

std::vector<TransferError> lopo_errors(const ValidationReport& rep, const CalData& data) {
  std::vector<TransferError> out;
  for (auto& t : data.tables) {
    TransferError e;
    e.table = t.id;
    const std::string ex = lopo_experiment(t.id);
    double st = 0, sr = 0;
    for (auto& r : rep.rows) {
      if (r.experiment != ex || !(r.published_ms > 0) || !(r.model_ms > 0)) continue;
      if (r.kind == "total" || r.kind == "total_prior") st += std::fabs(r.rel_err()), ++e.totals_n;
      if (r.kind == "predicted" || r.kind == "prior") sr += std::fabs(r.rel_err()), ++e.rows_n;
    }
    e.totals_mean = e.totals_n ? st / e.totals_n : 0;
    e.rows_mean = e.rows_n ? sr / e.rows_n : 0;
    out.push_back(e);
  }
  return out;
}

std::vector<TransferSpeedup> lopo_speedups(const ValidationReport& rep, const CalData& data) {
  std::vector<TransferSpeedup> out;
  for (auto& t : data.tables) {
    std::set<std::string> baseline;
    for (auto& e : t.entries)
      if (e.baseline) baseline.insert(e.config);
    const std::string ex = lopo_experiment(t.id);
    std::vector<const ValidationRow*> tot;
    for (auto& r : rep.rows)
      if (r.experiment == ex && (r.kind == "total" || r.kind == "total_prior") &&
          r.published_ms > 0 && r.model_ms > 0)
        tot.push_back(&r);
    for (auto* b : tot) {
      if (!baseline.count(b->config)) continue;
      for (auto* f : tot) {
        if (baseline.count(f->config) || f->workload != b->workload || f->row != b->row) continue;
        out.push_back({t.id, b->workload, b->row, b->config, f->config,
                       b->published_ms / f->published_ms, b->model_ms / f->model_ms});
      }
    }
  }
  return out;
}

void wilson_interval(int k, int n, double z, double* lo, double* hi) {
  if (n <= 0) {
    *lo = 0, *hi = 1;
    return;
  }
  const double p = double(k) / n, z2 = z * z, den = 1 + z2 / n;
  const double c = (p + z2 / (2 * n)) / den;
  const double h = z * std::sqrt(p * (1 - p) / n + z2 / (4.0 * n * n)) / den;
  *lo = std::max(0.0, c - h), *hi = std::min(1.0, c + h);
}

double conformal_quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double n = double(v.size());
  long k = q >= 0.5 ? long(std::ceil((n + 1) * q)) : long(std::floor((n + 1) * q));
  k = std::max(1L, std::min(long(v.size()), k));
  return v[size_t(k - 1)];
}

PredictionInterval interval_from_rows(const std::vector<ValidationRow>& rows, double level,
                                      const std::string& exclude_table) {
  std::vector<double> q, tot;
  std::map<std::string, std::vector<double>> per_pass;
  for (auto& r : rows) {
    if (r.table == exclude_table) continue;
    if (held_out(r)) {
      q.push_back(std::log(r.published_ms / r.model_ms));
      if (r.parts.size() == 1)
        per_pass[r.parts[0].pass].push_back(std::log(r.published_ms / r.model_ms));
    } else if (held_out_total(r)) {
      tot.push_back(std::log(r.published_ms / r.model_ms));
    }
  }
  PredictionInterval iv;
  if (q.empty()) return iv;
  const double a_lo = (1 - level) / 2, a_hi = (1 + level) / 2;
  iv.level = level;
  iv.n = int(q.size());
  iv.lo_factor = std::min(1.0, std::exp(conformal_quantile(q, a_lo)));
  iv.hi_factor = std::max(1.0, std::exp(conformal_quantile(q, a_hi)));
  // Partial pooling (gpu_profile.h): a pass's quantiles shrink toward the pooled ones in log
  // space with weight n / (n + kPassIntervalPrior).
  for (auto& [pass, v] : per_pass) {
    const int n = int(v.size());
    if (n < kMinPassIntervalRows) continue;
    const double a = n / (n + kPassIntervalPrior);
    auto shrink = [&](double own, double pooled) {
      return std::exp(a * std::log(own) + (1 - a) * std::log(pooled));
    };
    iv.passes[pass] = {shrink(std::min(1.0, std::exp(conformal_quantile(v, a_lo))), iv.lo_factor),
                       shrink(std::max(1.0, std::exp(conformal_quantile(v, a_hi))), iv.hi_factor),
                       n};
  }
  // Only where the held-out totals can carry the level: the upper rank ceil((n+1)(1+L)/2)
  // must exist (n >= 9 at 80%; 95% needs 39 rows, so it combines the passes' intervals). The
  // totals are every held-out frame total (held_out_total): leave-one-scene-out totals alone
  // (18) were too few and too alike to calibrate a held-out paper's (61-67% at 80%, or 94%
  // through the fallback).
  const double nt = double(tot.size());
  if (tot.size() >= size_t(kMinPassIntervalRows) && std::ceil((nt + 1) * a_hi) <= nt &&
      std::floor((nt + 1) * a_lo) >= 1) {
    iv.total = {std::min(1.0, std::exp(conformal_quantile(tot, a_lo))),
                std::max(1.0, std::exp(conformal_quantile(tot, a_hi))), int(tot.size())};
    std::sort(tot.begin(), tot.end());
    iv.total_scores = tot;
  }
  return iv;
}

void row_interval(const PredictionInterval& iv, const std::vector<PassCost>& parts, double* lo_ms,
                  double* hi_ms, bool total) {
  const IntervalFactors tf = iv.for_total();
  if (total && tf.n > 0) {
    double ms = 0;
    for (auto& pc : parts) ms += pc.ms;
    *lo_ms = ms * tf.lo_factor, *hi_ms = ms * tf.hi_factor;
    return;
  }
  std::vector<PassSpan> spans;
  for (auto& pc : parts) {
    const IntervalFactors f = iv.for_pass(pc.pass);
    spans.push_back({pc.ms, pc.ms * f.lo_factor, pc.ms * f.hi_factor});
  }
  combine_pass_intervals(spans, lo_ms, hi_ms);
}

ModelSummary summarize_model(const ValidationReport& rep, CostModelKind model, double level) {
  ModelSummary s;
  s.model = model;
  double sf = 0, sl = 0;
  std::set<std::string> tables;
  for (auto& r : rep.rows) {
    double e = std::fabs(r.rel_err());
    if (r.experiment == "calibration" && r.kind == "fitted" && r.published_ms > 0) {
      sf += e, ++s.fitted_n, s.fitted_worst = std::max(s.fitted_worst, e);
    } else if (held_out(r)) {
      sl += e, ++s.leaveout_n, s.leaveout_worst = std::max(s.leaveout_worst, e);
      tables.insert(r.table);
    } else if (held_out_total(r)) {
      tables.insert(r.table);
    }
  }
  s.fitted_mean = s.fitted_n ? sf / s.fitted_n : 0;
  s.leaveout_mean = s.leaveout_n ? sl / s.leaveout_n : 0;
  s.interval = interval_from_rows(rep.rows, level);
  for (double lv : {0.5, 0.8, 0.95}) {
    CoverageStat cp, ct;
    cp.level = ct.level = lv;
    std::vector<double> wp, wt;
    for (auto& t : tables) {
      PredictionInterval iv = interval_from_rows(rep.rows, lv, t);
      if (iv.level <= 0) continue;
      for (auto& r : rep.rows) {
        if (r.table != t) continue;
        const bool total = held_out_total(r);
        if (!held_out(r) && !total) continue;
        double lo = 0, hi = 0;
        row_interval(iv, r.parts, &lo, &hi, total);
        const bool inside = r.published_ms >= lo && r.published_ms <= hi;
        CoverageStat& c = total ? ct : cp;
        c.inside += inside, ++c.n;
        (total ? wt : wp).push_back((hi - lo) / (2 * r.model_ms));
      }
    }
    for (auto* c : {&cp, &ct}) {
      c->coverage = c->n ? double(c->inside) / c->n : 0;
      wilson_interval(c->inside, c->n, 1.96, &c->wilson_lo, &c->wilson_hi);
      std::vector<double>& w = c == &cp ? wp : wt;
      if (!w.empty()) {
        std::sort(w.begin(), w.end());
        const size_t m = w.size() / 2;
        c->median_half_width = w.size() % 2 ? w[m] : 0.5 * (w[m - 1] + w[m]);
      }
    }
    s.pass_cov.push_back(cp);
    s.total_cov.push_back(ct);
    if (std::fabs(lv - level) < 1e-9) {
      s.coverage = cp.coverage, s.coverage_n = cp.n;
      s.total_coverage = ct.coverage, s.total_coverage_n = ct.n;
    }
  }
  return s;
}

}  // namespace fovsim
