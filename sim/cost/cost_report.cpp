// `fovsim calibrate` / `fovsim validate-cost` orchestration (see cost_report.h).
#include "sim/cost/cost_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/text.h"
#include "sim/cost/passes.h"
#include "sim/trace/csv_table.h"

namespace fovsim {

namespace {

// A table cell: user text (GPU, workload, entry names) escaped, then padded.
std::string pad(const std::string& raw, size_t w) {
  const std::string s = escape_control(raw, 80);
  return s.size() >= w ? s : s + std::string(w - s.size(), ' ');
}

std::string csv_quote(const std::string& s) {
  std::string o = "\"";
  for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}

const char* kIntervalMethod =
    "split-conformal 10%/90% quantiles of log(published/model) over the held-out rows of fovsim "
    "validate-cost's leave-one-seed/GPU/scene-out refits: per pass (passes) where the pass has "
    "at least 5 single-pass rows, shrunk toward the pooled quantiles with weight n/(n+8) in log "
    "space, else pooled; the total (total) from every held-out frame total (leave-one-scene-out "
    "and leave-one-paper-out, passes a refit never measured costed from their nominal work), "
    "whose sorted scores (total_scores) give budget's probability of fitting; widen > 1: a GPU "
    "no table used (log-widths multiplied)";

}  // namespace

std::set<std::string> parse_id_list(const std::string& text, const std::string& where) {
  std::set<std::string> out;
  for (const CsvField& f : split_csv_line(text, ',', where, 1))
    if (!f.text.empty()) out.insert(f.text);
  return out;
}

GpuProfile calibrated_profile(const CostFit& fit, const CalData& data, const std::string& gpu,
                              const PredictionInterval& iv, const std::set<std::string>& tables) {
  GpuProfile g = profile_from_fit(fit, gpu, data);
  g.interval = iv;
  if (iv.level > 0) g.interval.method = kIntervalMethod;
  for (auto& t : data.tables) {
    if (!tables.empty() && !tables.count(t.id)) continue;
    g.calibration_tables.push_back(t.id + ": " + t.source);
    if (t.gpu != gpu) continue;
    g.calibrated = true;
    for (auto& e : t.entries) {
      const double ms = predict_entry(fit, data, e);
      g.residuals.push_back({e.id, e.fit, e.published_ms, ms,
                             e.published_ms > 0 ? (ms - e.published_ms) / e.published_ms : 0.0});
    }
  }
  if (!g.calibrated) {  // extrapolation: wider intervals (docs/cost_model.md "Current GPUs")
    const GpuSpecEntry& se = data.specs.at(gpu);
    g.interval.widen = se.widen;
    g.architecture = se.architecture;
  }
  g.calibration_comment =
      std::string("Written by `fovsim calibrate`: NNLS on relative error over the tables below; ") +
      (g.calibrated
           ? "residuals are this GPU's entries."
           : "no table used this GPU: coefficients transferred through spec-sheet ratios only.");
  return g;
}

CalibrationRun run_calibration(const CalibrateOptions& o) {
  CalibrationRun run;
  run.data = load_calibration(o.models);
  run.opt.tables = o.tables;
  run.opt.model = o.model;
  for (auto& t : o.tables) {
    bool known = false;
    for (auto& ct : run.data.tables) known |= ct.id == t;
    if (!known) throw Error("--tables", "unknown calibration table '" + t + "'");
  }
  run.fit = fit_cost_model(run.data, run.opt);
  double sum = 0;
  for (auto& t : run.data.tables)
    for (auto& e : t.entries) {
      const double ms = predict_entry(run.fit, run.data, e);
      const double re = e.published_ms > 0 ? (ms - e.published_ms) / e.published_ms : 0;
      if (e.fit && (o.tables.empty() || o.tables.count(t.id))) sum += std::fabs(re), ++run.fitted_n;
      run.rows.push_back({e, ms, re});
    }
  run.fitted_mean_abs_err = run.fitted_n ? sum / run.fitted_n : 0;
  if (!o.write) return run;
  // Prediction interval from the leave-out experiments of this model (docs/cost_model.md).
  run.interval = interval_from_rows(validate_cost(run.data, run.fit, run.opt).rows, 0.8);
  for (auto& [gpu, se] : run.data.specs) {
    (void)se;
    run.profiles.push_back(calibrated_profile(run.fit, run.data, gpu, run.interval, o.tables));
    const std::string dir = (o.out.empty() ? o.models : o.out) + "/gpus";
    make_dirs(dir);
    const std::string file = dir + "/" + gpu + ".json";
    write_file_atomic(file, run.profiles.back().to_file_text());
    run.written.push_back(file);
  }
  // Fitted workload costs go into the workload files, which keep their authors' layout.
  for (auto& wl : run.fit.fitted_workloads) {
    const std::string dir = (o.out.empty() ? o.models : o.out) + "/workloads";
    make_dirs(dir);
    const std::string file = dir + "/" + wl + ".json";
    const std::string src = o.models + "/workloads/" + wl + ".json";
    auto j = parse_json_text_ordered(read_file(src), src);
    const Workload& w = run.fit.workloads.at(wl);
    const std::string p = fitted_param(w);
    j[p] = p == "vpl_flops" ? w.vpl_flops : w.shading_flops;
    j["tri_cost"] = w.tri_cost;
    j["fitted_by"] = "fovsim calibrate: " + p + ", tri_cost";
    write_file_atomic(file, j.dump(2) + "\n");
    run.written.push_back(file);
  }
  return run;
}

namespace {

// The sections of report.txt and the CSVs of `fovsim validate-cost` (run_validation below).

// validate_cost.csv: every validation row with its interval (the nested one on cross-prediction
// rows).
void write_validation_csv(std::ostream& csv, const ValidationReport& rep,
                          const PredictionInterval& iv_all,
                          std::map<std::string, PredictionInterval>& iv_nested) {
  csv << "experiment,id,table,gpu,workload,config,row,passes,kind,published_ms,model_ms,rel_err,"
         "model_lo_ms,model_hi_ms\n";
  for (auto& r : rep.rows) {
    const bool cross = r.experiment.rfind("cross:", 0) == 0;
    const PredictionInterval& iv = cross ? iv_nested[r.table] : iv_all;
    std::string passes;
    for (auto& pc : r.parts) passes += (passes.empty() ? "" : "+") + pc.pass;
    csv << csv_quote(r.experiment) << ',' << csv_quote(r.id) << ',' << r.table << ',' << r.gpu
        << ',' << r.workload << ',' << r.config << ',' << csv_quote(r.row) << ',' << passes << ','
        << r.kind << ',' << r.published_ms << ',' << r.model_ms << ','
        << (r.published_ms > 0 ? std::to_string(r.rel_err()) : "") << ',';
    if (r.parts.empty()) {
      csv << ",\n";
    } else {
      double lo = 0, hi = 0;
      row_interval(iv, r.parts, &lo, &hi,
                   r.kind == "total" || r.kind == "total_prior" || r.kind == "withheld");
      csv << lo << ',' << hi << "\n";
    }
  }
}

// The models ranked by held-out error and their interval calibration.
void report_model_ranking(std::ostream& txt, const ValidationOutputs& v, int pct) {
  txt << "fovsim validate-cost: predicted vs. published per-pass times (ms)\n\n";
  txt << "== models ranked by held-out mean |rel err| (leave-one-seed-out = leave-one-GPU-out, "
         "leave-one-scene-out), not by the fitted error\n";
  txt << pad("model", 10) << pad("fitted mean/worst", 20) << pad("held-out mean/worst (n)", 28)
      << pad("pooled " + std::to_string(pct) + "% interval", 22) << pad("per-pass coverage", 20)
      << "total coverage\n";
  for (auto& m : v.ranked)
    txt << pad(model_name(m.model), 10)
        << pad(fmt("%.1f%%", 100 * m.fitted_mean) + fmt(" / %.1f%%", 100 * m.fitted_worst), 20)
        << pad(fmt("%.1f%%", 100 * m.leaveout_mean) + fmt(" / %.1f%%", 100 * m.leaveout_worst) +
                   " (" + std::to_string(m.leaveout_n) + ")",
               28)
        << pad(fmt("[%.2f, ", m.interval.lo_factor) + fmt("%.2f] x model", m.interval.hi_factor),
               22)
        << pad(fmt("%.0f%%", 100 * m.coverage) + " of " + std::to_string(m.coverage_n), 20)
        << fmt("%.0f%%", 100 * m.total_coverage) << " of " << m.total_coverage_n << "\n";
  txt << "coverage (nested): each target table's held-out rows against the intervals built from "
         "the other tables' held-out rows;\n"
         "  per-pass: held-out per-pass rows; total: held-out frame totals whose passes the refit "
         "all saw or costed from nominal work (split-conformal on the other tables' held-out "
         "totals)\n\n";
  txt << "== interval calibration per model (split-conformal on log(published/model), grouped by "
         "paper = GPU: a table never calibrates its own rows); coverage [Wilson 95%] and median "
         "half-width / estimate\n";
  txt << pad("model", 10) << pad("level", 7) << pad("per-pass coverage [95% CI] (n)", 32)
      << pad("half-width", 12) << pad("total coverage [95% CI] (n)", 30) << "half-width\n";
  for (auto& m : v.ranked)
    for (size_t i = 0; i < m.pass_cov.size() && i < m.total_cov.size(); ++i) {
      const CoverageStat &cp = m.pass_cov[i], &ct = m.total_cov[i];
      auto cov = [](const CoverageStat& c) {
        return fmt("%.0f%%", 100 * c.coverage) + fmt(" [%.0f, ", 100 * c.wilson_lo) +
               fmt("%.0f]", 100 * c.wilson_hi) + " (" + std::to_string(c.n) + ")";
      };
      txt << pad(model_name(m.model), 10) << pad(fmt("%.0f%%", 100 * cp.level), 7)
          << pad(cov(cp), 32) << pad(fmt("%.2f", cp.median_half_width), 12) << pad(cov(ct), 30)
          << fmt("%.2f", ct.median_half_width) << "\n";
    }
}

void report_resolutions(std::ostream& txt, const CalData& data) {
  // Leave-one-resolution-out needs one configuration at several resolutions in a table.
  txt << "leave-one-resolution-out: not possible, every calibration table gives one resolution (";
  {
    std::string sep;
    for (auto& t : data.tables) {
      std::set<std::string> res;
      for (auto& e : t.entries)
        res.insert(std::to_string(e.display.width) + "x" + std::to_string(e.display.height) +
                   (e.display.eyes > 1 ? " x" + std::to_string(e.display.eyes) + " eyes" : ""));
      std::string r;
      for (auto& x : res) r += (r.empty() ? "" : ", ") + x;
      txt << sep << t.id << " " << r;
      sep = "; ";
    }
  }
  txt << "); the seeds' multi-resolution figures (KFR thesis Table 4.2, TWFR Fig. 10) are "
         "withheld and only predicted below\n\n";
}

void report_pass_intervals(std::ostream& txt, const ValidationOutputs& v,
                           const PredictionInterval& iv_all, int pct) {
  txt << "== " << pct << "% interval factors (x model ms) of model " << model_name(v.model)
      << " per pass (rows: held-out single-pass rows, shrunk toward the pooled factors with weight "
         "n/(n+"
      << kPassIntervalPrior << "); fewer than " << kMinPassIntervalRows << " rows: pooled)\n";
  for (auto& p : known_passes()) {
    const IntervalFactors f = iv_all.for_pass(p);
    const bool own = iv_all.passes.count(p) > 0;
    txt << "  " << pad(p, 14) << fmt("[%.2f, ", f.lo_factor) << fmt("%.2f]", f.hi_factor)
        << (own ? "  " + std::to_string(f.n) + " rows" : "  pooled") << "\n";
  }
}

void report_leave_one_paper_out(std::ostream& txt, const ValidationOutputs& v,
                                const ValidationReport& rep, const CalData& data) {
  // Absolute times across papers: leave-one-paper-out error of the frame totals.
  txt << "\n== leave-one-paper-out (= leave-one-GPU-out) |rel err| of held-out frame totals, model "
      << model_name(v.model) << "\n";
  {
    double sum_all = 0;
    int n_all = 0;
    for (const TransferError& e : lopo_errors(rep, data)) {
      sum_all += e.totals_mean * e.totals_n, n_all += e.totals_n;
      txt << "  " << pad(e.table, 6) << " totals "
          << (e.totals_n
                  ? fmt("%.1f%%", 100 * e.totals_mean) + " (" + std::to_string(e.totals_n) + ")"
                  : std::string("none predictable"))
          << ", per-pass rows " << (e.rows_n ? fmt("%.1f%%", 100 * e.rows_mean) : std::string("-"))
          << " (" << e.rows_n << ")\n";
    }
    txt << "  all    totals " << (n_all ? fmt("%.1f%%", 100 * sum_all / n_all) : std::string("-"))
        << " (" << n_all << "); target <= 25%\n";
    txt << "  (totals and rows include passes the refit never measured, costed from their nominal "
           "work; the target's shading and triangle costs come from its baseline lighting and "
           "G-buffer rows)\n";
    txt << "  speedups of the held-out totals (baseline / foveated), published vs model:\n";
    for (const TransferSpeedup& s : lopo_speedups(rep, data))
      txt << "    " << pad(s.table + " " + s.workload + " " + s.row, 44) << " "
          << pad(s.base + " / " + s.fov, 24) << fmt(" %.2fx", s.published)
          << fmt(" model %.2fx", s.model)
          << fmt(" (%+.1f%%)", 100 * (s.model - s.published) / s.published) << "\n";
  }
}

void report_fitted_parameters(std::ostream& txt, const ValidationOutputs& v,
                              const ValidationReport& rep, const CalData& data) {
  // Fitted parameters with their jackknife uncertainty over the leave-one-paper-out refits.
  txt << "\n== fitted parameters of model " << model_name(v.model)
      << " (full fit; +- jackknife SE over the leave-one-paper-out refits, sqrt((k-1)/k sum "
         "(x_i - mean)^2); k: refits that fitted it)\n";
  {
    CalData d2 = data;
    FitOptions o;
    o.model = v.model;
    const CostFit full = fit_cost_model(d2, o);
    size_t refits = 0;
    for (auto& [k, xs] : rep.lopo_theta) refits = std::max(refits, xs.size());
    std::map<std::string, double> params(full.theta.begin(), full.theta.end());
    for (auto& [r, e] : full.efficiency) params[std::string("efficiency.") + resource_name(r)] = e;
    params["prior.overhead_ms"] = full.prior_overhead_ms;
    for (auto& [k, val] : params) {
      if (k.rfind("geo:", 0) == 0) continue;
      txt << "  " << pad(k, 28) << fmt("%12.5g", val);
      auto it = rep.lopo_theta.find(k);
      if (it != rep.lopo_theta.end() && it->second.size() >= 2 && it->second.size() == refits) {
        const auto& xs = it->second;
        double m = 0;
        for (double x : xs) m += x;
        m /= double(xs.size());
        double ss = 0;
        for (double x : xs) ss += (x - m) * (x - m);
        const double kk = double(xs.size());
        txt << " +- " << fmt("%-10.3g", std::sqrt((kk - 1) / kk * ss)) << " (k " << xs.size()
            << ")";
      } else {
        txt << " +- ?          (one paper's rows only: no spread)";
      }
      txt << " " << theta_unit(k) << "\n";
    }
  }
}

// A fitted term further than this factor from its transfer prior is a flagged residual.
constexpr double kResidualFlag = 2.0;

// The one calibration table whose fitted rows measure `pass` ("" when none or several).
std::string measuring_table(const CalData& data, const std::string& pass) {
  std::string found;
  for (auto& t : data.tables)
    for (auto& e : t.entries)
      if (e.fit && std::find(e.passes.begin(), e.passes.end(), pass) != e.passes.end()) {
        if (!found.empty() && found != t.id) return "";
        found = t.id;
      }
  return found;
}

void report_nominal_work(std::ostream& txt, const ValidationOutputs& v, const ValidationReport& rep,
                         const CalData& data) {
  // Nominal work of the passes one paper alone measures, and what the pooled efficiency makes
  // of it, next to the full fit's theta (how far the transfer prior is from the paper's rows).
  txt << "\n== nominal work of passes one paper alone measures (prior in its leave-one-paper-out "
         "refit: nominal / pooled efficiency of the resource, or the named term's theta x factor); "
         "full-fit theta for comparison\n";
  for (auto& [table, pr] : rep.lopo_priors) {
    txt << "  left out " << pad(table, 6);
    for (auto& [k, x] : pr) txt << " " << k << fmt(" %.4g", x);
    txt << "\n";
  }
  {
    FitOptions o;
    o.model = v.model;
    const CostFit full = fit_cost_model(data, o);
    std::string flagged;
    for (const std::string& pass : known_passes())
      for (const std::string& term : term_names()) {
        std::string like, why;
        const double w = nominal_work(pass, term, &like, &why);
        if (!(w > 0)) continue;
        CostFit without = full;  // the prior the full fit's efficiencies give this term
        without.seen_passes.erase(pass);
        if (without.seen_passes.empty()) without.seen_passes.insert("-");
        auto it = full.theta.find(pass + "." + std::string(term));
        txt << "  " << pad(pass + "." + term, 22)
            << (like.empty() ? fmt("nominal %-8.4g", w) : pad(fmt("%.4g x ", w) + like, 30))
            << fmt(" prior %-10.4g", prior_theta(without, pass, term))
            << (it == full.theta.end() ? std::string(" fitted (floor)")
                                       : fmt(" fitted %-10.4g", it->second))
            << " " << theta_unit(pass + "." + term) << "\n      " << why << "\n";
        // Residual: the fitted work over what the paper's stated work costs at the pooled
        // efficiency of the refit that leaves its paper out (work nothing stated explains when
        // far above 1; not fitted away by a multiplier).
        const std::string table = measuring_table(data, pass);
        if (!like.empty() || table.empty() || it == full.theta.end()) continue;
        double eff = 1.0;
        if (auto pr = rep.lopo_priors.find(table); pr != rep.lopo_priors.end()) {
          const auto r = find_term_resource(pass, term);
          auto e = r ? pr->second.find(std::string("efficiency.") + resource_name(*r))
                     : pr->second.end();
          if (e != pr->second.end() && e->second > 0) eff = e->second;
        }
        const double res = it->second / std::max(theta_floor(pass, term), w / eff);
        const bool flag = res > kResidualFlag || res < 1.0 / kResidualFlag;
        txt << fmt("      residual x%.3g", res) << " (fitted / prior without " << table << ")"
            << (flag ? "  FLAGGED: work the paper's stated algorithm does not explain" : "")
            << "\n";
        if (flag) flagged += " " + pass + "." + term + fmt(" x%.3g", res);
      }
    txt << "  flagged residuals (fitted / prior outside [1/" << fmt("%g", kResidualFlag) << ", "
        << fmt("%g", kResidualFlag) << "]):" << (flagged.empty() ? " none" : flagged) << "\n";
  }
}

void report_calibration_entries(std::ostream& txt, const ValidationOutputs& v,
                                const ValidationReport& rep) {
  txt << "\ndetailed report below: model " << model_name(v.model) << "\n\n";
  txt << "== calibration entries (all tables fitted together; 'check' rows are totals, not "
         "fitted)\n";
  double se[2] = {0, 0};
  int ne[2] = {0, 0};
  for (auto& r : rep.rows) {
    if (r.experiment != "calibration") continue;
    int k = r.kind == "fitted" ? 0 : 1;
    se[k] += std::fabs(r.rel_err()), ne[k]++;
    txt << pad(r.id, 62) << " " << pad(r.kind, 9) << fmt(" %8.3f", r.published_ms)
        << fmt(" %8.3f", r.model_ms) << fmt(" %+7.1f%%", 100 * r.rel_err()) << "\n";
  }
  txt << "mean |rel err|: fitted " << fmt("%.1f%%", ne[0] ? 100 * se[0] / ne[0] : 0) << " ("
      << ne[0] << " rows), check " << fmt("%.1f%%", ne[1] ? 100 * se[1] / ne[1] : 0) << " ("
      << ne[1] << " rows)\n\n";
}

void report_withheld(std::ostream& txt, const ValidationReport& rep,
                     const PredictionInterval& iv_all, int pct) {
  txt << "== withheld figures (published values withheld from the seeds: predictions only; "
         "total ms with its "
      << pct << "% interval)\n";
  std::map<std::string, std::vector<const ValidationRow*>> wh;
  for (auto& r : rep.rows)
    if (r.experiment == "withheld") wh[r.id + " " + r.workload].push_back(&r);
  for (auto& [k, rows] : wh) {
    txt << pad(k, 52);
    for (auto* r : rows) {
      double lo = 0, hi = 0;
      row_interval(iv_all, r->parts, &lo, &hi, true);
      txt << " " << r->config << fmt(" %.2f ms", r->model_ms) << fmt(" [%.2f, ", lo)
          << fmt("%.2f]", hi);
    }
    if (rows.size() == 2 && rows[1]->model_ms > 0)
      txt << fmt("  speedup %.2fx", rows[0]->model_ms / rows[1]->model_ms);
    txt << "\n";
  }
}

// The cross-predictions, in report.txt and cross_predictions.csv.
void report_cross_predictions(std::ostream& txt, std::ostream& ccsv, const ValidationReport& rep) {
  txt << "\n== cross-predictions (target's shading and triangle costs refit from its baseline "
         "lighting and G-buffer rows only)\n";
  ccsv << "name,fit_on,target,possible,n,mean_abs_rel_err,speedup_published,speedup_model\n";
  for (auto& c : rep.cross) {
    ccsv << csv_quote(c.name) << ',' << csv_quote(c.fit_on) << ',' << c.target << ',' << c.possible
         << ',' << c.n << ',' << c.mean_abs_rel_err << ',' << c.speedup_published << ','
         << c.speedup_model << "\n";
    txt << pad(c.name, 48);
    if (!c.possible) {
      txt << " not predictable (" << c.why << ")\n";
      continue;
    }
    if (c.n == 0) {
      txt << " no row of measured passes beyond the refit ones (rows costed from nominal work: "
             "leave-one-paper-out section)\n";
      continue;
    }
    txt << " rows " << c.n << ", mean |rel err| " << fmt("%.1f%%", 100 * c.mean_abs_rel_err);
    if (c.speedup_published > 0)
      txt << ", speedup published " << fmt("%.2fx", c.speedup_published) << " model "
          << fmt("%.2fx", c.speedup_model);
    if (!c.why.empty()) txt << " [not counted here, costed from nominal work: " << c.why << "]";
    txt << "\n";
  }
}

}  // namespace

ValidationOutputs run_validation(const std::string& models, double level) {
  ValidationOutputs v;
  CalData data = load_calibration(models);
  FitOptions opt;  // the default model (roofline) is the detailed report
  v.model = opt.model;
  CostFit fit = fit_cost_model(data, opt);
  v.report = validate_cost(data, fit, opt);
  for (CostModelKind k : {CostModelKind::Roofline, CostModelKind::Linear}) {
    if (k == opt.model) {
      v.ranked.push_back(summarize_model(v.report, k, level));
    } else {
      FitOptions o = opt;
      o.model = k;
      CostFit f = fit_cost_model(data, o);
      v.ranked.push_back(summarize_model(validate_cost(data, f, o), k, level));
    }
  }
  std::stable_sort(v.ranked.begin(), v.ranked.end(),
                   [](const ModelSummary& x, const ModelSummary& y) {
                     return x.leaveout_mean < y.leaveout_mean;
                   });
  const ValidationReport& rep = v.report;
  // model_lo_ms/model_hi_ms: the interval; on cross-prediction rows the nested one (built
  // without the row's table), on the others the interval the profiles carry.
  const PredictionInterval iv_all = interval_from_rows(rep.rows, level);
  std::map<std::string, PredictionInterval> iv_nested;
  for (auto& t : data.tables) iv_nested[t.id] = interval_from_rows(rep.rows, level, t.id);
  std::ostringstream txt, csv, ccsv;
  write_validation_csv(csv, rep, iv_all, iv_nested);
  const int pct = int(std::lround(100 * level));
  report_model_ranking(txt, v, pct);
  report_resolutions(txt, data);
  report_pass_intervals(txt, v, iv_all, pct);
  report_leave_one_paper_out(txt, v, rep, data);
  report_fitted_parameters(txt, v, rep, data);
  report_nominal_work(txt, v, rep, data);
  report_calibration_entries(txt, v, rep);
  report_withheld(txt, rep, iv_all, pct);
  report_cross_predictions(txt, ccsv, rep);
  v.report_txt = txt.str();
  v.validate_csv = csv.str();
  v.cross_csv = ccsv.str();
  return v;
}

void write_validation(const ValidationOutputs& v, const std::string& dir) {
  make_dirs(dir);
  write_file_atomic(dir + "/validate_cost.csv", v.validate_csv);
  write_file_atomic(dir + "/cross_predictions.csv", v.cross_csv);
  write_file_atomic(dir + "/report.txt", v.report_txt);
}

}  // namespace fovsim
