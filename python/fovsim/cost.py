"""The cost model from Python: `predict` and `budget` (what `fovsim predict` and `fovsim budget`
print, docs/cost_model.md), through the library functions the CLI calls (`predict_rows`,
`budget_rows`, `recost` of the compiled module, python/bindings.cpp).

    fovsim.predict(gpu="gtx1080", workload="atrium", methods=["full", "kfr:sigma=1.8"])
    fovsim.budget(gpu="gtx1080", workload="atrium", hz=90, scale={"shading": 2})
    fovsim.predict(results="results/quickstart", gpu=["rtx2080ti"])   # re-cost a finished run

Each returns a table: a pandas DataFrame when pandas is installed, else a list of dicts (one
per GPU × method), with the CLI's `--json` keys (est_ms_total, est_ms_<pass>, intervals,
speedup_vs_full; budget: verdict, headroom_ms, factor_<resource>, factor_all).
"""
from .engine import _module


def _table(rows, as_frame):
    if not as_frame:
        return rows
    try:
        import pandas as pd
    except ImportError:
        return rows
    return pd.DataFrame(rows)


def _list(x):
    if x is None:
        return []
    return [x] if isinstance(x, str) else list(x)


def _flat(e):
    """A library row (`fovsim predict/budget --json`) with the display and resource_ms flattened
    into columns and "inf" factors as floats."""
    r = {k: v for k, v in e.items() if k not in ("display", "resource_ms")}
    d = e.get("display")
    if isinstance(d, dict):
        r.update(display=d.get("name"), width=d.get("width"), height=d.get("height"), eyes=d.get("eyes"))
    for k, ms in e.get("resource_ms", {}).items():
        r["resource_ms_" + k] = ms
    for k, v in list(r.items()):
        if k.startswith("factor_") and v == "inf":
            r[k] = float("inf")
    return r


def predict(gpu, workload=None, methods=None, display=None, width=0, height=0, eyes=0,
            results=None, models="", as_frame=True):
    """Per-frame estimates of `methods` ("kfr", "kfr:sigma=1.8,alpha=4", ...; default ["full"])
    on each GPU profile for a workload and display (default fovsim.DEFAULT_DISPLAY), with
    speedup_vs_full — `fovsim predict`, through the same library function (predict_rows).
    With results=DIR: the run's measured counters re-costed (`fovsim predict --results`;
    display/workload default to the run's; methods are the run's configurations)."""
    m = _module()
    gpus = _list(gpu)
    if not gpus:
        raise ValueError("predict: give at least one gpu")
    if results is not None:
        rows = m.recost(str(results), gpus, display or "", width, height, eyes, workload or "", models)
        return _table([_flat_recost(r) for r in rows], as_frame)
    if not workload:
        raise ValueError("predict: workload is required (the scene's triangles, lights and shading cost decide "
                         "every estimate; models/workloads/)")
    rows = m.predict_rows(gpus, workload, _list(methods), display or "", width, height, eyes, models)
    return _table([_flat(r) for r in rows], as_frame)


def _flat_recost(e):
    """A re-costed row with passes as est_ms_<pass> columns."""
    r = {k: v for k, v in e.items() if k not in ("passes", "passes_lo", "passes_hi", "resource_ms")}
    for p, ms in e.get("passes", {}).items():
        r["est_ms_" + p] = ms
        if "passes_lo" in e:
            r["est_ms_" + p + "_lo"] = e["passes_lo"][p]
            r["est_ms_" + p + "_hi"] = e["passes_hi"][p]
    for k, ms in e.get("resource_ms", {}).items():
        r["resource_ms_" + k] = ms
    return r


def budget(gpu, workload, methods=None, hz=90.0, budget_ms=None, scale=None, display=None,
           width=0, height=0, eyes=0, models="", p=None, as_frame=True):
    """Does each method fit a frame budget (1000/hz, or budget_ms) on each GPU, optionally with
    resources' throughput scaled (scale={"shading": 2.0, ...}) — `fovsim budget`, through the
    same library function (budget_rows). Per row: p_fit (probability that the frame fits, from
    the profile's held-out errors), fits (p_fit >= p) and verdict ("fits"; "does not fit":
    p_fit <= 1 - p; else "uncertain"; p None: 0.8, the library's kDefaultFitLevel), headroom_ms,
    changes (the cheapest changes reaching p), factor_<resource> (throughput factor that
    resource alone needs to fit; inf: cannot) and factor_all (uniform factor on everything but
    fixed overheads)."""
    m = _module()
    # The ranges of `fovsim budget --hz / --budget-ms` (CostArgRanges in the C++, checked by
    # the library): NaN, 0 and negative values are errors, not "the default".
    if budget_ms is not None:
        b = m.check_cost_arg("budget_ms", float(budget_ms))
    else:
        b = 1000.0 / m.check_cost_arg("hz", float(hz))
    kw = {} if p is None else {"p": p}
    rows = m.budget_rows(_list(gpu), workload, _list(methods), display or "", width, height, eyes, models,
                         b, scale=dict(scale or {}), **kw)
    return _table([_flat(r) for r in rows], as_frame)
