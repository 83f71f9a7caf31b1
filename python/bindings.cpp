// pybind11 module `_fovsim`: run a config, run a sweep, an evaluation hook for outside
// optimisers, the ask/tell searcher of `fovsim search` (sim/experiment/search.h), and the cost
// model's per-frame estimate (what `fovsim predict` / `fovsim budget` compute) and re-costing
// of a finished run, on the same library as the CLI. Kept thin: tables and derived columns
// are built in python/fovsim (engine.py, cost.py); docs/python.md. Library errors
// (fovsim::Error: location + message) become FovsimError.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <map>
#include <string>
#include <vector>

#include "sim/core/disk_cache.h"
#include "sim/core/error.h"
#include "sim/core/params.h"
#include "sim/cost/analytic.h"
#include "sim/cost/budget.h"
#include "sim/cost/cost_model.h"
#include "sim/cost/gpu_profile.h"
#include "sim/cost/passes.h"
#include "sim/cost/workload.h"
#include "sim/experiment/config.h"
#include "sim/experiment/cost_queries.h"
#include "sim/experiment/info.h"
#include "sim/experiment/intervals.h"
#include "sim/experiment/recost.h"
#include "sim/experiment/runner.h"
#include "sim/experiment/search.h"
#include "sim/experiment/sweep_runner.h"
#include "sim/experiment/sweep_spec.h"
#include "sim/foveation/factory.h"

namespace py = pybind11;
using namespace fovsim;

namespace {

py::list rows_to_list(const ResultTable& t) {
  py::list out;
  for (auto& r : t.rows()) {
    py::dict d;
    for (auto& [k, v] : r.text) d[py::str(k)] = v;
    for (auto& [k, v] : r.num) d[py::str(k)] = v;
    out.append(d);
  }
  return out;
}

struct RunOut {
  std::string out_dir;
  ResultTable summary;
  size_t frame_rows = 0;
};

// The run options `fovsim run` and `fovsim sweep` share (RunControl, run_options.h), checked
// with the CLI's ranges; a bad --target spec fails before any work.
RunControl run_control(int threads, const std::string& models, double watchdog, bool cache,
                       const std::vector<std::string>& targets) {
  RunControl c;
  c.threads = int(check_integer("threads", threads, RunControl::threads_range()));
  c.models_dir = models;
  c.watchdog_s = RunControl::check_watchdog("watchdog", watchdog);
  // The reference cache as in `fovsim run` (config cache.*; FOVSIM_NO_CACHE=1 turns it off).
  c.use_cache = cache && !cache_disabled_by_env();
  for (auto& t : targets) (void)parse_target(t);
  c.targets = targets;
  return c;
}

RunOut run_one(const std::string& config, const std::vector<std::string>& overrides,
               const std::string& out, const RunControl& control) {
  LoadedConfig cfg = load_config(config, overrides);
  RunOptions opt;
  static_cast<RunControl&>(opt) = control;
  opt.out_dir = out;
  opt.print_summary = false;
  opt.command_line = "python: fovsim.run " + config;
  for (auto& o : overrides) opt.command_line += " " + o;
  RunResult r = run_experiment(cfg, opt);
  return {r.out_dir, r.summary, r.frames.rows().size()};
}

py::dict run_py(const std::string& config, const std::vector<std::string>& overrides,
                const std::string& out, int threads, const std::string& models, double watchdog,
                bool cache, const std::vector<std::string>& targets) {
  const RunControl control = run_control(threads, models, watchdog, cache, targets);
  RunOut r;
  {
    py::gil_scoped_release nogil;
    r = run_one(config, overrides, out, control);
  }
  py::dict d;
  d["out_dir"] = r.out_dir;
  d["summary"] = rows_to_list(r.summary);
  d["frame_rows"] = r.frame_rows;
  return d;
}

py::dict sweep_py(const std::string& config, const std::vector<std::string>& overrides,
                  const std::string& out, int threads, const std::string& models, double watchdog,
                  bool cache, const std::vector<std::string>& targets) {
  const RunControl control = run_control(threads, models, watchdog, cache, targets);
  SweepReport r;
  {
    py::gil_scoped_release nogil;
    LoadedConfig cfg = load_config(config, overrides);
    SweepPlan plan = expand_sweep(cfg);
    validate_cells(plan);
    SweepOptions opt;
    static_cast<RunControl&>(opt) = control;
    opt.out_dir = out;
    opt.command_line = "python: fovsim.sweep " + config;
    for (auto& o : overrides) opt.command_line += " " + o;
    r = run_sweep(plan, cfg, opt);
  }
  py::dict d;
  d["out_dir"] = r.out_dir;
  d["cells_total"] = r.cells_total;
  d["cells_run"] = r.cells_run;
  d["cells_done_before"] = r.cells_done_before;
  d["cells_other_build"] = r.cells_other_build;  // complete cells another build made: recomputed
  d["complete"] = r.complete;
  return d;
}

// Evaluation hook: the optimiser (outside) asks for points, this evaluates each point as
// `config + base overrides + the point's overrides` and returns its summary rows; the
// optimiser is told the objective it reads from them. Point n is written to <out>/eval_<n>.
class Evaluator {
 public:
  // threads, models, watchdog, cache, targets: fovsim.run's run options (run_control).
  Evaluator(std::string config, std::vector<std::string> overrides, std::string out, int threads,
            const std::string& models, double watchdog, bool cache,
            const std::vector<std::string>& targets)
      : config_(std::move(config)),
        base_(std::move(overrides)),
        out_(std::move(out)),
        control_(run_control(threads, models, watchdog, cache, targets)) {
    if (out_.empty()) throw Error("Evaluator(out=...)", "an output folder is required");
    load_config(config_, base_);  // fail early on a bad config or override
  }

