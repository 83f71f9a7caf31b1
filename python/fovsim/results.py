"""Loaders for fovsim's result folders (results/README.md, docs/sweeps.md).

CSV cells follow results/README.md: numbers with %.10g, `inf`/`nan` spelled so, empty cells
for parameters a method does not have. A column whose every non-empty cell parses as a
number becomes float64 (empty -> nan); any other column stays text (numpy unicode).
"""
import csv
import json
import math
import os

import numpy as np


def _is_number(s):
    try:
        float(s)
        return True
    except ValueError:
        return False


def load_csv(path):
    """Reads one fovsim CSV into a numpy structured array (one field per column, file order).

    Numeric columns are float64 with nan for empty cells; text columns are `<U n`. Returns
    None when the file does not exist; a header-only file gives an empty array that keeps
    its columns (all float64)."""
    if not os.path.exists(path):
        return None
    with open(path, newline="") as f:
        reader = csv.reader(f)
        try:
            header = next(reader)
        except StopIteration:
            raise ValueError(f"{path}: empty file (no header)")
        rows = []
        for lineno, row in enumerate(reader, start=2):
            if len(row) != len(header):
                raise ValueError(f"{path}:{lineno}: {len(row)} cells, header has {len(header)}")
            rows.append(row)
    if len(set(header)) != len(header):
        dup = sorted({c for c in header if header.count(c) > 1})
        raise ValueError(f"{path}:1: duplicate column(s) {', '.join(dup)}")
    dtypes, columns = [], []
    for j, name in enumerate(header):
        cells = [r[j].strip() for r in rows]
        if all(c == "" or _is_number(c) for c in cells):
            columns.append([float(c) if c != "" else math.nan for c in cells])
            dtypes.append((name, "f8"))
        else:
            width = max([1] + [len(c) for c in cells])
            columns.append(cells)
            dtypes.append((name, f"U{width}"))
    out = np.empty(len(rows), dtype=dtypes)
    for (name, _), col in zip(dtypes, columns):
        out[name] = col
    return out


def _load_json(path):
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def _frames_of(res, keys, as_frame):
    if as_frame:
        for k in keys:
            if res[k] is not None:
                res[k] = to_dataframe(res[k])
    return res


def load_run(directory, as_frame=False):
    """Loads a `fovsim run` folder: {"frames", "summary", "paired"} as structured arrays (None
    when the file is absent), "manifest" as a dict (None when absent), "dir" the folder. With
    as_frame=True the tables are pandas DataFrames (needs pandas). Raises FileNotFoundError when
    the folder has neither frames.csv nor summary.csv."""
    d = os.fspath(directory)
    res = {
        "dir": d,
        "frames": load_csv(os.path.join(d, "frames.csv")),
        "summary": load_csv(os.path.join(d, "summary.csv")),
        "paired": load_csv(os.path.join(d, "paired.csv")),
        "manifest": _load_json(os.path.join(d, "manifest.json")),
    }
    if res["frames"] is None and res["summary"] is None:
        raise FileNotFoundError(f"{d}: no frames.csv or summary.csv (not a fovsim run folder)")
    return _frames_of(res, ("frames", "summary", "paired"), as_frame)


def load_sweep(directory, cells=False, as_frame=False):
    """Loads a `fovsim sweep` folder: {"summary", "pareto", "paired", "iso_budget"} as structured
    arrays (paired: the sweep's paired.csv, within-cell and across-cell differences with their 95%
    intervals, docs/sweeps.md; None when a file is absent), "sweep" (the
    expanded sweep.json) as a dict, "dir"; with cells=True also "cells": {cell_id: load_run(...)}
    for every complete cell under runs/; as_frame=True gives DataFrames. Raises
    FileNotFoundError without summary.csv."""
    d = os.fspath(directory)
    summary = load_csv(os.path.join(d, "summary.csv"))
    if summary is None:
        raise FileNotFoundError(f"{d}: no summary.csv (not a merged fovsim sweep folder)")
    res = {
        "dir": d,
        "summary": summary,
        "pareto": load_csv(os.path.join(d, "pareto.csv")),
        "paired": load_csv(os.path.join(d, "paired.csv")),
        "iso_budget": load_csv(os.path.join(d, "iso_budget.csv")),
        "sweep": _load_json(os.path.join(d, "sweep.json")),
    }
    if cells:
        res["cells"] = {}
        runs = os.path.join(d, "runs")
        if os.path.isdir(runs):
            for name in sorted(os.listdir(runs)):
                cd = os.path.join(runs, name)
                if os.path.exists(os.path.join(cd, "cell.json")):
                    res["cells"][name] = load_run(cd, as_frame=as_frame)
    return _frames_of(res, ("summary", "pareto", "paired", "iso_budget"), as_frame)


