"""Running fovsim from Python through the compiled module `_fovsim` (python/bindings.cpp).

The module is built by `make` (CMake option FOVSIM_PYTHON, on when pybind11 is found) into
<build>/python/. It is looked up in $FOVSIM_PYTHON_EXT, then <repo>/build/python.

Overrides are given as a dict {"render.scale": 0.5, "methods[1].sigma": 2.2} (values are
written as JSON, like the CLI's key.path=value) or as a list of "key.path=value" strings.
"""
import glob
import importlib
import json
import math
import os
import sys

_REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
_mod = None


def _module():
    global _mod
    if _mod is not None:
        return _mod
    dirs = [d for d in (os.environ.get("FOVSIM_PYTHON_EXT"), os.path.join(_REPO, "build", "python")) if d]
    for d in dirs:
        if glob.glob(os.path.join(d, "_fovsim*.so")):
            if d not in sys.path:
                sys.path.insert(0, d)
            break
    try:
        _mod = importlib.import_module("_fovsim")
    except ImportError as e:
        raise ImportError(
            "fovsim's compiled module _fovsim was not found (looked in " + ", ".join(dirs) +
            "); build it with `make` (needs Debian pybind11-dev and python3-dev) or set FOVSIM_PYTHON_EXT "
            "to the folder holding _fovsim*.so") from e
    return _mod


def overrides_list(overrides):
    """["key.path=value", ...] from a dict (values as JSON), a list of strings, or None."""
    if overrides is None:
        return []
    if isinstance(overrides, dict):
        out = []
        for k, v in overrides.items():
            out.append(f"{k}={v}" if isinstance(v, str) else f"{k}={json.dumps(v)}")
        return out
    return [str(o) for o in overrides]


