#!/usr/bin/env python3
"""Plot `fovsim density` output like Ye et al. 2022 Fig. 11: sampling density (shading samples per
screen pixel, capped at 1) against eccentricity, one panel per method, one line per direction.
Usage: plot_density.py DENSITY.csv OUT.png"""
import argparse
import csv
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("density_csv", help="`fovsim density` output")
    ap.add_argument("out_png", help="figure to write (PNG; --format adds PDF or SVG next to it)")
    common.add_output_args(ap, configs=False)
    a = ap.parse_args(argv)
    common.set_output(a)
    src, out = a.density_csv, a.out_png
    with open(src, newline="") as f:
        rows = list(csv.DictReader(f))
    methods = list(dict.fromkeys(r["method"] for r in rows))
    summary = {}
    js = os.path.splitext(src)[0] + ".json"
    if os.path.exists(js):
        with open(js) as f:
            summary = json.load(f).get("methods", {})
    dirs_all = list(dict.fromkeys(f"{float(r['direction_deg']):.0f}°" for r in rows))
    fig, axes = common.figure(len(methods), height=2.2, legend=dirs_all, sharey=True)
    for ax, m in zip(axes, methods):
        dirs = list(dict.fromkeys(r["direction_deg"] for r in rows if r["method"] == m))
        for k, d in enumerate(dirs):
            pts = [(float(r["ecc_deg"]), float(r["density_capped"])) for r in rows
                   if r["method"] == m and r["direction_deg"] == d]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], lw=1, label=f"{float(d):.0f}°",
                    ls=common.LINESTYLES[k % len(common.LINESTYLES)])
        title = m
        if m in summary:
            title += f"  (shaded {100 * summary[m]['shaded_fraction']:.1f} %)"
        ax.set_title(title)
        ax.set_xlabel("eccentricity [deg]")
        ax.set_ylim(0, 1.05)
        ax.grid(alpha=0.3)
    for i, ax in enumerate(axes):
        if i % common.MAX_COLUMNS == 0:
            ax.set_ylabel("samples per pixel\n(capped at 1)")
    lg = common.figure_legend(fig, axes)
    if lg is not None:
        lg.set_title("direction")
    # Temporary name, then rename, like every fovsim output (common.save).
    common.save(fig, out)
    print("wrote", out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