def numeric_columns(arr, exclude=()):
    """Names of the float64 fields of a structured array, in file order."""
    return [n for n in arr.dtype.names if arr.dtype[n].kind == "f" and n not in exclude]


def select(arr, **equal):
    """Rows whose fields equal the given values, e.g. select(frames, method="kfr")."""
    mask = np.ones(len(arr), dtype=bool)
    for k, v in equal.items():
        if k not in arr.dtype.names:
            raise KeyError(f"no column {k!r} (columns: {', '.join(arr.dtype.names)})")
        mask &= arr[k] == v
    return arr[mask]


def long_format(arr, id_cols, value_cols=None, drop_nan=True):
    """Tidy (long) form: one row per input row × value column, fields id_cols + `metric` +
    `value`. value_cols defaults to every numeric column not in id_cols. With drop_nan (the
    default) cells that are nan — a column a method does not fill — are left out; inf (psnr of
    an exact image) is kept. Works on frames (frame × method × metric) and summaries."""
    names = arr.dtype.names
    for c in list(id_cols) + list(value_cols or []):
        if c not in names:
            raise KeyError(f"no column {c!r} (columns: {', '.join(names)})")
    if value_cols is None:
        value_cols = numeric_columns(arr, exclude=set(id_cols))
    for c in value_cols:
        if arr.dtype[c].kind != "f":
            raise TypeError(f"column {c!r} is text, not numeric")
    mwidth = max([6] + [len(c) for c in value_cols])
    dt = [(c, arr.dtype[c]) for c in id_cols] + [("metric", f"U{mwidth}"), ("value", "f8")]
    parts = []
    for c in value_cols:
        v = arr[c]
        keep = ~np.isnan(v) if drop_nan else np.ones(len(arr), dtype=bool)
        part = np.empty(int(keep.sum()), dtype=dt)
        for ic in id_cols:
            part[ic] = arr[ic][keep]
        part["metric"] = c
        part["value"] = v[keep]
        parts.append(part)
    if not parts:
        return np.empty(0, dtype=dt)
    return np.concatenate(parts)


def to_dataframe(arr):
    """pandas.DataFrame of a structured array (frames, summary, or long_format's output).
    pandas is optional (Debian python3-pandas); without it this raises ImportError."""
    try:
        import pandas as pd
    except ImportError as e:
        raise ImportError("fovsim.to_dataframe needs pandas (apt-get install python3-pandas); "
                          "the structured arrays work without it") from e
    return pd.DataFrame(arr)


# Columns that identify a row of frames.csv / summary.csv (results/README.md "Keys", "Per frame").
# The label first: it names one configuration (config_id adds "@gpu"), while two
# configurations may share a method (`full` and `full` with FIR lighting): group by label.
KEY_COLUMNS = ("label", "config_id", "method", "gpu", "frame", "t")
# Per-frame columns that are not metrics: gaze, validity, latency bookkeeping.
CONTEXT_COLUMNS = ("gaze_x", "gaze_y", "gaze_valid", "phase", "gaze_est_x", "gaze_est_y")
# Wall-clock columns: differ run to run (results/README.md); left out of the tidy form.
WALL_CLOCK = ("ref_ms", "sim_ms")


def parameter_columns(run):
    """Method parameter columns of a loaded run (sigma, alpha, fx, ...): the keys of the resolved
    config's method entries (manifest.json) that are columns of frames.csv."""
    arr = run["frames"] if run.get("frames") is not None else run.get("summary")
    names = set(arr.dtype.names) if arr is not None else set()
    man = run.get("manifest") or {}
    methods = ((man.get("resolved_config") or man.get("config") or {}).get("methods")) or []
    out = []
    for m in methods:
        if not isinstance(m, dict):
            continue
        for k, v in m.items():
            if k in ("method", "label") or isinstance(v, (dict, list)) or k not in names or k in out:
                continue
            out.append(k)
    return out


