#include "sim/experiment/convergence.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numeric>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/progress.h"
#include "sim/experiment/runner.h"
#include "sim/metrics/registry.h"

namespace fovsim {

const std::vector<ConvergenceMetric>& convergence_metrics() {
  static const std::vector<ConvergenceMetric> m = [] {
    std::vector<ConvergenceMetric> v;
    for (auto& d : metric_registry()) {
      if (!d.headline) continue;
      using Tol = MetricDecl::Tol;
      const int kind = d.convergence_tol == Tol::db     ? 0
                       : d.convergence_tol == Tol::unit ? 1
                       : d.convergence_tol == Tol::jod  ? 2
                                                        : -1;
      v.push_back({d.name, d.better == Better::higher, kind});
    }
    return v;
  }();
  return m;
}

namespace {

// Moves by less than tol (equal infinities count as no move).
bool within(double a, double b, double tol) {
  if (std::isinf(a) || std::isinf(b)) return a == b;
  return std::fabs(a - b) < tol;
}

std::vector<size_t> ranking(const ConvergenceResult& r, size_t level, size_t metric) {
  std::vector<size_t> idx(r.labels.size());
  std::iota(idx.begin(), idx.end(), size_t(0));
  const bool hi = convergence_metrics()[metric].higher_better;
  std::stable_sort(idx.begin(), idx.end(), [&](size_t a, size_t b) {
    const double va = r.value[level][a][metric], vb = r.value[level][b][metric];
    return hi ? va > vb : va < vb;
  });
  return idx;
}

std::string fmt(double v, int prec) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}

}  // namespace

void evaluate_convergence(ConvergenceResult& r, const ConvergenceOptions& opt) {
  const size_t L = r.spps.size(), nm = convergence_metrics().size();
  r.level_ok.assign(L, false);
  r.chosen_spp = 0;
  for (size_t i = 0; i + 1 < L; ++i) {
    bool ok = true;
    for (size_t k = 0; k < r.labels.size() && ok; ++k)
      for (size_t m = 0; m < nm && ok; ++m) {
        const int kind = convergence_metrics()[m].tol_kind;
        if (kind < 0 || (std::isnan(r.value[i][k][m]) && std::isnan(r.value[i + 1][k][m])))
          continue;  // no tolerance, or not computed by the run
        const double tol = kind == 0 ? opt.tol_db : kind == 1 ? opt.tol_flip : opt.tol_jod;
        ok = within(r.value[i][k][m], r.value[i + 1][k][m], tol);
      }
    // The ranking (by every metric with a tolerance) is the same at this and every higher level.
    for (size_t m = 0; m < nm && ok; ++m) {
      if (convergence_metrics()[m].tol_kind < 0) continue;
      const auto base = ranking(r, i, m);
      for (size_t j = i + 1; j < L && ok; ++j) ok = ranking(r, j, m) == base;
    }
    r.level_ok[i] = ok;
  }
  // The lowest level from which every higher comparison also holds.
  for (size_t i = 0; i + 1 < L; ++i) {
    bool all = true;
    for (size_t j = i; j + 1 < L; ++j) all = all && r.level_ok[j];
    if (all) {
      r.chosen_spp = r.spps[i];
      break;
    }
  }
}

std::string ConvergenceResult::markdown() const {
  // Columns: every metric of the study, then Δ for those with a tolerance (the registry).
  const auto& ms = convergence_metrics();
  auto prec = [](const std::string& name) {
    const MetricDecl* d = find_metric(name);
    return d ? d->precision : 4;
  };
  std::string s = "| method | spp |";
  for (auto& m : ms) s += " " + m.name + " |";
  for (auto& m : ms)
    if (m.tol_kind >= 0) s += " Δ" + m.name + " |";
  s += "\n|---|---|";
  for (auto& m : ms) s += m.tol_kind >= 0 ? "---|---|" : "---|";
  s += "\n";
  for (size_t k = 0; k < labels.size(); ++k)
    for (size_t i = 0; i < spps.size(); ++i) {
      const auto& v = value[i][k];
      s += "| " + labels[k] + " | " + std::to_string(spps[i]) + " |";
      for (size_t m = 0; m < ms.size(); ++m) s += " " + fmt(v[m], prec(ms[m].name)) + " |";
      for (size_t m = 0; m < ms.size(); ++m) {
        if (ms[m].tol_kind < 0) continue;
        s += i + 1 < spps.size() ? " " + fmt(value[i + 1][k][m] - v[m], prec(ms[m].name) + 1) + " |"
                                 : "  |";
      }
      s += "\n";
    }
  s += "\nΔ = next level minus this level. Level meets the criterion:";
  for (size_t i = 0; i + 1 < spps.size(); ++i)
    s += " " + std::to_string(spps[i]) + (level_ok[i] ? " yes;" : " no;");
  s += chosen_spp ? " chosen spp = " + std::to_string(chosen_spp) + "\n"
                  : " no level converged: use the highest\n";
  return s;
}

