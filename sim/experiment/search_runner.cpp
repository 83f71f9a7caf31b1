#include "sim/experiment/search_runner.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <utility>

#include "sim/core/error.h"
#include "sim/core/files.h"
#include "sim/core/hash.h"
#include "sim/core/progress.h"
#include "sim/core/version.h"
#include "sim/experiment/engine.h"
#include "sim/experiment/jod_fidelity.h"
#include "sim/experiment/search.h"
#include "sim/experiment/search_verdict.h"

namespace fovsim {

namespace {

// The summary row a search scores: the method entry named by search.label, else the first.
const ResultRow* scored_row(const ResultTable& t, const std::string& label) {
  for (auto& r : t.rows()) {
    const std::string* l = r.text_of("label");
    if (label.empty() || (l && *l == label)) return &r;
  }
  return nullptr;
}

// True when a cached evaluation holds every column this search scores (done.json is written
// last, so its presence means the run completed; a run cached by a search with another
// objective or constraint lacks their columns and is evaluated again) and was made by this
// build (`git_commit`: a rebuilt cost model or metric must not be answered from the numbers of
// the previous one; `stale` counts those).
bool cached_eval_complete(const std::string& done_path, const SearchSpec& sp, int& stale) {
  if (!file_exists(done_path)) return false;
  Json d;
  try {
    d = parse_json_text(read_file(done_path), done_path);
  } catch (const std::exception&) {
    return false;
  }
  if (!d.is_object() || !d.contains("columns") || !d["columns"].is_object()) return false;
  if (!d.contains("git_commit") || d["git_commit"] != git_commit()) {
    ++stale;
    return false;
  }
  if (!d["columns"].contains(sp.objective.column)) return false;
  for (auto& k : sp.constraints)
    if (!d["columns"].contains(k.column)) return false;
  return true;
}

}  // namespace

void refuse_undefined_bounds(const ResultRow& r, const SearchSpec& sp, const std::string& file) {
  const std::string* missing = r.text_of("ci_missing");
  if (!missing || missing->empty()) return;
  auto reason = [&](const std::string& base) -> std::string {
    size_t pos = 0;
    while (pos < missing->size()) {
      size_t end = missing->find("; ", pos);
      if (end == std::string::npos) end = missing->size();
      const std::string seg = missing->substr(pos, end - pos);
      pos = end + 2;
      const size_t colon = seg.find(": ");
      if (colon == std::string::npos) continue;
      const std::string cols = " " + seg.substr(0, colon) + " ";
      if (cols.find(" " + base + " ") != std::string::npos) return seg.substr(colon + 2);
    }
    return "";
  };
  auto check = [&](const std::string& column, const std::string& where) {
    if (!std::isnan(r.get(column, NAN))) return;
    for (const char* suffix : {"_lo", "_hi", "_ci95"}) {
      const std::string sfx = suffix;
      if (column.size() <= sfx.size() ||
          column.compare(column.size() - sfx.size(), sfx.size(), sfx))
        continue;
      const std::string base = column.substr(0, column.size() - sfx.size());
      const std::string why = reason(base);
      if (why.empty()) continue;
      const std::string* label = r.text_of("label");
      throw Error(file + ": " + where,
                  column + " is nan for " + (label ? *label : std::string("the scored row")) +
                      ": the 95% interval of " + base + " is undefined (" + why +
                      "), so no point could meet a bound on it; run more frames "
                      "(frames.count, docs/intervals.md) or bound " +
                      base + " itself");
    }
  };
  for (auto& k : sp.constraints) check(k.column, "sweep.search.subject_to." + k.column);
  check(sp.objective.column, "sweep.search");
}

namespace {

// The jobs of one batch of points of context `ci`, each point's folder appended to `dirs`. A
// point whose folder holds a complete evaluation is not run again (counted in `cached`).
std::vector<CellJob> batch_jobs(const std::vector<std::vector<double>>& pts, const SweepCell& ctx,
                                int ci, const SearchSpec& sp, const std::string& evals_dir,
                                const LoadedConfig& cfg, const SweepOptions& opt,
                                std::vector<std::string>& dirs, int& cached, int& stale) {
  std::vector<CellJob> jobs;
  for (auto& x : pts) {
    Json doc = ctx.doc;
    for (size_t d = 0; d < x.size(); ++d)
      apply_assignment(doc, sp.space[d].path, Json(x[d]), sp.space[d].where);
    std::string h = short_hash(doc.dump());
    std::string dir = evals_dir + "/" + h;
    dirs.push_back(dir);
    if (cached_eval_complete(dir + "/done.json", sp, stale)) {
      ++cached;
      continue;
    }
    CellJob j;
    j.doc = std::move(doc);
    j.file = cfg.file;
    j.origins = cfg.overridden;
    j.inherited = cfg.inherited;
    j.base_dir = cfg.base_dir;
    j.out_dir = dir;
    j.command_line = opt.command_line;
    j.extra_manifest = Json{{"search", {{"context", ci}, {"hash", h}}}};
    jobs.push_back(std::move(j));
  }
  return jobs;
}

// The per-point inputs of the search's verdict (search_verdict.h), kept in done.json: the
// scored row's p95 frame time, budget, the objective's 95% half-width and per-frame values
// (its start-up frames left out, as the means do), and the frame-budget columns of the first
// `full` entry of the run (the unfoveated frame: when it fits, no budget binds).
Json verdict_inputs(const CellResult& res, const ResultRow& r, const SearchSpec& sp) {
  auto num = [](double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); };
  const std::string& col = sp.objective.column;
  Json v{{"est_ms_total_p95", num(r.get("est_ms_total_p95", NAN))},
         {"budget_ms", num(r.get("budget_ms", NAN))},
         {"score_ci95", num(r.get(col + "_ci95", NAN))}};
  const std::string* id = r.text_of("config_id");
  Json frames = Json::array();
  int skip = int(r.get("startup_frames", 0));
  bool has_col = false;
  for (auto& f : res.frames.rows()) {
    const std::string* fid = f.text_of("config_id");
    if (!id || !fid || *fid != *id) continue;
    if (skip > 0) {
      --skip;
      continue;
    }
    const double x = f.get(col, NAN);
    has_col = has_col || !std::isnan(x);
    frames.push_back(num(x));
  }
  if (has_col) v["frame_scores"] = frames;
  // JOD against native resolution (jod_fidelity.h): a JOD constraint's margin or "needs native".
  if (res.fidelity.is_object() && res.fidelity.contains("jod")) v["jod"] = res.fidelity["jod"];
  for (auto& o : res.summary.rows()) {
    const std::string* m = o.text_of("method");
    const std::string* l = o.text_of("label");
    if (!m || *m != "full" || &o == &r) continue;
    Json fc{{"label", l ? *l : std::string("full")},
            {"est_ms_total_p95", num(o.get("est_ms_total_p95", NAN))},
            {"budget_ms", num(o.get("budget_ms", NAN))}};
    for (auto& k : sp.constraints) fc[k.column] = num(o.get(k.column, NAN));
    v["full"] = fc;
    break;
  }
  return v;
}

// Runs a batch's jobs, one reference pass per reference group, and records each point's
// scored columns in its done.json.
void run_batch(std::vector<CellJob>& jobs, const EngineOptions& eo, const SweepPlan& plan,
               const LoadedConfig& cfg) {
  const SearchSpec& sp = plan.search;
  // One reference pass per batch (all points of a context share the reference key).
  std::map<std::string, std::vector<CellJob>> groups;
  for (auto& j : jobs) groups[reference_key(j.doc)].push_back(std::move(j));
  for (auto& [k, js] : groups) {
    auto res = run_cells(js, eo);
    for (size_t i = 0; i < res.size(); ++i) {
      const ResultRow* r = scored_row(res[i].summary, sp.select_label);
      if (!r)
        throw Error(cfg.file + ": sweep.search.label",
                    "no method labelled \"" + sp.select_label + "\"");
      // The objective and constraint name columns of the summary (else every score would
      // be NaN and the "best" arbitrary): checked on the first evaluation.
      check_plan_columns(plan, res[i].summary, true);
      refuse_undefined_bounds(*r, sp, cfg.file);
      auto num = [](double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); };
      // Every column a search may score, keyed by name: a rerun with another objective or
      // constraint reuses the run when its columns are here (cached_eval_complete).
      Json cols = Json::object();
      cols[sp.objective.column] = num(r->get(sp.objective.column, NAN));
      for (auto& k : sp.constraints) cols[k.column] = num(r->get(k.column, NAN));
      // Every candidate's probability of fitting the budget (sim/cost/budget.h), constrained
      // or not: search_history.csv reports it.
      cols["p_fit"] = num(r->get("p_fit", NAN));
      Json done{
          {"score", cols[sp.objective.column]}, {"columns", cols}, {"git_commit", git_commit()}};
      // What the verdict (search_verdict.h) needs: the frame time against the budget, the
      // score's interval and per-frame values, and `full`'s frame time when the run has it.
      done["verdict"] = verdict_inputs(res[i], *r, sp);
      write_file_atomic(js[i].out_dir + "/done.json", done.dump() + "\n");
    }
  }
}

