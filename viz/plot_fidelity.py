#!/usr/bin/python3
"""Log-log plot of a fidelity ladder: error against simulation time (docs/fidelity.md).

    /usr/bin/python3 viz/plot_fidelity.py results/<name>_fidelity [--out DIR]

Reads fidelity.csv (one row per rung x config x output; `fovsim fidelity`) and writes
<dir>/plots/fidelity.png: one panel per headline output, x = the rung's wall time (s),
y = the largest |error| over the methods against the top rung (relative for frame times,
absolute otherwise), one point per rung, labelled; error bars: the largest 95% half-width of
the error (err_ci95) over the same methods. A rung with error 0 (the top rung) is drawn at the
panel's floor. Exit status: 0, or 2 when fidelity.csv is missing.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from common import log, read_csv, to_float  # noqa: E402

RELATIVE = {"est_ms_total", "est_ms_total_p95"}
COSTS = ["est_ms_total", "est_ms_total_p95", "shaded_fraction"]  # + the headline metrics (registry)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir")
    ap.add_argument("--out")
    common.add_output_args(ap, configs=False)
    a = ap.parse_args(argv)
    common.set_output(a)
    cols, rows = read_csv(os.path.join(a.dir, "fidelity.csv"))
    if rows is None:
        log(f"no fidelity.csv in {a.dir}")
        return 2
    out = a.out or os.path.join(a.dir, "plots")
    os.makedirs(out, exist_ok=True)
    # The outputs fidelity.csv has, costs first, then metrics in the C++ registry's order.
    order = COSTS + common.headline_metrics()
    seen = [r["output"] for r in rows]
    outputs = [o for o in order if o in seen] + [o for o in dict.fromkeys(seen) if o not in order]
    # Per output and rung: (wall_s, max |err|, max ci).
    data = {}
    for r in rows:
        o = r["output"]
        if o not in outputs:
            continue
        err = to_float(r["err_rel"] if o in RELATIVE else r["err"])
        ci = to_float(r["err_ci95"])
        if o in RELATIVE and math.isfinite(ci):
            top = abs(to_float(r["top"]))
            ci = ci / top if top > 0 else math.nan
        key = (o, r["rung"])
        w = to_float(r["wall_s"])
        e0, c0 = data.get(key, (w, -1.0, math.nan))[1:]
        if math.isfinite(err) and abs(err) > e0:
            e0 = abs(err)
        if math.isfinite(ci) and not (ci <= c0):
            c0 = ci
        data[key] = (w, e0, c0)
    if not outputs:
        log("fidelity.csv has no rows")
        return 0
    rung_order = []
    for r in rows:
        if r["rung"] not in rung_order:
            rung_order.append(r["rung"])
    colour = {rung: f"C{i % 10}" for i, rung in enumerate(rung_order)}  # same colour per rung
    n = len(outputs)
    fig, axes = common.figure(n, height=2.3, legend=rung_order)
    for i, o in enumerate(outputs):
        ax = axes[i]
        pts = [(rung, *v) for (oo, rung), v in data.items() if oo == o and v[1] >= 0]
        pos = [p[2] for p in pts if p[2] > 0]
        floor = min(pos) / 10 if pos else 1e-6
        for rung, w, e, c in pts:
            y = e if e > 0 else floor
            if not (math.isfinite(w) and w > 0):
                continue
            yerr = [[0], [c]] if math.isfinite(c) and c > 0 else None
            # The rung is named by its colour in the legend below (labels beside the points collide).
            ax.errorbar([w], [y], yerr=yerr, fmt="o", capsize=3, color=colour[rung], label=rung)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time of the rung [s]")
        ax.set_ylabel("max |relative error|" if o in RELATIVE else "max |error|")
        ax.set_title(o)
        ax.grid(True, which="both", alpha=0.3)
    common.figure_legend(fig, axes)
    fig.suptitle("Fidelity ladder: error vs. simulation time (top rung = truth, drawn at the floor)")
    path = os.path.join(out, "fidelity.png")
    common.save(fig, path)
    log(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