def tidy(run, metrics=None, drop_nan=True, as_frame=True):
    """Tidy (long) form of a run's frames.csv: one row per frame × configuration × metric, with
    the keys (label, config_id, method, gpu, frame, t; group by label, not method: two
    configurations may share a method), the method parameters (sigma, alpha, …;
    nan where a method lacks one) and the gaze as columns, then `metric` and `value`.

    `run` is load_run's dict or a run folder. `metrics` defaults to every numeric column that is
    not a key, parameter, gaze or wall-clock column (est_ms_*, psnr, fpsnr, ssim, counters, …).
    With drop_nan a metric a method does not fill (nan) gives no row; inf is kept (psnr of an
    exact image). Returns a pandas DataFrame when pandas is installed and as_frame, else a
    numpy structured array with the same columns."""
    if not isinstance(run, dict):
        run = load_run(run)
    elif run.get("frames") is not None and not isinstance(run["frames"], np.ndarray):
        run = load_run(run["dir"])  # loaded with as_frame=True: read the arrays again
    fr = run["frames"]
    if fr is None:
        raise FileNotFoundError(f"{run.get('dir')}: no frames.csv")
    names = fr.dtype.names
    params = parameter_columns(run)
    ids = [c for c in KEY_COLUMNS if c in names] + params + [c for c in CONTEXT_COLUMNS if c in names]
    if metrics is None:
        skip = set(ids) | set(WALL_CLOCK)
        metrics = [c for c in numeric_columns(fr) if c not in skip]
    arr = long_format(fr, ids, metrics, drop_nan=drop_nan)
    if as_frame:
        try:
            import pandas as pd
        except ImportError:
            return arr
        return pd.DataFrame(arr)
    return arr


def tidy_sweep(directory, metrics=None, drop_nan=True, as_frame=True):
    """Tidy (long) form of a sweep's summary.csv: one row per cell × configuration × metric with
    the keys (label, config_id, cell_id, method, gpu), the swept axes (columns named by their
    path, e.g. `methods[kfr].sigma`), the method parameters and `frames` as columns, then
    `metric`, `value` (the mean over the cell's frames) and `ci95` (its 95% half-width from
    `<metric>_ci95`; nan when absent), `lo` and `hi` (value ∓ ci95). `metrics` defaults to every
    numeric column that is not a key, axis, parameter, half-width, pareto flag or wall-clock
    column. DataFrame with pandas. Differences between cells with paired intervals:
    load_sweep(d)["paired"]."""
    d = os.fspath(directory)
    sw = load_sweep(d)
    s = sw["summary"]
    names = s.dtype.names
    meta = _load_json(os.path.join(d, "sweep_summary.json")) or {}
    axes = [a for a in meta.get("axes", []) if a in names]
    params = []
    runs = os.path.join(d, "runs")
    if os.path.isdir(runs):
        for name in sorted(os.listdir(runs)):
            man = _load_json(os.path.join(runs, name, "manifest.json"))
            if man:
                params = [p for p in parameter_columns({"summary": s, "manifest": man}) if p not in axes]
                break
    keys = [c for c in ("label", "config_id", "cell_id", "cell", "method", "gpu") if c in names]
    ids = keys + axes + params + (["frames"] if "frames" in names else [])
    if metrics is None:
        skip = set(ids) | set(WALL_CLOCK) | {"pareto"}
        metrics = [c for c in numeric_columns(s) if c not in skip and not c.endswith("_ci95")]
    arr = long_format(s, ids, metrics, drop_nan=drop_nan)
    ci = np.full(len(arr), np.nan)
    # long_format stacks metric blocks in `metrics` order, each keeping the rows it did not drop.
    pos = 0
    for m in metrics:
        keep = ~np.isnan(s[m]) if drop_nan else np.ones(len(s), dtype=bool)
        n = int(keep.sum())
        if m + "_ci95" in names and s.dtype[m + "_ci95"].kind == "f":
            ci[pos:pos + n] = s[m + "_ci95"][keep]
        pos += n
    out = np.empty(len(arr), dtype=arr.dtype.descr + [("ci95", "f8"), ("lo", "f8"), ("hi", "f8")])
    for n in arr.dtype.names:
        out[n] = arr[n]
    out["ci95"] = ci
    out["lo"] = out["value"] - ci
    out["hi"] = out["value"] + ci
    if as_frame:
        try:
            import pandas as pd
        except ImportError:
            return out
        return pd.DataFrame(out)
    return out