// The frame time and its limit of frame-budget constraint `c` at a point whose value of c's
// column is `value` (v: the point's verdict inputs); false when c sets no upper limit on time.
bool frame_budget_terms(const SearchConstraint& c, double value, const Json& v, double& ms,
                        double& limit) {
  auto get = [&](const char* k) {
    return v.contains(k) && v[k].is_number() ? v[k].get<double>() : double(NAN);
  };
  const double budget = get("budget_ms");
  if (c.column == "headroom_ms") {  // budget - p95 >= min
    if (!std::isfinite(c.min)) return false;
    ms = budget - value;
    limit = budget - c.min;
  } else if (c.column == "fits_budget" || c.column == "p_fit") {  // the p95 frame's decision
    if (!std::isfinite(c.min) || c.min <= 0) return false;
    ms = get("est_ms_total_p95");
    limit = budget;
  } else {  // est_ms_total and its percentiles or interval ends: <= max
    if (!std::isfinite(c.max)) return false;
    ms = value;
    limit = c.max;
  }
  return true;
}

std::vector<double> frame_scores(const Json& v) {
  std::vector<double> out;
  if (!v.contains("frame_scores") || !v["frame_scores"].is_array()) return out;
  for (auto& x : v["frame_scores"]) out.push_back(x.is_number() ? x.get<double>() : NAN);
  return out;
}

