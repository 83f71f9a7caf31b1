#!/usr/bin/env python3
"""Plot `fovsim density` output like Ye et al. 2022 Fig. 11: sampling density (shading samples per
screen pixel, capped at 1) against eccentricity, one panel per method, one line per direction.
Usage: plot_density.py DENSITY.csv OUT.png"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    src, out = sys.argv[1], sys.argv[2]
    rows = list(csv.DictReader(open(src)))
    methods = list(dict.fromkeys(r["method"] for r in rows))
    summary = {}
    js = os.path.splitext(src)[0] + ".json"
    if os.path.exists(js):
        summary = json.load(open(js)).get("methods", {})
    fig, axes = plt.subplots(1, len(methods), figsize=(4 * len(methods), 3.4), squeeze=False)
    for ax, m in zip(axes[0], methods):
        dirs = list(dict.fromkeys(r["direction_deg"] for r in rows if r["method"] == m))
        for d in dirs:
            pts = [(float(r["ecc_deg"]), float(r["density_capped"])) for r in rows
                   if r["method"] == m and r["direction_deg"] == d]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], lw=1, label=f"{float(d):.0f}°")
        title = m
        if m in summary:
            title += f"  (shaded {100 * summary[m]['shaded_fraction']:.1f} %)"
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("eccentricity (deg)")
        ax.set_ylim(0, 1.05)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("samples per pixel (capped at 1)")
    axes[0][-1].legend(fontsize=7, title="direction")
    fig.tight_layout()
    # Temporary name, then rename, like every fovsim output: a killed plot never leaves a
    # truncated PNG under its final name.
    tmp = os.path.join(os.path.dirname(out) or ".", ".tmp.%d.%s" % (os.getpid(), os.path.basename(out)))
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, out)
    print("wrote", out)


if __name__ == "__main__":
    main()
