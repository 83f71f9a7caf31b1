#!/usr/bin/python3
"""Foveal quality vs latency per method, from a latency sweep (configs/sweeps/latency.json).

Reads <dir>/summary.csv (one row per cell x method), x = mean `latency_ms` of the cell,
y = a metric (default rmse_fovea) with its 95% interval `<metric>_ci95` as error bars, one
line per method label and value of every other sweep axis (e.g. latency.predictor). Prints,
per line, the first latency at which the metric is worse than at the lowest latency by more
than --margin (relative; for *psnr and ssim lower is worse; from an exact 0 any rise counts).
Writes <dir>/plots/latency_<metric>.png and latency_<metric>.csv; `fovsim sweep` draws the
rmse_fovea plot through viz/plot_sweep.py. See docs/latency.md.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from common import plt, to_float, log  # noqa: E402


class NoLatency(Exception):
    pass


def plot_latency(sweep_dir, out, metric="rmse_fovea", margin=0.10, report=print):
    """Draws one plot; returns its file name (inside `out`). NoLatency when not a latency sweep."""
    cols, rows = common.read_csv(os.path.join(sweep_dir, "summary.csv"))
    if not rows:
        raise NoLatency(f"{sweep_dir}/summary.csv: missing or empty")
    for need in ("latency_ms", metric):
        if need not in cols:
            raise NoLatency(f"no column {need} in summary.csv (no latency block)")
    meta = common.read_json(os.path.join(sweep_dir, "sweep_summary.json")) or {}
    others = [a for a in meta.get("axes", []) if a in cols and not (a.startswith("latency.") and a.endswith("_ms"))]
    higher_is_better = common.higher_is_better(metric)  # the metric registry (C++)
    by, meth = {}, {}
    for r in rows:
        key = " ".join([r.get("label", r.get("method", "?"))] + [f"{a}={r[a]}" for a in others])
        by.setdefault(key, []).append((to_float(r["latency_ms"]), to_float(r[metric]), to_float(r.get(metric + "_ci95"))))
        meth.setdefault(key, r.get("method") or r.get("label", "?"))
    styles = common.variant_styles([(k, meth[k]) for k in sorted(by)])  # colour per method
    fig, ax = plt.subplots(figsize=(6.5, 4))
    lines = [f"line,latency_ms,{metric},{metric}_ci95,degraded"]
    for key, pts in sorted(by.items()):
        pts.sort()
        e = [0 if math.isnan(p[2]) else p[2] for p in pts]
        col, ls, mk = styles[key]
        ax.errorbar([p[0] for p in pts], [p[1] for p in pts], yerr=e, marker=mk, ls=ls, color=col, capsize=3,
                    label=key)
        base, first = pts[0][1], None
        for xi, yi, ei in pts:
            diff = (base - yi) if higher_is_better else (yi - base)
            worse = diff / abs(base) if base else (math.inf if diff > 0 else 0.0)
            deg = int(worse > margin)
            if deg and first is None:
                first = xi
            lines.append(f"{key},{xi:.6g},{yi:.6g},{ei:.6g},{deg}")
        report(f"{key}: {metric} {'drops' if higher_is_better else 'rises'} by more than {100 * margin:.0f}% at "
               + (f"{first:.0f} ms" if first is not None else "no swept latency"))
    ax.set_xlabel("end-to-end latency [ms]")
    ax.set_ylabel(common.metric_label(metric) + " (95% interval)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    name = f"latency_{metric}.png"
    common.save(fig, os.path.join(out, name))
    common.write_text_atomic(os.path.join(out, f"latency_{metric}.csv"), "\n".join(lines) + "\n")
    return name


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir", help="sweep results folder")
    ap.add_argument("--metric", default="rmse_fovea")
    ap.add_argument("--margin", type=float, default=0.10, help="relative drop that counts (default 0.10)")
    a = ap.parse_args()
    try:
        name = plot_latency(a.dir, os.path.join(a.dir, "plots"), a.metric, a.margin)
    except NoLatency as e:
        sys.exit(f"latency: error: {a.dir}: {e}")
    log(os.path.join(a.dir, "plots", name))


if __name__ == "__main__":
    main()