std::string point_text(const SearchSpec& sp, const std::vector<double>& x) {
  std::string at;
  for (size_t d = 0; d < x.size() && d < sp.space.size(); ++d)
    at += (d ? ", " : "") + sp.space[d].path + " = " + format_number(x[d]);
  return at;
}

// The verdict of context `ctx` (search_verdict.h) into its search_best.csv row `b` and
// `lines`: does the budget bind, is the optimum on an end of the space, is the winner ahead
// of the runner-up beyond noise. `cv[i]` and `vin[i]` belong to s.history()[i].
void add_verdict(ResultRow& b, const SearchSpec& sp, const Searcher& s,
                 const std::vector<std::pair<std::vector<double>, std::vector<double>>>& cv,
                 const std::vector<Json>& vin, std::vector<std::string>& lines) {
  const auto& hist = s.history();
  const size_t n = hist.size();
  if (!s.has_best() || n == 0 || cv.size() != n || vin.size() != n) return;
  const SearchEval& w = s.best();
  // (a) Does a constraint bind?
  if (!sp.constraints.empty()) {
    double budget_binds = NAN;
    bool any_violated = false;
    SearchSpec other;  // the constraints that are not frame budgets
    std::vector<std::vector<double>> other_values(n);
    for (size_t k = 0; k < sp.constraints.size(); ++k) {
      const SearchConstraint& c = sp.constraints[k];
      size_t violators = 0;
      for (size_t i = 0; i < n; ++i) {
        const double x = cv[i].second[k];
        if (std::isnan(x) || x < c.min || x > c.max) ++violators;
      }
      any_violated = any_violated || violators > 0;
      if (!is_frame_budget_column(c.column)) {
        other.constraints.push_back(c);
        for (size_t i = 0; i < n; ++i) other_values[i].push_back(cv[i].second[k]);
        continue;
      }
      double ms = NAN, limit = NAN;
      if (!frame_budget_terms(c, 0, vin[0], ms, limit)) continue;
      if (violators > 0) {
        budget_binds = 1;
        lines.push_back("budget binds: " + std::to_string(violators) + " of " + std::to_string(n) +
                        " evaluated points miss " + c.describe());
        continue;
      }
      if (std::isnan(budget_binds)) budget_binds = 0;
      std::string sentence;
      const Json& f = vin[size_t(0)].contains("full") ? vin[0]["full"] : Json();
      if (f.is_object() && f.contains(c.column) && f[c.column].is_number()) {
        const double fx = f[c.column].get<double>();
        if (fx >= c.min && fx <= c.max && frame_budget_terms(c, fx, f, ms, limit))
          sentence =
              budget_sentence("unfoveated " + f.value("label", std::string("full")), ms, limit);
      }
      if (sentence.empty()) {  // the most expensive evaluated point
        size_t worst = 0;
        double worst_ms = -INFINITY;
        for (size_t i = 0; i < n; ++i) {
          double m = NAN, l = NAN;
          if (frame_budget_terms(c, cv[i].second[k], vin[i], m, l) && m > worst_ms)
            worst = i, worst_ms = m, ms = m, limit = l;
        }
        sentence = budget_sentence("the most expensive of the " + std::to_string(n) +
                                       " evaluated points (" + point_text(sp, hist[worst].x) + ")",
                                   ms, limit);
      }
      if (!sentence.empty()) lines.push_back(sentence + " (" + c.describe() + ")");
    }
    for (auto& l : non_binding_constraints(other, other_values)) lines.push_back(l);
    // (a') A JOD constraint below native resolution: judged with its measured bias, or the
    // answer needs native resolution (jod_fidelity.h).
    const Json jod = vin[0].contains("jod") ? vin[0]["jod"] : Json();
    bool needs_native = false;
    for (auto& c : sp.constraints) {
      const JodJudgement j = judge_jod(c, jod);
      const std::string line = jod_verdict_sentence(c, j, jod);
      if (line.empty()) continue;
      lines.push_back(line);
      needs_native = needs_native || j.needs_native;
    }
    if (jod.is_object() && !jod.value("native", true))
      b.set("needs_native_resolution", needs_native ? 1 : 0);
    if (!std::isnan(budget_binds)) b.set("budget_binds", budget_binds);
    b.set("constraints_bind", any_violated ? 1 : 0);
  }
  // (b) The optimum on an end of the space.
  if (w.violation <= 0) {
    const auto hits = boundary_hits(sp.space, w.x);
    std::string axes;
    for (auto& h : hits)
      axes += (axes.empty() ? "" : " ") + sp.space[h.dim].path + (h.end < 0 ? ":lower" : ":upper");
    b.set_text("boundary", axes);
    if (!hits.empty()) lines.push_back(describe_boundary(sp.space, hits));
  }
  // (c) Winner against the runner-up (the best other point; a feasible winner's runner-up
  // must be feasible too).
  const SearchEval* r = nullptr;
  size_t ri = 0, wi = 0;
  for (size_t i = 0; i < n; ++i) {
    if (hist[i].x == w.x) {
      wi = i;
      continue;
    }
    if (!r || s.better(hist[i], *r)) r = &hist[i], ri = i;
  }
  if (!r || (w.violation <= 0 && r->violation > 0)) return;
  auto ci = [&](size_t i) {
    return vin[i].contains("score_ci95") && vin[i]["score_ci95"].is_number()
               ? vin[i]["score_ci95"].get<double>()
               : double(NAN);
  };
  const std::vector<double> fw = frame_scores(vin[wi]), fr = frame_scores(vin[ri]);
  const ScoreComparison c = compare_scores(w.score, r->score, fw, fr, ci(wi), ci(ri));
  b.set("runner_up_delta", c.delta);
  b.set("runner_up_delta_ci95", c.ci95);
  if (c.tied >= 0) b.set("tied", c.tied);
  lines.push_back(describe_comparison(c, sp.objective.column) + "; runner-up at " +
                  point_text(sp, r->x));
}

