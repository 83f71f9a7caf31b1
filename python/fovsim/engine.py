"""Running fovsim from Python through the compiled module `_fovsim` (python/bindings.cpp).

The module is built by `make` (CMake option FOVSIM_PYTHON, on when pybind11 is found) into
<build>/python/. It is looked up in $FOVSIM_PYTHON_EXT, then <repo>/build/python.

Overrides are given as a dict {"render.scale": 0.5, "methods[1].sigma": 2.2} (values are
written as JSON, like the CLI's key.path=value) or as a list of "key.path=value" strings.
"""
import glob
import importlib
import json
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


def run(config, overrides=None, out="", threads=0, models=""):
    """Runs one config like `fovsim run` (same outputs under `out`, default results/<name>).
    Returns {"out_dir", "summary": [dict per configuration], "frame_rows"}. Errors in the
    config raise FovsimError with the JSON path and the allowed range."""
    return _module().run(os.fspath(config), overrides_list(overrides), os.fspath(out), threads, models)


def sweep(config, overrides=None, out="", threads=0, models=""):
    """Runs a sweep config like `fovsim sweep` (resumable). Returns a report dict; load the
    results with fovsim.load_sweep(report["out_dir"])."""
    return _module().sweep(os.fspath(config), overrides_list(overrides), os.fspath(out), threads, models)


class Evaluator:
    """Evaluation hook for an outside optimiser (ask/tell): the optimiser asks for points, each
    point is a dict of overrides; evaluate() runs them and returns one summary per point (list
    of dicts, one per configuration), from which the caller tells its optimiser the objective.

        ev = fovsim.Evaluator("configs/quickstart.json", out="results/opt", overrides={...})
        for p in optimiser.ask(): ...
        summaries = ev.evaluate(points)
    """

    def __init__(self, config, overrides=None, out="results/evaluator", threads=0, models=""):
        self._ev = _module().Evaluator(os.fspath(config), overrides_list(overrides), os.fspath(out), threads, models)

    def evaluate(self, points):
        return self._ev.evaluate([overrides_list(p) for p in points])

    @property
    def evaluations(self):
        return self._ev.evaluations


def __getattr__(name):
    if name == "FovsimError":
        return _module().FovsimError
    raise AttributeError(name)
