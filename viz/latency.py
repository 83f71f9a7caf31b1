#!/usr/bin/python3
"""Foveal quality vs latency per method, from a latency sweep (configs/sweeps/latency.json).

Reads <dir>/summary.csv (one row per cell x method), x = mean `latency_ms` of the cell,
y = a metric (default rmse_fovea) with its 95% interval `<metric>_ci95` as error bars, one
line per method label. Prints, per method, the first latency at which the metric is worse than
at the lowest latency by more than --margin (relative; for *psnr metrics, lower is worse).
Writes <dir>/plots/latency_<metric>.png and latency_<metric>.csv. See docs/latency.md.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from common import plt, to_float, log  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir", help="sweep results folder")
    ap.add_argument("--metric", default="rmse_fovea")
    ap.add_argument("--margin", type=float, default=0.10, help="relative drop that counts (default 0.10)")
    a = ap.parse_args()
    cols, rows = common.read_csv(os.path.join(a.dir, "summary.csv"))
    if not rows:
        sys.exit(f"{a.dir}/summary.csv: missing or empty")
    for need in ("latency_ms", a.metric):
        if need not in cols:
            sys.exit(f"{a.dir}/summary.csv: no column {need} (was the sweep run with a latency block?)")
    higher_is_better = a.metric.endswith("psnr") or a.metric == "ssim"
    by = {}
    for r in rows:
        by.setdefault(r.get("label", r.get("method", "?")), []).append(
            (to_float(r["latency_ms"]), to_float(r[a.metric]), to_float(r.get(a.metric + "_ci95"))))
    fig, ax = plt.subplots(figsize=(6, 4))
    lines = ["label,latency_ms,%s,%s_ci95,degraded" % (a.metric, a.metric)]
    for label, pts in sorted(by.items()):
        pts.sort()
        x = [p[0] for p in pts]
        y = [p[1] for p in pts]
        e = [0 if math.isnan(p[2]) else p[2] for p in pts]
        ax.errorbar(x, y, yerr=e, marker="o", capsize=3, label=label)
        base = y[0]
        first = None
        for xi, yi, ei in pts:
            diff = (base - yi) if higher_is_better else (yi - base)
            worse = diff / abs(base) if base else (math.inf if diff > 0 else 0.0)  # from exact: any rise counts
            deg = int(worse > a.margin)
            if deg and first is None:
                first = xi
            lines.append(f"{label},{xi:.6g},{yi:.6g},{ei:.6g},{deg}")
        print(f"{label}: {a.metric} {'drops' if higher_is_better else 'rises'} by more than "
              f"{100 * a.margin:.0f}% at " + (f"{first:.0f} ms" if first is not None else "no swept latency"))
    ax.set_xlabel("end-to-end latency (ms)")
    ax.set_ylabel(a.metric + " (95% interval)")
    ax.grid(alpha=0.3)
    ax.legend()
    out = os.path.join(a.dir, "plots", f"latency_{a.metric}.png")
    common.save(fig, out)
    common.write_text_atomic(os.path.join(a.dir, "plots", f"latency_{a.metric}.csv"), "\n".join(lines) + "\n")
    log(out)


if __name__ == "__main__":
    main()