// search_best.csv's row of context `ci` after `n` evaluations; a context without a feasible
// point adds a note naming the least violation.
ResultRow best_row(const SweepCell& ctx, int ci, int n, const SearchSpec& sp, const Searcher& s,
                   const std::vector<std::pair<std::vector<double>, std::vector<double>>>& seen_cv,
                   std::vector<std::string>& notes) {
  ResultRow b;
  b.set_text("context_id", ctx.id());
  for (auto& a : ctx.assign)
    if (a.value.is_string()) b.set_text(a.path, a.value.get<std::string>());
  b.set("context", ci);
  for (auto& a : ctx.assign)
    if (a.value.is_number()) b.set(a.path, a.value.get<double>());
  b.set("evaluations", n);
  if (s.has_best()) {
    for (size_t d = 0; d < s.best().x.size(); ++d) b.set(sp.space[d].path, s.best().x[d]);
    b.set(sp.objective.column, s.best().score);
    b.set("feasible", s.best().violation <= 0 ? 1 : 0);
    if (!sp.constraints.empty()) {
      std::vector<double> cv(sp.constraints.size(), NAN);
      for (auto& [x, v] : seen_cv)
        if (x == s.best().x) cv = v;
      std::string limits, values;
      for (size_t k = 0; k < cv.size(); ++k) {
        b.set(sp.constraints[k].column, cv[k]);
        limits += (k ? ", " : "") + sp.constraints[k].describe();
        values += (k ? ", " : "") + sp.constraints[k].column + " = " + format_number(cv[k]);
      }
      b.set("violation", s.best().violation);
      if (s.best().violation > 0) {
        // Nothing met the constraint: the "best" is the point of least violation, said so.
        std::string at;
        for (size_t d = 0; d < s.best().x.size(); ++d)
          at += (d ? ", " : "") + sp.space[d].path + " = " + format_number(s.best().x[d]);
        notes.push_back("context " + ctx.id() + ": no feasible point in " + std::to_string(n) +
                        " evaluations (" + limits + "); least violation " +
                        format_number(s.best().violation) + " (" + values + ") at " + at +
                        ": widen sweep.search.space or relax the constraint");
      }
    }
  }
  return b;
}

}  // namespace

