// pybind11 module `_fovsim`: run a config, run a sweep, and an evaluation hook for outside
// (ask/tell) optimisers, on the same library as the CLI. Wrapped by python/fovsim/engine.py;
// docs/python.md. Library errors (fovsim::Error: location + message) become FovsimError.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "sim/core/error.h"
#include "sim/experiment/config.h"
#include "sim/experiment/runner.h"
#include "sim/experiment/sweep_runner.h"
#include "sim/experiment/sweep_spec.h"

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

RunOut run_one(const std::string& config, const std::vector<std::string>& overrides,
               const std::string& out, int threads, const std::string& models) {
  LoadedConfig cfg = load_config(config, overrides);
  RunOptions opt;
  opt.out_dir = out;
  opt.models_dir = models;
  opt.threads = threads;
  opt.print_summary = false;
  opt.command_line = "python: fovsim.run " + config;
  for (auto& o : overrides) opt.command_line += " " + o;
  RunResult r = run_experiment(cfg, opt);
  return {r.out_dir, r.summary, r.frames.rows().size()};
}

py::dict run_py(const std::string& config, const std::vector<std::string>& overrides,
                const std::string& out, int threads, const std::string& models) {
  RunOut r;
  {
    py::gil_scoped_release nogil;
    r = run_one(config, overrides, out, threads, models);
  }
  py::dict d;
  d["out_dir"] = r.out_dir;
  d["summary"] = rows_to_list(r.summary);
  d["frame_rows"] = r.frame_rows;
  return d;
}

py::dict sweep_py(const std::string& config, const std::vector<std::string>& overrides,
                  const std::string& out, int threads, const std::string& models) {
  SweepReport r;
  {
    py::gil_scoped_release nogil;
    LoadedConfig cfg = load_config(config, overrides);
    SweepPlan plan = expand_sweep(cfg);
    validate_cells(plan);
    SweepOptions opt;
    opt.out_dir = out;
    opt.models_dir = models;
    opt.threads = threads;
    opt.command_line = "python: fovsim.sweep " + config;
    for (auto& o : overrides) opt.command_line += " " + o;
    r = run_sweep(plan, cfg, opt);
  }
  py::dict d;
  d["out_dir"] = r.out_dir;
  d["cells_total"] = r.cells_total;
  d["cells_run"] = r.cells_run;
  d["cells_done_before"] = r.cells_done_before;
  d["complete"] = r.complete;
  return d;
}

// Evaluation hook: the optimiser (outside) asks for points, this evaluates each point as
// `config + base overrides + the point's overrides` and returns its summary rows; the
// optimiser is told the objective it reads from them. Point n is written to <out>/eval_<n>.
class Evaluator {
 public:
  Evaluator(std::string config, std::vector<std::string> overrides, std::string out, int threads,
            std::string models)
      : config_(std::move(config)),
        base_(std::move(overrides)),
        out_(std::move(out)),
        threads_(threads),
        models_(std::move(models)) {
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
        r = run_one(config_, ov, dir, threads_, models_);
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
  int threads_;
  std::string models_;
  int count_ = 0;
};

}  // namespace

PYBIND11_MODULE(_fovsim, m) {
  m.doc() =
      "fovsim C++ engine (run, sweep, evaluation hook); use the fovsim package (python/fovsim)";
  static py::exception<Error> fovsim_error(m, "FovsimError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      fovsim_error(e.what());
    }
  });
  m.def("run", &run_py, py::arg("config"), py::arg("overrides") = std::vector<std::string>{},
        py::arg("out") = "", py::arg("threads") = 0, py::arg("models") = "",
        "Runs one config (like `fovsim run`); returns {out_dir, summary (list of dicts), "
        "frame_rows}");
  m.def("sweep", &sweep_py, py::arg("config"), py::arg("overrides") = std::vector<std::string>{},
        py::arg("out") = "", py::arg("threads") = 0, py::arg("models") = "",
        "Runs a sweep config (like `fovsim sweep`, resumable); returns a report dict");
  py::class_<Evaluator>(m, "Evaluator")
      .def(py::init<std::string, std::vector<std::string>, std::string, int, std::string>(),
           py::arg("config"), py::arg("overrides") = std::vector<std::string>{},
           py::arg("out") = "", py::arg("threads") = 0, py::arg("models") = "")
      .def("evaluate", &Evaluator::evaluate, py::arg("points"),
           "Evaluates each point (a list of key.path=value overrides); returns one summary (list "
           "of dicts) per point")
      .def_property_readonly("evaluations", &Evaluator::evaluations);
}
