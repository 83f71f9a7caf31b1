#!/usr/bin/python3
"""Predicted vs. published pass times for `fovsim validate-cost`.

Top row, one panel per GPU: the held-out rows of the leave-one-seed/GPU/scene-out refits
(model ms against published ms) with their 80% prediction interval as a vertical bar (nested:
built without the row's table; a bar that crosses the diagonal covers the published value),
the calibration fit faint behind them, held-out frame totals as squares; rows and totals with
passes the refit never measured (costed from their nominal work) as down-triangles / diamonds.
Below, one panel per pass: the same for the single-pass held-out rows of that pass.
Usage: plot_cost.py validate_cost.csv out.png"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from common import read_csv, to_float  # noqa: E402

# prior / total_prior: passes the refit never measured, costed from their nominal work
KIND_STYLE = {"predicted": ("^", 0.9), "total": ("s", 0.9), "prior": ("v", 0.5),
              "total_prior": ("D", 0.6)}
GPU_COLORS = {"gtx980": "tab:orange", "gtx1080": "tab:blue", "rtx2070": "tab:green",
              "rtx2080ti": "tab:red"}
TABLE_COLORS = {"kfr": "tab:blue", "rmfr": "tab:orange", "twfr": "tab:green", "flc": "tab:red"}


def panel(ax, rows, calib, title, colour_by):
    vals = [to_float(r["published_ms"]) for r in rows + calib] + [to_float(r["model_ms"]) for r in rows + calib]
    vals = [v for v in vals if v > 0 and math.isfinite(v)]
    lo, hi = (min(vals) / 2, max(vals) * 2) if vals else (0.01, 100)
    for r in calib:
        ax.scatter(to_float(r["published_ms"]), to_float(r["model_ms"]), marker="o", s=12, color="0.75",
                   label="_calibration fit")
    seen = set()
    for r in rows:
        x, y = to_float(r["published_ms"]), to_float(r["model_ms"])
        if not (x > 0 and y > 0):
            continue
        key = r[colour_by]
        c = (GPU_COLORS if colour_by == "gpu" else TABLE_COLORS).get(key, None)
        m, a = KIND_STYLE.get(r["kind"], ("o", 0.6))
        ylo, yhi = to_float(r["model_lo_ms"]), to_float(r["model_hi_ms"])
        if math.isfinite(ylo) and math.isfinite(yhi):
            ax.errorbar(x, y, yerr=[[y - ylo], [yhi - y]], color=c or "tab:purple", alpha=0.45, lw=1.0,
                        capsize=2)
        label = f"{key} {r['kind']}"
        ax.scatter(x, y, marker=m, alpha=a, color=c or "tab:purple", s=26,
                   label=None if label in seen else label)
        seen.add(label)
    ax.plot([lo, hi], [lo, hi], "k-", lw=0.8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(lo, hi)
    ax.set_ylim(lo, hi)
    ax.set_xlabel("published [ms]")
    ax.set_ylabel("model [ms] (bar: 80% interval)")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.2)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("validate_csv", help="`fovsim validate-cost` output")
    ap.add_argument("out_png", help="figure to write (PNG; --format adds PDF or SVG next to it)")
    common.add_output_args(ap, configs=False)
    a = ap.parse_args(argv)
    common.set_output(a)
    _, rows = read_csv(a.validate_csv)
    if rows is None:
        sys.exit(f"plot_cost.py: {a.validate_csv} not found")
    held = [r for r in rows if r["experiment"].startswith("cross:")
            and r["kind"] in ("predicted", "total", "prior", "total_prior") and to_float(r["published_ms"]) > 0]
    calib = [r for r in rows if r["experiment"] == "calibration" and to_float(r["published_ms"]) > 0]
    gpus = sorted({r["gpu"] for r in held})
    passes = sorted({r["passes"] for r in held if r["kind"] == "predicted" and "+" not in r["passes"]})
    entries = []  # legend entries of every panel: "<table or gpu> <kind>"
    for r in held:
        entries.append(f"{r['table']} {r['kind']}")
        if r["kind"] == "predicted" and r["passes"] in passes:
            entries.append(f"{r['gpu']} {r['kind']}")
    fig, axes = common.figure(len(gpus) + len(passes), height=2.6, legend=common.legend_labels(entries),
                              title_lines=2)
    for i, g in enumerate(gpus):
        n = sum(1 for r in held if r["gpu"] == g)
        panel(axes[i], [r for r in held if r["gpu"] == g], [r for r in calib if r["gpu"] == g],
              f"GPU {g}: {n} held-out rows", "table")
    for i, p in enumerate(passes):
        sel = [r for r in held if r["passes"] == p and r["kind"] == "predicted"]
        panel(axes[len(gpus) + i], sel, [r for r in calib if r["passes"] == p],
              f"pass {p}: {len(sel)} held-out rows", "gpu")
    common.figure_legend(fig, axes)
    fig.suptitle(common.wrap("fovsim validate-cost: held-out predictions vs. published times with 80% "
                             "intervals, per GPU (first panels) and per pass", 95))
    common.save(fig, a.out_png)  # temporary name, then rename, like every fovsim output
    return 0


if __name__ == "__main__":
    sys.exit(main())
