#!/usr/bin/python3
"""Foveal quality vs latency per method, from a latency sweep (configs/sweeps/latency.json).

Reads <dir>/summary.csv (one row per cell x method), x = mean `latency_ms` of the cell,
y = a metric (default rmse_fovea) with its 95% interval `<metric>_ci95` as error bars, one
line per method label and value of every other sweep axis (e.g. latency.predictor).

Whether a latency degrades a line is decided from the sweep's paired.csv, never from the
per-cell means: the `across` row that pairs the line's configuration in the lowest-latency
cell with the same configuration at latency x (same frames, same gaze, docs/intervals.md)
gives the change x − lowest and its 95% interval. The line degrades at x when that interval
lies entirely on the worse side of 0 (for *psnr, ssim, JOD lower is worse, for errors higher)
and, with --threshold T, beyond T (in the metric's unit). Prints, per line, the first such
latency with its change, or that none degrades (with the largest change and its interval);
a metric paired.csv has no rows for (e.g. a per-phase column) is plotted but not decided.
Writes <dir>/plots/latency_<metric>.<format> and latency_<metric>.csv; `fovsim sweep` draws
the rmse_fovea plot through viz/plot_sweep.py. See docs/latency.md.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from common import to_float, log  # noqa: E402


class NoLatency(Exception):
    pass


def frame_config(summary_row):
    """The configuration id inside its cell (the sweep's summary writes "<cell index>/<id>")."""
    cid = summary_row.get("config_id") or summary_row.get("label") or ""
    return cid.split("/", 1)[1] if "/" in cid else cid


def paired_change(paired, metric, config, gpu, base_cell, cell, higher_is_better):
    """(change, lo, hi) of `metric` for `config` in `cell` against `base_cell` from paired.csv's
    `across` rows, oriented so that a positive change is a degradation; None when paired.csv has
    no such row."""
    for r in paired or []:
        if r.get("kind") != "across" or r.get("metric") != metric or r.get("config_a") != config:
            continue
        if gpu and r.get("gpu") and r.get("gpu") != gpu:
            continue
        a, b = r.get("cell_a_id"), r.get("cell_b_id")
        if (a, b) == (cell, base_cell):
            sign = 1.0  # diff = cell - base
        elif (a, b) == (base_cell, cell):
            sign = -1.0
        else:
            continue
        if higher_is_better:
            sign = -sign  # worse = base - cell
        d, lo, hi = (to_float(r.get(k)) for k in ("diff", "diff_lo", "diff_hi"))
        return (sign * d, lo * sign, hi * sign) if sign > 0 else (sign * d, sign * hi, sign * lo)
    return None


def degraded(change, threshold=0.0):
    """1 when the paired interval of the change lies entirely beyond `threshold` (>= 0) on the
    worse side, 0 when it does not, None when undecided (no paired row or no interval)."""
    if change is None or not all(math.isfinite(v) for v in change):
        return None
    return int(change[1] > threshold)


def plot_latency(sweep_dir, out, metric="rmse_fovea", threshold=0.0, report=print):
    """Draws one plot; returns its file name (inside `out`). NoLatency when not a latency sweep."""
    if not (threshold >= 0 and math.isfinite(threshold)):
        raise ValueError(f"--threshold {threshold}: expected a finite number >= 0")
    cols, rows = common.read_csv(os.path.join(sweep_dir, "summary.csv"))
    if not rows:
        raise NoLatency(f"{sweep_dir}/summary.csv: missing or empty")
    for need in ("latency_ms", metric):
        if need not in cols:
            raise NoLatency(f"no column {need} in summary.csv (no latency block)")
    _, paired = common.read_csv(os.path.join(sweep_dir, "paired.csv"))
    meta = common.read_json(os.path.join(sweep_dir, "sweep_summary.json")) or {}
    others = [a for a in meta.get("axes", []) if a in cols and not (a.startswith("latency.") and a.endswith("_ms"))]
    higher_is_better = common.higher_is_better(metric)  # the metric registry (C++)
    by, meth = {}, {}
    for r in rows:
        key = " ".join([r.get("label", r.get("method", "?"))] + [f"{a}={r[a]}" for a in others])
        by.setdefault(key, []).append((to_float(r["latency_ms"]), to_float(r[metric]),
                                       to_float(r.get(metric + "_ci95")), r.get("cell_id", ""), frame_config(r),
                                       r.get("gpu", "")))
        meth.setdefault(key, r.get("method") or r.get("label", "?"))
    styles = common.variant_styles([(k, meth[k]) for k in sorted(by)])  # colour per method
    fig, ax = common.figure(1, height=3.0)
    ax = ax[0]
    lines = [f"line,latency_ms,{metric},{metric}_ci95,worse_by,worse_by_lo,worse_by_hi,degraded"]
    worse = "drops" if higher_is_better else "rises"
    cond = ("the paired 95% interval of how much worse it got lies entirely above "
            + (f"{threshold:g}" if threshold > 0 else "0"))
    handles = []
    for key, pts in sorted(by.items()):
        pts.sort(key=lambda p: p[0])
        e = [0 if math.isnan(p[2]) else p[2] for p in pts]
        col, ls, mk = styles[key]
        h = ax.errorbar([p[0] for p in pts], [p[1] for p in pts], yerr=e, marker=mk, ls=ls, color=col, capsize=3,
                        label=key)
        handles.append(h)
        base = pts[0]
        first, largest, undecided = None, None, False
        for xi, yi, ei, cell, cfg, gpu in pts:
            ch = None if cell == base[3] else paired_change(paired, metric, cfg, gpu, base[3], cell,
                                                            higher_is_better)
            deg = None if cell == base[3] else degraded(ch, threshold)
            if cell != base[3] and deg is None:
                undecided = True
            if deg and first is None:
                first = (xi, ch)
            if ch is not None and all(math.isfinite(v) for v in ch) and (largest is None or ch[0] > largest[1][0]):
                largest = (xi, ch)
            chs = ch if ch is not None else (math.nan,) * 3
            lines.append(f"{key},{xi:.6g},{yi:.6g},{ei:.6g},{chs[0]:.6g},{chs[1]:.6g},{chs[2]:.6g},"
                         + ("" if deg is None else str(deg)))

        def ival(c):
            c = [v + 0.0 for v in c]  # no "-0"
            return f"{c[0]:+.4g} worse (95% [{c[1]:+.4g}, {c[2]:+.4g}])"

        if first is not None:
            report(f"{key}: {metric} {worse} at {first[0]:.0f} ms vs {base[0]:.0f} ms: {ival(first[1])}: "
                   f"a degradation ({cond})")
        elif undecided and largest is None:
            report(f"{key}: {metric}: no paired interval in paired.csv, so no degradation is decided "
                   f"(paired.csv pairs {', '.join(sorted({r.get('metric', '') for r in paired or []})) or 'nothing'})")
        else:
            tail = f"; least favourable change at {largest[0]:.0f} ms: {ival(largest[1])}" if largest else ""
            report(f"{key}: {metric}: no swept latency degrades it (a degradation: {cond}){tail}")
    ax.set_xlabel("end-to-end latency [ms]")
    ax.set_ylabel(common.wrap(common.metric_label(metric) + " (95% interval)", 40))
    ax.grid(alpha=0.3)
    common.legend_below(fig, handles, [h.get_label() for h in handles])
    name = common.figure_name(f"latency_{metric}")
    common.save(fig, os.path.join(out, f"latency_{metric}.png"))
    common.write_text_atomic(os.path.join(out, f"latency_{metric}.csv"), "\n".join(lines) + "\n")
    return name


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir", help="sweep results folder")
    ap.add_argument("--metric", default="rmse_fovea")
    ap.add_argument("--threshold", type=float, default=0.0,
                    help="a degradation also needs the paired interval of the change to lie beyond this "
                    "(absolute, in the metric's unit; default 0: the interval excludes 0)")
    common.add_output_args(ap, configs=False)
    a = ap.parse_args(argv)
    common.set_output(a)
    if not (a.threshold >= 0 and math.isfinite(a.threshold)):
        sys.exit(f"latency: error: --threshold {a.threshold}: expected a finite number >= 0")
    try:
        name = plot_latency(a.dir, os.path.join(a.dir, "plots"), a.metric, a.threshold)
    except NoLatency as e:
        sys.exit(f"latency: error: {a.dir}: {e}")
    log(os.path.join(a.dir, "plots", name))
    return 0


if __name__ == "__main__":
    sys.exit(main())