namespace {

// One context's search of one plan (its sweep.search): the searcher after its evaluations,
// each point's constraint values and verdict inputs; history rows appended to `history`.
struct ContextSearch {
  explicit ContextSearch(Searcher s) : searcher(std::move(s)) {}
  Searcher searcher;
  int evaluations = 0;
  std::vector<std::pair<std::vector<double>, std::vector<double>>> seen_cv;
  std::vector<Json> vin;  // each point's verdict inputs (done.json "verdict"), history order
};

ContextSearch search_context(const SweepPlan& plan, const SweepCell& ctx, int ci,
                             const LoadedConfig& cfg, const SweepOptions& opt,
                             const EngineOptions& eo, const std::string& evals_dir,
                             ResultTable& history, Progress& progress, SearchReport& rep,
                             bool with_label) {
  const SearchSpec& sp = plan.search;
  ContextSearch cs(Searcher(sp.space, sp.objective.maximize, sp.seed + uint64_t(ci), sp.batch));
  Searcher& s = cs.searcher;
  int& n = cs.evaluations;
  while (n < sp.evaluations) {
    auto pts = s.ask();
    if (pts.empty()) break;
    if (int(pts.size()) > sp.evaluations - n) pts.resize(size_t(sp.evaluations - n));
    std::vector<std::string> dirs;
    std::vector<CellJob> jobs =
        batch_jobs(pts, ctx, ci, sp, evals_dir, cfg, opt, dirs, rep.cached, rep.stale);
    run_batch(jobs, eo, plan, cfg);
    std::vector<SearchEval> ev;
    for (size_t i = 0; i < pts.size(); ++i) {
      const std::string done_path = dirs[i] + "/done.json";
      Json done = parse_json_text(read_file(done_path), done_path);
      SearchEval e;
      e.x = pts[i];
      const Json& cols = done["columns"];
      auto col = [&](const std::string& c) {
        return cols.contains(c) && cols[c].is_number() ? cols[c].get<double>() : NAN;
      };
      e.score = col(sp.objective.column);
      std::vector<double> cv, margins;
      const Json& vj = done.contains("verdict") ? done["verdict"] : Json::object();
      const Json jod = vj.contains("jod") ? vj["jod"] : Json();
      for (auto& k : sp.constraints) {
        cv.push_back(col(k.column));
        margins.push_back(judge_jod(k, jod).margin);  // 0 unless a JOD column below native
      }
      e.violation = sp.violation(cv, margins);
      ev.push_back(e);
      cs.seen_cv.emplace_back(e.x, cv);
      cs.vin.push_back(done.contains("verdict") ? done["verdict"] : Json::object());
      ResultRow h;
      h.set_text("context_id", ctx.id());
      if (with_label) h.set_text("label", sp.select_label);  // a method axis
      h.set_text("eval_dir", "search/evals/" + dirs[i].substr(dirs[i].rfind('/') + 1));
      h.set("context", ci);
      h.set("eval", n + int(i));
      for (size_t d = 0; d < e.x.size(); ++d) h.set(sp.space[d].path, e.x[d]);
      h.set(sp.objective.column, e.score);
      for (size_t k = 0; k < cv.size(); ++k) {
        h.set(sp.constraints[k].column, cv[k]);
        if (!jod_metric_of(sp.constraints[k].column).empty() && jod.is_object() &&
            !jod.value("native", true))  // the margin it was judged with (NaN: none measured)
          h.set(sp.constraints[k].column + "_bias", jod_bias_of(jod, sp.constraints[k].column));
      }
      h.set("p_fit", col("p_fit"));  // (a p_fit constraint set it already: the same value)
      h.set("feasible", e.violation <= 0 ? 1 : 0);
      history.add(std::move(h));
    }
    n += int(pts.size());
    progress.step(pts.size());
    s.tell(ev);
  }
  if (n < sp.evaluations) progress.step(size_t(sp.evaluations - n));  // the searcher stopped
  return cs;
}

// A method's best point, as the comparison across methods needs it.
struct MethodWinner {
  std::string label, at;  // "methods[kfr].sigma = 1.6"
  bool found = false;
  double score = NAN, violation = INFINITY, ci95 = NAN;
  std::vector<double> frames;
};

MethodWinner method_winner(const SearchSpec& sp, const ContextSearch& cs) {
  MethodWinner w;
  w.label = sp.select_label;
  const Searcher& s = cs.searcher;
  if (!s.has_best()) return w;
  w.found = true;
  w.score = s.best().score;
  w.violation = s.best().violation;
  w.at = point_text(sp, s.best().x);
  const auto& hist = s.history();
  for (size_t i = 0; i < hist.size() && i < cs.vin.size(); ++i)
    if (hist[i].x == s.best().x) {
      w.frames = frame_scores(cs.vin[i]);
      if (cs.vin[i].contains("score_ci95") && cs.vin[i]["score_ci95"].is_number())
        w.ci95 = cs.vin[i]["score_ci95"].get<double>();
      break;
    }
  return w;
}

// "across methods: kfr (methods[kfr].sigma = 1.6) wins; winner and runner-up tied within noise
// (...); runner-up rmfr (...)": feasible winners before infeasible ones, then the objective.
std::string compare_methods(std::vector<MethodWinner> ws, const Objective& obj) {
  ws.erase(std::remove_if(ws.begin(), ws.end(), [](const MethodWinner& w) { return !w.found; }),
           ws.end());
  if (ws.size() < 2) return "";
  auto better = [&](const MethodWinner& a, const MethodWinner& b) {
    const bool fa = a.violation <= 0, fb = b.violation <= 0;
    if (fa != fb) return fa;
    if (!fa) return a.violation < b.violation;
    if (std::isnan(b.score)) return !std::isnan(a.score);
    if (std::isnan(a.score)) return false;
    return obj.maximize ? a.score > b.score : a.score < b.score;
  };
  std::stable_sort(ws.begin(), ws.end(), better);
  const MethodWinner &w = ws[0], &r = ws[1];
  std::string line = "across methods: " + w.label + " (" + w.at + ") wins";
  if (w.violation > 0) return line + ", but no method has a feasible point";
  if (r.violation > 0) return line + "; no other method has a feasible point";
  const ScoreComparison c = compare_scores(w.score, r.score, w.frames, r.frames, w.ci95, r.ci95);
  return line + "; " + describe_comparison(c, obj.column) + "; runner-up " + r.label + " (" + r.at +
         ")";
}

}  // namespace