std::string ConvergenceResult::csv() const {
  std::string s = "spp,label";
  for (auto& m : convergence_metrics()) s += "," + m.name;
  s += ",ref_seconds,level_ok\n";
  for (size_t i = 0; i < spps.size(); ++i)
    for (size_t k = 0; k < labels.size(); ++k) {
      s += std::to_string(spps[i]) + "," + labels[k];
      for (double v : value[i][k]) s += "," + format_number(v);
      s += "," + format_number(ref_seconds.size() > i ? ref_seconds[i] : NAN) + "," +
           (level_ok.size() > i && level_ok[i] ? "1" : "0") + "\n";
    }
  return s;
}

ConvergenceResult run_convergence(const std::string& config,
                                  const std::vector<std::string>& overrides,
                                  const ConvergenceOptions& opt) {
  if (opt.spps.size() < 2) throw Error("converge", "needs at least two spp levels");
  for (size_t i = 0; i < opt.spps.size(); ++i) {
    const int n = int(std::lround(std::sqrt(double(opt.spps[i]))));
    if (opt.spps[i] < 1 || n * n != opt.spps[i] || (i && opt.spps[i] <= opt.spps[i - 1]))
      throw Error("converge", "spp levels must be increasing perfect squares (e.g. 1,4,16,64)");
  }
  ConvergenceResult r;
  r.spps = opt.spps;
  const size_t nm = convergence_metrics().size();
  Progress progress("converge spp levels", opt.spps.size());  // each level's frames nest inside
  for (int spp : opt.spps) {
    progress.phase("render.spp " + std::to_string(spp));
    std::vector<std::string> ov = overrides;
    ov.push_back("render.spp=" + std::to_string(spp));
    LoadedConfig cfg = load_config(config, ov);
    RunOptions ro;
    ro.out_dir = (std::filesystem::path(opt.out_dir) / ("spp_" + std::to_string(spp))).string();
    static_cast<RunControl&>(ro) = opt;
    ro.targets.clear();
    ro.print_summary = false;
    ro.command_line = "fovsim converge " + config;
    const auto t0 = std::chrono::steady_clock::now();
    RunResult rr = run_experiment(cfg, ro);
    r.ref_seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    std::vector<std::vector<double>> lvl;
    std::vector<std::string> labels;
    for (const ResultRow& row : rr.summary.rows()) {
      const std::string* lab = row.text_of("label");
      const std::string name = lab ? *lab : "?";
      if (std::find(labels.begin(), labels.end(), name) != labels.end()) continue;  // other GPUs
      labels.push_back(name);
      std::vector<double> v(nm);
      for (size_t m = 0; m < nm; ++m) v[m] = row.get(convergence_metrics()[m].name, NAN);
      lvl.push_back(v);
    }
    if (r.labels.empty()) r.labels = labels;
    FOVSIM_CHECK(labels == r.labels, "converge: method labels differ between spp levels");
    r.value.push_back(lvl);
    progress.step();
  }
  evaluate_convergence(r, opt);
  write_file_atomic((std::filesystem::path(opt.out_dir) / "convergence.csv").string(), r.csv());
  write_file_atomic((std::filesystem::path(opt.out_dir) / "convergence.md").string(), r.markdown());
  return r;
}

}  // namespace fovsim
