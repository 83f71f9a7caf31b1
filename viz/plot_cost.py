#!/usr/bin/python3
"""Predicted vs. published pass times for `fovsim validate-cost`.

Top row, one panel per GPU: the held-out rows of the leave-one-seed/GPU/scene-out refits
(model ms against published ms) with their 80% prediction interval as a vertical bar (nested:
built without the row's table; a bar that crosses the diagonal covers the published value),
the calibration fit faint behind them, held-out frame totals as squares; rows and totals with
passes the refit never measured (costed from their nominal work) as down-triangles / diamonds.
Below, one panel per pass: the same for the single-pass held-out rows of that pass.
Usage: plot_cost.py validate_cost.csv out.png"""
import math
import sys

from common import plt, read_csv, save, to_float

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
    ax.set_xlabel("published ms")
    ax.set_ylabel("model ms (bar: 80% interval)")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=6, loc="upper left")
    ax.grid(True, which="both", alpha=0.2)


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_cost.py validate_cost.csv out.png")
    _, rows = read_csv(sys.argv[1])
    if rows is None:
        sys.exit(f"plot_cost.py: {sys.argv[1]} not found")
    held = [r for r in rows if r["experiment"].startswith("cross:")
            and r["kind"] in ("predicted", "total", "prior", "total_prior") and to_float(r["published_ms"]) > 0]
    calib = [r for r in rows if r["experiment"] == "calibration" and to_float(r["published_ms"]) > 0]
    gpus = sorted({r["gpu"] for r in held})
    passes = sorted({r["passes"] for r in held if r["kind"] == "predicted" and "+" not in r["passes"]})
    ncols = max(len(gpus), 4)
    nrows = 1 + math.ceil(len(passes) / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.2 * ncols, 4.0 * nrows), squeeze=False)
    for i, g in enumerate(gpus):
        n = sum(1 for r in held if r["gpu"] == g)
        panel(axes[0][i], [r for r in held if r["gpu"] == g], [r for r in calib if r["gpu"] == g],
              f"GPU {g}: {n} held-out rows", "table")
    for i, p in enumerate(passes):
        ax = axes[1 + i // ncols][i % ncols]
        sel = [r for r in held if r["passes"] == p and r["kind"] == "predicted"]
        panel(ax, sel, [r for r in calib if r["passes"] == p], f"pass {p}: {len(sel)} held-out rows", "gpu")
    for k in range(len(gpus), ncols):
        axes[0][k].axis("off")
    for k in range(len(passes), (nrows - 1) * ncols):
        axes[1 + k // ncols][k % ncols].axis("off")
    fig.suptitle("fovsim validate-cost: held-out predictions vs. published times with 80% intervals, "
                 "per GPU (top row) and per pass")
    fig.tight_layout(rect=(0, 0, 1, 0.98))
    save(fig, sys.argv[2])  # temporary name, then rename, like every fovsim output


if __name__ == "__main__":
    main()