SearchReport run_search(const SweepPlan& plan, const LoadedConfig& cfg, const SweepOptions& opt) {
  const SearchSpec& sp = plan.search;
  if (!sp.enabled())
    throw Error(cfg.file + ": sweep.search",
                "missing: a search needs sweep.search.space and an objective");
  const auto threads = thread_limit(opt.threads);
  SearchReport rep;
  rep.out_dir = sweep_out_dir(plan, opt.out_dir);
  const std::string evals_dir = rep.out_dir + "/search/evals";
  DirLock lock(rep.out_dir, ".lock", "another fovsim search or sweep");
  make_dirs(evals_dir);
  EngineOptions eo;
  eo.models_dir = opt.models_dir;
  eo.print_summary = false;
  eo.threads = opt.threads;
  eo.use_cache = opt.use_cache;

  ResultTable history, best;
  Json verdicts = Json::array();
  // One search per method entry with a method axis (sweep.search.methods), else one.
  std::vector<SweepPlan> subs;
  for (const SearchSpec& one : sp.per_method()) {
    subs.push_back(plan);
    subs.back().search = one;
  }
  const bool axis = subs.size() > 1;
  auto [first, last] = shard_range(int(plan.cells.size()), opt.shard, opt.shards);
  Progress progress("search evaluations", size_t(std::max(0, last - first)) * subs.size() *
                                              size_t(std::max(0, sp.evaluations)));
  for (int ci = first; ci < last; ++ci) {
    const SweepCell& ctx = plan.cells[size_t(ci)];
    ++rep.contexts;
    std::vector<MethodWinner> winners;
    for (const SweepPlan& sub : subs) {
      const SearchSpec& msp = sub.search;
      ContextSearch cs =
          search_context(sub, ctx, ci, cfg, opt, eo, evals_dir, history, progress, rep, axis);
      rep.evaluations += cs.evaluations;
      ResultRow b = best_row(ctx, ci, cs.evaluations, msp, cs.searcher, cs.seen_cv, rep.notes);
      if (axis) b.set_text("label", msp.select_label);
      std::vector<std::string> lines;
      add_verdict(b, msp, cs.searcher, cs.seen_cv, cs.vin, lines);
      std::string joined;
      for (auto& l : lines) joined += (joined.empty() ? "" : "; ") + l;
      b.set_text("verdict", joined);
      Json vj{{"context_id", ctx.id()}, {"context", ci}, {"verdict", lines}};
      if (axis) vj["label"] = msp.select_label;
      verdicts.push_back(vj);
      const std::string who = "context " + ctx.id() + (axis ? " " + msp.select_label : "") + ": ";
      for (auto& l : lines) rep.verdicts.push_back(who + l);
      if (axis) winners.push_back(method_winner(msp, cs));
      best.add(std::move(b));
    }
    if (axis) {  // the methods' winners against each other (docs/sweeps.md)
      const std::string line = compare_methods(winners, sp.objective);
      if (!line.empty()) {
        rep.verdicts.push_back("context " + ctx.id() + ": " + line);
        verdicts.push_back({{"context_id", ctx.id()}, {"context", ci}, {"across_methods", line}});
      }
    }
  }
  std::string suffix =
      opt.shards > 1 ? ".shard" + std::to_string(opt.shard) + "of" + std::to_string(opt.shards)
                     : "";
  write_file_atomic(rep.out_dir + "/search_history" + suffix + ".csv", history.to_csv());
  write_file_atomic(rep.out_dir + "/search_best" + suffix + ".csv", best.to_csv());
  write_file_atomic(rep.out_dir + "/search_verdict" + suffix + ".json", verdicts.dump(2) + "\n");
  rep.best = std::move(best);
  if (rep.stale > 0)
    rep.notes.push_back(
        std::to_string(rep.stale) + " evaluation" + (rep.stale == 1 ? "" : "s") + " found in " +
        rep.out_dir + " came from another build of fovsim (git_commit differs from " +
        git_commit() + ") and " + (rep.stale == 1 ? "was" : "were") + " evaluated again");
  return rep;
}

}  // namespace fovsim
