#!/usr/bin/python3
"""Predicted vs. published pass times for `fovsim validate-cost` (issue 14 item 6):
(1) the calibration fit, (2) held-out rows of the leave-one-seed/GPU/scene-out refits with
their 80% prediction intervals (nested: built without the row's table), coloured by GPU,
(3) published/model per pass for the held-out rows against the interval band.
Usage: plot_cost.py validate_cost.csv out.png"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_cost.py validate_cost.csv out.png")
    rows = list(csv.DictReader(open(sys.argv[1])))
    fig, axes = plt.subplots(1, 3, figsize=(18, 5.5))
    styles = {"fitted": ("o", 0.8), "check": ("s", 0.8), "predicted": ("^", 0.9), "refit": ("x", 0.5)}
    gpu_colors = {"gtx980": "tab:orange", "gtx1080": "tab:blue", "rtx2070": "tab:green", "rtx2080ti": "tab:red"}
    lo, hi = 0.01, 60
    for ax, exp_filter, title, bars in (
        (axes[0], lambda e: e == "calibration", "calibration fit (all tables)", False),
        (axes[1], lambda e: e.startswith("cross:"), "held-out (seed = GPU / scene) with 80% intervals", True),
    ):
        seen = set()
        for r in rows:
            if not exp_filter(r["experiment"]) or float(r["published_ms"]) <= 0:
                continue
            m, a = styles.get(r["kind"], ("o", 0.5))
            label = f'{r["gpu"]} ({r["table"]}) {r["kind"]}'
            x, y = float(r["published_ms"]), float(r["model_ms"])
            c = gpu_colors.get(r["gpu"], "gray")
            if bars and r["kind"] == "predicted" and r.get("model_lo_ms"):
                ax.errorbar(x, y, yerr=[[y - float(r["model_lo_ms"])], [float(r["model_hi_ms"]) - y]],
                            color=c, alpha=0.35, lw=0.8, capsize=0)
            ax.scatter(x, y, marker=m, alpha=a, color=c, label=None if label in seen else label, s=28)
            seen.add(label)
        ax.plot([lo, hi], [lo, hi], "k-", lw=0.8)
        ax.fill_between([lo, hi], [lo * 0.8, hi * 0.8], [lo * 1.2, hi * 1.2], color="gray", alpha=0.15,
                        label="±20%")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(lo, hi)
        ax.set_ylim(lo, hi)
        ax.set_xlabel("published ms (seed tables)")
        ax.set_ylabel("fovsim model ms")
        ax.set_title(title)
        ax.legend(fontsize=6, loc="upper left")
        ax.grid(True, which="both", alpha=0.2)
    # Per pass: published / model of the held-out rows, interval band of each row's table.
    ax = axes[2]
    held = [r for r in rows if r["experiment"].startswith("cross:") and r["kind"] == "predicted"
            and float(r["published_ms"]) > 0 and float(r["model_ms"]) > 0]
    passes = sorted({r["row"] for r in held})
    seen = set()
    for i, p in enumerate(passes):
        for r in held:
            if r["row"] != p:
                continue
            m = float(r["model_ms"])
            c = gpu_colors.get(r["gpu"], "gray")
            ax.scatter(float(r["published_ms"]) / m, i, color=c, s=18, alpha=0.8,
                       label=None if r["gpu"] in seen else r["gpu"])
            seen.add(r["gpu"])
            if r.get("model_lo_ms"):
                ax.plot([float(r["model_lo_ms"]) / m, float(r["model_hi_ms"]) / m], [i, i], color="gray",
                        alpha=0.15, lw=4)
    ax.axvline(1.0, color="k", lw=0.8)
    ax.set_xscale("log")
    ax.set_yticks(range(len(passes)))
    ax.set_yticklabels(passes, fontsize=7)
    ax.set_xlabel("published / model (held-out rows); grey: 80% interval")
    ax.set_title("held-out error per pass (table row)")
    ax.legend(fontsize=7, loc="lower right")
    ax.grid(True, which="both", alpha=0.2)
    fig.tight_layout()
    out = sys.argv[2]  # temporary name, then rename, like every fovsim output
    tmp = os.path.join(os.path.dirname(out) or ".", ".tmp.%d.%s" % (os.getpid(), os.path.basename(out)))
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, out)


if __name__ == "__main__":
    main()