  py::list evaluate(const std::vector<std::vector<std::string>>& points) {
    py::list res;
    for (auto& p : points) {
      std::vector<std::string> ov = base_;
      ov.insert(ov.end(), p.begin(), p.end());
      std::string dir = out_ + "/eval_" + std::to_string(count_++);
      RunOut r;
      {
        py::gil_scoped_release nogil;
        r = run_one(config_, ov, dir, control_);
      }
      res.append(rows_to_list(r.summary));
    }
    return res;
  }
  int evaluations() const { return count_; }

 private:
  std::string config_;
  std::vector<std::string> base_;
  std::string out_;
  RunControl control_;
  int count_ = 0;
};

// JSON text -> Python object through the json module (params, nested dicts).
template <class J>
py::object from_json(const J& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

// `fovsim predict` / `fovsim budget` as the CLI computes them (sim/experiment/cost_queries.h):
// the same rows, the same checks. Python's argument names locate the errors.
CostTarget py_cost_target(const std::vector<std::string>& gpus, const std::string& workload,
                          const std::vector<std::string>& methods, const std::string& display,
                          double width, double height, double eyes, const std::string& models) {
  check_cost_args(width, height, eyes, 0, {});  // floats from Python: checked before the cast
  CostTarget t;
  t.models = models.empty() ? default_models_dir() : models;
  t.display = display.empty() ? std::string(kDefaultDisplay) : display;
  t.workload = workload;
  t.gpus = gpus;
  t.methods = methods;
  t.width = int(width), t.height = int(height), t.eyes = int(eyes);
  t.where_method = "method", t.where_workload = "workload", t.where_gpu = "gpu";
  t.workload_hint = "";
  return t;
}

py::list rows_py(const CostRows& r) {
  py::list out;
  for (auto& j : r.rows) out.append(from_json(j));  // key order kept: the CLI's --json order
  return out;
}

py::list predict_py(const std::vector<std::string>& gpus, const std::string& workload,
                    const std::vector<std::string>& methods, const std::string& display,
                    double width, double height, double eyes, const std::string& models) {
  return rows_py(
      predict_rows(py_cost_target(gpus, workload, methods, display, width, height, eyes, models)));
}

py::list budget_py(const std::vector<std::string>& gpus, const std::string& workload,
                   const std::vector<std::string>& methods, const std::string& display,
                   double width, double height, double eyes, const std::string& models,
                   double budget_ms, double level, const std::map<std::string, double>& scale) {
  return rows_py(
      budget_rows(py_cost_target(gpus, workload, methods, display, width, height, eyes, models),
                  budget_ms, level, what_if_from(scale, "scale")));
}

// `fovsim predict --results DIR`: a finished run's measured counters re-costed (recost.h).
py::list recost_py(const std::string& results, const std::vector<std::string>& gpus,
                   const std::string& display, double width, double height, double eyes,
                   const std::string& workload, const std::string& models) {
  check_cost_args(width, height, eyes, 0, {});  // the flags' ranges, as predict --results
  RecostOptions o;
  o.results = results;
  o.models = models.empty() ? default_models_dir() : models;
  o.gpus = gpus;
  o.display = display;
  o.width = int(width);
  o.height = int(height);
  o.eyes = int(eyes);
  o.workload = workload;
  RecostResult res;
  {
    py::gil_scoped_release nogil;
    res = recost_results(o);
  }
  py::list out;
  for (auto& x : res.rows) {
    py::dict r;
    r["label"] = x.label;  // first: two configurations may share a method (full, fir)
    r["gpu"] = x.gpu;
    r["config_id"] = x.config_id;
    r["method"] = x.method;
    r["frames"] = x.frames;
    r["display"] = res.display.name;
    r["width"] = res.display.width;
    r["height"] = res.display.height;
    r["eyes"] = res.display.eyes;
    r["workload"] = res.workload;
    r["est_ms_total"] = x.total_ms;
    if (x.level > 0) {
      r["est_ms_total_lo"] = x.lo_ms;
      r["est_ms_total_hi"] = x.hi_ms;
      r["interval_level"] = x.level;
    }
    py::dict passes;
    for (auto& [k, v] : x.pass_ms) passes[py::str(k)] = v;
    r["passes"] = passes;
    out.append(r);
  }
  return out;
}

// Ask/tell over the search space of `fovsim search` (sweep.search in a config, or given here
// as the same JSON): the Searcher of sim/experiment/search.h proposes, the caller evaluates.
// `search_json` (may be empty: the config's own sweep.search) is validated by expand_sweep, so
// errors read as for `fovsim search`.
class AskTell {
 public:
  AskTell(const std::string& config, const std::vector<std::string>& overrides,
          const std::string& search_json)
      : spec_(load_spec(config, overrides, search_json)),
        searcher_(spec_.space, spec_.objective.maximize, spec_.seed, spec_.batch) {}

  std::vector<std::vector<double>> ask() { return searcher_.ask(); }
  // `checked` false: the scores came from runs' summaries (scored like `fovsim search`); the
  // points are checked either way. A bad point or value is a ValueError (check_told's message).
  void tell(const std::vector<std::vector<double>>& xs, const std::vector<double>& scores,
            const std::vector<double>& violations, bool checked) {
    if (xs.size() != scores.size() || xs.size() != violations.size())
      throw Error("AskTell.tell", "points, scores and violations differ in length");
    std::vector<SearchEval> ev(xs.size());
    for (size_t i = 0; i < xs.size(); ++i) {
      ev[i] = {xs[i], scores[i], violations[i]};
      try {
        check_told(spec_.space, ev[i], "AskTell.tell", checked);
      } catch (const Error& e) {
        throw py::value_error(e.what());
      }
    }
    searcher_.tell(ev);
  }
  py::dict spec() const {
    py::dict d;
    py::list dims;
    for (auto& s : spec_.space) {
      py::dict x;
      x["path"] = s.path;
      x["lo"] = s.lo;
      x["hi"] = s.hi;
      x["step"] = s.step;
      x["log"] = s.log;
      x["integer"] = s.integer;
      dims.append(x);
    }
    d["space"] = dims;
    d["objective"] = spec_.objective.column;
    d["maximize"] = spec_.objective.maximize;
    py::list cons;  // subject_to: [{"column", "min", "max"}] (absent bounds are -inf/inf)
    for (auto& k : spec_.constraints) {
      py::dict c;
      c["column"] = k.column;
      c["min"] = k.min;
      c["max"] = k.max;
      cons.append(c);
    }
    d["constraints"] = cons;
    d["label"] = spec_.select_label;
    d["evaluations"] = spec_.evaluations;
    d["batch"] = spec_.batch;
    d["seed"] = spec_.seed;
    return d;
  }
  py::object best() const {
    if (!searcher_.has_best()) return py::none();
    const SearchEval& b = searcher_.best();
    py::dict d;
    d["x"] = b.x;
    d["score"] = b.score;
    d["violation"] = b.violation;
    return d;
  }
  size_t told() const { return searcher_.history().size(); }
  double step() const { return searcher_.step(); }

 private:
  static SearchSpec load_spec(const std::string& config, const std::vector<std::string>& overrides,
                              const std::string& search_json) {
    LoadedConfig cfg = load_config(config, overrides);
    if (!search_json.empty()) {
      Json s = parse_json_text(search_json, "AskTell(search=...)");
      if (!cfg.doc.contains("sweep") || !cfg.doc["sweep"].is_object())
        cfg.doc["sweep"] = Json::object();
      cfg.doc["sweep"]["search"] = s;
    }
    SweepPlan plan = expand_sweep(cfg);  // the objective's and constraints' columns
    if (!plan.search.enabled())
      throw Error(config + ": sweep.search",
                  "no search space (give space=... or a config with sweep.search, "
                  "docs/sweeps.md)");
    if (!plan.search.methods.empty())
      throw Error(config + ": sweep.search.methods",
                  "a method axis runs in `fovsim search`; AskTell searches one space (give "
                  "space and label)");
    // As `fovsim search` before its first evaluation: the space's paths and ends, the label.
    validate_cells(plan);
    return plan.search;
  }
  SearchSpec spec_;
  Searcher searcher_;
};

}  // namespace

PYBIND11_MODULE(_fovsim, m) {
  m.doc() =
      "fovsim C++ engine (run, sweep, evaluation hook); use the fovsim package (python/fovsim)";
  static py::exception<Error> fovsim_error(m, "FovsimError", PyExc_RuntimeError);
  m.attr("DEFAULT_DISPLAY") = kDefaultDisplay;  // the one default, for python/fovsim
  m.attr("DEFAULT_GPU") = kDefaultGpu;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      fovsim_error(e.what());
    }
  });
  // The range checks of the CLI's flags (params.h), for the Python layer's own arguments.
  m.def(
      "check_number",
      [](const std::string& where, double v, double lo, double hi, bool lo_open) {
        return check_number(where, v, lo_open ? Range::above(lo, hi) : Range::closed(lo, hi));
      },
      py::arg("where"), py::arg("value"), py::arg("lo"), py::arg("hi"), py::arg("lo_open") = false);
  m.def(
      "check_integer",
      [](const std::string& where, double v, double lo, double hi) {
        return check_integer(where, v, Range::closed(lo, hi));
      },
      py::arg("where"), py::arg("value"), py::arg("lo"), py::arg("hi"));
  // `fovsim predict` / `budget` argument ranges by name (CostArgRanges): one declaration.
  m.def(
      "check_cost_arg",
      [](const std::string& name, double v) { return check_number(name, v, cost_arg_range(name)); },
      py::arg("name"), py::arg("value"));
  m.def(
      "info", [] { return info_json().dump(); },
      "`fovsim info --json` as a JSON string: methods, metric registry, column units, ranges");
  m.def("run", &run_py, py::arg("config"), py::arg("overrides") = std::vector<std::string>{},
        py::arg("out") = "", py::arg("threads") = 0, py::arg("models") = "",
        py::arg("watchdog") = 60.0, py::arg("cache") = false,
        py::arg("targets") = std::vector<std::string>{},
        "Runs one config (like `fovsim run`); returns {out_dir, summary (list of dicts), "
        "frame_rows}");
  m.def("sweep", &sweep_py, py::arg("config"), py::arg("overrides") = std::vector<std::string>{},
        py::arg("out") = "", py::arg("threads") = 0, py::arg("models") = "",
        py::arg("watchdog") = 60.0, py::arg("cache") = false,
        py::arg("targets") = std::vector<std::string>{},
        "Runs a sweep config (like `fovsim sweep`, resumable); returns a report dict");
  m.def("predict_rows", &predict_py, py::arg("gpus"), py::arg("workload"),
        py::arg("methods") = std::vector<std::string>{}, py::arg("display") = "",
        py::arg("width") = 0, py::arg("height") = 0, py::arg("eyes") = 0, py::arg("models") = "",
        "`fovsim predict --json`'s rows (GPU-major): the library function the CLI calls");
  m.def("budget_rows", &budget_py, py::arg("gpus"), py::arg("workload"),
        py::arg("methods") = std::vector<std::string>{}, py::arg("display") = "",
        py::arg("width") = 0, py::arg("height") = 0, py::arg("eyes") = 0, py::arg("models") = "",
        py::arg("budget_ms") = 0.0, py::arg("p") = kDefaultFitLevel,
        py::arg("scale") = std::map<std::string, double>{},
        "`fovsim budget --json`'s rows at fit level p with resources scaled: the library "
        "function the CLI calls");
  m.def("recost", &recost_py, py::arg("results"), py::arg("gpus"), py::arg("display") = "",
        py::arg("width") = 0, py::arg("height") = 0, py::arg("eyes") = 0, py::arg("workload") = "",
        py::arg("models") = "",
        "A finished run's counters re-costed for other GPUs/displays (fovsim predict --results)");
  py::class_<AskTell>(m, "AskTell")
      .def(py::init<std::string, std::vector<std::string>, std::string>(), py::arg("config"),
           py::arg("overrides") = std::vector<std::string>{}, py::arg("search") = "")
      .def("ask", &AskTell::ask, "Next batch of points (real units, one value per dimension)")
      .def("tell", &AskTell::tell, py::arg("points"), py::arg("scores"), py::arg("violations"),
           py::arg("checked") = true)
      .def_property_readonly("spec", &AskTell::spec)
      .def_property_readonly("best", &AskTell::best)
      .def_property_readonly("told", &AskTell::told)
      .def_property_readonly("step", &AskTell::step);
  py::class_<Evaluator>(m, "Evaluator")
      .def(py::init<std::string, std::vector<std::string>, std::string, int, const std::string&,
                    double, bool, const std::vector<std::string>&>(),
           py::arg("config"), py::arg("overrides") = std::vector<std::string>{},
           py::arg("out") = "", py::arg("threads") = 0, py::arg("models") = "",
           py::arg("watchdog") = 60.0, py::arg("cache") = false,
           py::arg("targets") = std::vector<std::string>{})
      .def("evaluate", &Evaluator::evaluate, py::arg("points"),
           "Evaluates each point (a list of key.path=value overrides); returns one summary (list "
           "of dicts) per point")
      .def_property_readonly("evaluations", &Evaluator::evaluations);
}