def make_plots(directory, sweep=False, quiet=True):
    """Runs viz/plot_run.py (or plot_sweep.py) on a result folder, as `fovsim run` does at its
    end: plots, index.html (and run.mp4 when ffmpeg is present) in <directory>/plots/. Returns
    the path of that index.html. Raises RuntimeError when the script fails (e.g. no matplotlib)."""
    import subprocess

    script = os.path.join(_REPO, "viz", "plot_sweep.py" if sweep else "plot_run.py")
    p = subprocess.run([sys.executable, script, os.fspath(directory)], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{script} failed (exit {p.returncode}): {(p.stderr or p.stdout).strip()[-500:]}")
    if not quiet:
        print(p.stdout, end="")
    return os.path.join(os.fspath(directory), "plots", "index.html")


def run(config, overrides=None, out="", threads=0, models="", plots=False, watchdog=60.0, cache=False,
        targets=None):
    """Runs one config like `fovsim run` (same outputs under `out`, default results/<name>).
    The run options are `fovsim run`'s (RunControl in the C++): threads (-j), models (--models),
    watchdog (--watchdog seconds), cache (the reference cache; off unless asked, the CLI's is on
    unless --no-cache) and targets (--target specs, e.g. ["est_ms_total:1%"]).
    Returns {"out_dir", "summary": [dict per configuration], "frame_rows"} (and "index" with
    plots=True: the plots are made as `fovsim run` makes them, make_plots). Errors in the config
    raise FovsimError with the JSON path and the allowed range."""
    r = _module().run(os.fspath(config), overrides_list(overrides), os.fspath(out), threads, models,
                      float(watchdog), bool(cache), list(targets or []))
    if plots:
        r["index"] = make_plots(r["out_dir"])
    return r


def sweep(config, overrides=None, out="", threads=0, models="", plots=False, watchdog=60.0, cache=False,
          targets=None):
    """Runs a sweep config like `fovsim sweep` (resumable), with the run options of run().
    Returns a report dict; load the results with fovsim.load_sweep(report["out_dir"]).
    plots=True: viz/plot_sweep.py too."""
    r = _module().sweep(os.fspath(config), overrides_list(overrides), os.fspath(out), threads, models,
                        float(watchdog), bool(cache), list(targets or []))
    if plots and r.get("complete"):
        r["index"] = make_plots(r["out_dir"], sweep=True)
    return r


class Evaluator:
    """Evaluation hook for an outside optimiser (ask/tell): the optimiser asks for points, each
    point is a dict of overrides; evaluate() runs them and returns one summary per point (list
    of dicts, one per configuration), from which the caller tells its optimiser the objective.

        ev = fovsim.Evaluator("configs/quickstart.json", out="results/opt", overrides={...})
        for p in optimiser.ask(): ...
        summaries = ev.evaluate(points)
    """

    def __init__(self, config, overrides=None, out="results/evaluator", threads=0, models="", watchdog=60.0,
                 cache=False, targets=None):
        """The run options are run()'s (RunControl in the C++): threads, models, watchdog, cache, targets."""
        self._ev = _module().Evaluator(os.fspath(config), overrides_list(overrides), os.fspath(out), threads, models,
                                       float(watchdog), bool(cache), list(targets or []))

    def evaluate(self, points):
        return self._ev.evaluate([overrides_list(p) for p in points])

    @property
    def evaluations(self):
        return self._ev.evaluations



def _score(rows, objective, label, constraints):
    """(score, violation) of one evaluation's summary rows, as `fovsim search` scores them
    (sim/experiment/search_runner.cpp): the row labelled `label` (else the first); an objective
    or constraint column the row does not have is a KeyError; a non-finite objective is nan; the
    violation is the sum over `constraints` ({"column", "min", "max"}) of how far the value lies
    outside [min, max]; a non-finite constraint value counts as infinitely violated."""
    row = None
    for r in rows:
        if not label or r.get("label") == label:
            row = r
            break
    if row is None:
        raise KeyError(f"no summary row labelled {label!r} (labels: {', '.join(str(r.get('label')) for r in rows)})")
    # A column the summary does not have is an error (as `fovsim search` refuses it), never a
    # NaN score that would make an arbitrary point "best".
    checks = [(objective, "objective")] + [(k["column"], "constraint") for k in constraints]
    for col, what in checks:
        if col and col not in row:
            raise KeyError(f"{what} column {col!r} is not in the summary "
                           f"(columns: {', '.join(sorted(str(k) for k in row))})")
    v = row.get(objective, math.nan)
    score = float(v) if isinstance(v, (int, float)) and math.isfinite(v) else math.nan
    violation = 0.0
    for k in constraints:
        c = row.get(k["column"], math.nan)
        if not (isinstance(c, (int, float)) and math.isfinite(c)):
            return score, math.inf
        violation += max(0.0, float(c) - k["max"]) + max(0.0, k["min"] - float(c))
    return score, violation


class AskTell:
    """Ask/tell search for an outside loop or optimiser, on the searcher of `fovsim search`
    (sim/experiment/search.h: a seeded Latin-hypercube batch, then a batched compass search).

        opt = fovsim.AskTell("configs/quickstart.json",
                             space={"methods[kfr].sigma": {"from": 1.2, "to": 3.0, "step": 0.1}},
                             maximize="fpsnr", subject_to={"shaded_fraction": {"max": 0.35}},
                             label="kfr", batch=4, out="results/asktell")
        for x in opt.ask():                 # x: {"methods[kfr].sigma": 1.6}
            opt.tell(x, opt.evaluate(x))    # or opt.tell(x, score=..., violation=...)
        opt.best                            # {"x": {...}, "score": ..., "violation": ...}

    `space` etc. take the JSON of a config's `sweep.search` block (docs/sweeps.md) and are
    validated like it; with none given the config's own `sweep.search` is used (its sweep axes
    are not expanded: pick a context with overrides). `evaluate(x)` runs the config with the
    point's overrides (like Evaluator, into <out>/eval_<n>/, with the run options of run():
    threads, models, watchdog, cache, targets) and returns its summary rows; a
    result from anywhere else can be told as a score instead."""

    def __init__(self, config, space=None, maximize=None, minimize=None, subject_to=None, label=None,
                 batch=None, seed=None, overrides=None, out="results/asktell", threads=0, models="", watchdog=60.0,
                 cache=False, targets=None):
        search = {}
        if space is not None:
            search["space"] = space
        for k, v in (("maximize", maximize), ("minimize", minimize), ("subject_to", subject_to),
                     ("label", label), ("batch", batch), ("seed", seed)):
            if v is not None:
                search[k] = v
        if search and "space" not in search:
            raise ValueError("AskTell: give space= with the other search keys (or none: the config's sweep.search)")
        if space is not None and maximize is None and minimize is None:
            raise ValueError("AskTell: give maximize='column' or minimize='column'")
        self._config = os.fspath(config)
        self._overrides = overrides_list(overrides)
        self._at = _module().AskTell(self._config, self._overrides, json.dumps(search) if search else "")
        self.spec = self._at.spec
        self._paths = [d["path"] for d in self.spec["space"]]
        self._out = os.fspath(out)
        self._run = dict(threads=threads, models=models, watchdog=watchdog, cache=cache, targets=targets)
        self._ev = None
        self.history = []  # [(x dict, score, violation)] in tell order

    def _vec(self, x):
        if isinstance(x, dict):
            missing = [p for p in self._paths if p not in x]
            if missing:
                raise KeyError(f"point lacks {', '.join(missing)}")
            return [float(x[p]) for p in self._paths]
        return [float(v) for v in x]

    def _dict(self, v):
        return {p: (int(round(a)) if d["integer"] else a) for p, a, d in zip(self._paths, v, self.spec["space"])}

    def ask(self):
        """The next batch of points as dicts {path: value}; [] when the search has converged
        (its step is below every dimension's resolution)."""
        return [self._dict(v) for v in self._at.ask()]

    def evaluate(self, x):
        """Runs the config with the point's overrides; returns its summary rows (list of dicts)."""
        if self._ev is None:
            self._ev = Evaluator(self._config, self._overrides, self._out, **self._run)
        return self._ev.evaluate([x])[0]

    def tell(self, x, result=None, score=None, violation=0.0):
        """Reports a point's result: `result` the summary rows of its run (scored like `fovsim
        search`: spec's objective, label and constraint), or `score` (finite) and `violation`
        (>= 0, 0 = feasible, inf = infinitely violated) computed elsewhere. A point outside the
        space, a non-finite score or a negative or NaN violation is a ValueError (checked by the
        library, sim/experiment/search.h check_told). Returns (score, violation)."""
        if result is not None:
            score, violation = _score(result, self.spec["objective"], self.spec["label"],
                                      self.spec["constraints"])
        elif score is None:
            raise ValueError("tell: give the run's summary rows or a score")
        self._at.tell([self._vec(x)], [float(score)], [float(violation)], result is None)
        self.history.append((dict(x) if isinstance(x, dict) else self._dict(self._vec(x)), score, violation))
        return score, violation

    def run(self, evaluations=None):
        """The whole loop here (ask, evaluate, tell) until `evaluations` (default: the spec's)
        points are told or the search converges; returns best."""
        n = self.spec["evaluations"] if evaluations is None else \
            int(_module().check_integer("evaluations", evaluations, 1, 1e9))
        while len(self.history) < n:
            xs = self.ask()
            if not xs:
                break
            for x in xs[:n - len(self.history)]:
                self.tell(x, self.evaluate(x))
        return self.best

    @property
    def best(self):
        """{"x": {path: value}, "score", "violation"} of the best point told (feasible first), or None."""
        b = self._at.best
        if b is None:
            return None
        return {"x": self._dict(b["x"]), "score": b["score"], "violation": b["violation"]}


def __getattr__(name):
    if name == "FovsimError":
        return _module().FovsimError
    raise AttributeError(name)
