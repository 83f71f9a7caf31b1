#!/usr/bin/python3
"""Predicted vs. published pass times (Accel-Sim-style correlation plot) for
`fovsim validate-cost`. Usage: plot_cost.py validate_cost.csv out.png"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_cost.py validate_cost.csv out.png")
    rows = list(csv.DictReader(open(sys.argv[1])))
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.5))
    styles = {"fitted": ("o", 0.8), "check": ("s", 0.8), "predicted": ("^", 0.9), "refit": ("x", 0.5)}
    colors = {"kfr": "tab:blue", "rmfr": "tab:orange", "twfr": "tab:green", "flc": "tab:red"}
    for ax, exp_filter, title in (
        (axes[0], lambda e: e == "calibration", "calibration fit (all tables)"),
        (axes[1], lambda e: e.startswith("cross:"), "cross-predictions (held-out seed / scene)"),
    ):
        seen = set()
        for r in rows:
            if not exp_filter(r["experiment"]) or float(r["published_ms"]) <= 0:
                continue
            m, a = styles.get(r["kind"], ("o", 0.5))
            label = f'{r["table"]} {r["kind"]}'
            ax.scatter(float(r["published_ms"]), float(r["model_ms"]), marker=m, alpha=a,
                       color=colors.get(r["table"], "gray"), label=None if label in seen else label, s=28)
            seen.add(label)
        lo, hi = 0.01, 60
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
        ax.legend(fontsize=7, loc="upper left")
        ax.grid(True, which="both", alpha=0.2)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)


if __name__ == "__main__":
    main()
