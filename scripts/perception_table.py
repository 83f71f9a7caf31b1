#!/usr/bin/env python3
"""Verdicts of docs/perception.md from perception sweeps' summary.csv.

For every row: dJOD = 10 - fvvdp_jod_fl with its 95% interval [10 - fvvdp_jod_fl_hi,
10 - fvvdp_jod_fl_lo], the probability that an observer prefers regular rendering,
P = Phi(0.6745 * dJOD) (1 JOD = 75% preference, Mantiuk et al. 2021), and the verdict:
invisible (interval <= T80), noticed (interval >= TMOST), small (inside [T80, TMOST]),
undecided (straddles a threshold). Below the display's own resolution the interval is widened
by the measured JOD bias of the run's render.scale (manifest fidelity.jod, docs/fidelity.md);
where none is measured the verdict is "needs native resolution". Prints one Markdown table per
sweep folder, stamped with the fovsim version, the plan hash of the sweep, and the pixels per
degree the metric saw against the display's native ones.

    scripts/perception_table.py DIR [DIR ...]
"""
import csv
import glob
import json
import math
import os
import sys

T80 = 0.38   # P = 0.60: 20% of observers see it, the others guess
TMOST = 1.0  # P = 0.75: half of them see it
Z75 = 0.6744897501960817


def phi(x):
    return 0.5 * (1.0 + math.erf(x / math.sqrt(2.0)))


def verdict(lo, hi):
    if hi <= T80:
        return "invisible"
    if lo >= TMOST:
        return "noticed"
    if lo >= T80 and hi <= TMOST:
        return "small"
    return "undecided"


def num(row, key):
    try:
        return float(row[key])
    except (KeyError, ValueError):
        return float("nan")


def stamp(d):
    """(version, plan text, JOD record of the run's fidelity: manifest fidelity.jod, the
    reference's render.spp)."""
    version, plan, extra, jod, spp = "?", "?", "", {}, "?"
    for m in sorted(glob.glob(os.path.join(d, "runs", "*", "manifest.json")))[:1]:
        with open(m) as f:
            j = json.load(f)
        version = f"{j.get('version', '?')} ({j.get('git_commit', '?')})"
        spp = j.get("resolved_config", {}).get("render", {}).get("spp", "?")
        fv = j.get("fvvdp", {})
        extra = f"; {fv.get('mode', '?')} at {fv.get('fps', '?')} Hz; {fv.get('display', '')}"
        jod = j.get("fidelity", {}).get("jod") or {}
        if jod:
            extra += (f"; {jod.get('ppd_simulated', float('nan')):.3g} of the display's "
                      f"{jod.get('ppd_display', float('nan')):.3g} px/deg")
            if not jod.get("native", False):
                b = (jod.get("bias") or {}).get("fvvdp_jod_fl")
                extra += (f", JOD bias ±{b:.2f} (in the intervals)" if b is not None
                          else ", no measured JOD bias: verdicts need native resolution")
    sj = os.path.join(d, "sweep_summary.json")
    if os.path.exists(sj):
        with open(sj) as f:
            plan = json.load(f).get("plan_hash", "?")
    return version, plan + extra, jod, spp


def table(d):
    with open(os.path.join(d, "summary.csv")) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        return
    axes = [k for k in rows[0] if k.startswith("methods[")]
    version, plan, jod, spp = stamp(d)
    native = jod.get("native", False) if jod else False
    bias = 0.0 if native else (jod.get("bias") or {}).get("fvvdp_jod_fl") if jod else None
    print(f"\n#### {os.path.basename(os.path.normpath(d))} (fovsim {version}, plan {plan})\n")
    head = axes + ["shaded", "fpsnr_fl [dB]", "fvvdp_jod_fl", "ΔJOD [95%]", "P(prefer full)",
                   "verdict", f"fvvdp_jod (vs the {spp}-spp reference)"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    best_jod = max(rows, key=lambda r: num(r, "fvvdp_jod_fl"))
    best_fpsnr = max(rows, key=lambda r: num(r, "fpsnr_fl"))
    for r in rows:
        j, lo, hi = num(r, "fvvdp_jod_fl"), num(r, "fvvdp_jod_fl_lo"), num(r, "fvvdp_jod_fl_hi")
        d_, dlo, dhi = 10 - j, 10 - hi, 10 - lo
        if bias is not None:  # the measured bias of the run's render.scale widens the interval
            dlo, dhi = dlo - bias, dhi + bias
        mark = ""
        if r is best_jod:
            mark += " (max JOD)"
        if r is best_fpsnr:
            mark += " (max FPSNR)"
        cells = [r[a] for a in axes] + [
            f"{num(r, 'shaded_fraction'):.3f}",
            f"{num(r, 'fpsnr_fl'):.2f} ± {num(r, 'fpsnr_fl_ci95'):.2f}",
            f"{j:.3f}",
            f"{d_:.3f} [{dlo:.3f}, {dhi:.3f}]",
            f"{phi(Z75 * d_):.2f}",
            (verdict(dlo, dhi) if bias is not None else "needs native resolution") + mark,
            f"{num(r, 'fvvdp_jod'):.3f}",
        ]
        print("| " + " | ".join(cells) + " |")
    if best_jod is not best_fpsnr:
        bj_lo = num(best_jod, "fvvdp_jod_fl_lo")
        bf_hi = num(best_fpsnr, "fvvdp_jod_fl_hi")
        print(f"\nmax FPSNR and max JOD differ; the FPSNR optimum's JOD interval "
              f"{'lies below' if bf_hi < bj_lo else 'overlaps'} the JOD optimum's.")


def main():
    if len(sys.argv) < 2:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    for d in sys.argv[1:]:
        table(d)
    return 0


if __name__ == "__main__":
    sys.exit(main())
