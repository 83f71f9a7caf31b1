#!/usr/bin/env python3
"""Ye et al. 2022 Fig. 12 (§6.1) from a run of configs/perception/ye2022_fig12.json.

The paper rotates three textured patterns over 180 degrees, scores the four foveation methods at
the same compression (sigma 2.6) with FPSNR and FovVideoVDP at every rotation step, and reports
the mean over the steps per pattern, with RMFR "with the optimal parameters at each rotation
step". Here RMFR's optimum is the best of the config's f_x, f_y grid per step (`rmfr_opt`, taken
per metric), next to RMFR at its default 0.38/0.38 (`rmfr`). For each pattern it prints the mean
over the steps with a 95% t-interval across the steps (the spread of the rotation, not of
observers), the FovVideoVDP order of RMFR, log-polar (KFR), hyperbolic and linear, and for each
adjacent pair of that order the paired difference with its 95% interval, next to the paper's
values (transcribed from the table of Fig. 12; FPSNR in dB, FovVideoVDP in JOD).

    scripts/ye2022_fig12.py SWEEP_DIR
"""
import csv
import glob
import json
import math
import os
import sys

# Ye et al. 2022, Fig. 12 (table under the snapshots), per pattern: FPSNR, FovVideoVDP.
PAPER = {
    "a": {"rmfr": (35.90, 9.56), "kfr": (34.49, 9.49), "hyperbolic": (30.65, 8.91),
          "linear": (27.99, 8.32)},
    "b": {"rmfr": (23.98, 8.42), "kfr": (19.33, 7.29), "hyperbolic": (19.11, 6.88),
          "linear": (15.85, 5.40)},
    "c": {"rmfr": (29.87, 8.90), "kfr": (26.94, 8.35), "hyperbolic": (26.26, 8.31),
          "linear": (22.89, 7.42)},
}
# Which of the scene's patterns stands in for the paper's (a), (b), (c) (configs/README.md).
PATTERN = {"stripes": "a", "checker": "b", "grating": "c"}
FOUR = ["rmfr_opt", "kfr", "hyperbolic", "linear"]
NAME = {"rmfr_opt": "RMFR (best f_x, f_y)", "rmfr": "RMFR (0.38, 0.38)", "rmfr_auto": "rmfr_auto",
        "kfr": "log-polar (KFR)", "hyperbolic": "hyperbolic", "linear": "linear"}
T975 = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365, 8: 2.306,
        9: 2.262, 10: 2.228, 12: 2.179, 15: 2.131, 17: 2.110, 20: 2.086}


def t975(dof):
    keys = sorted(k for k in T975 if k <= dof)
    return T975[keys[-1]] if keys else float("nan")


def mean_ci(xs):
    n = len(xs)
    m = sum(xs) / n
    if n < 2:
        return m, float("nan")
    sd = math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1))
    return m, t975(n - 1) * sd / math.sqrt(n)


def load(sweep):
    """{pattern: {angle: {label: (fpsnr, jod, shaded_fraction)}}}"""
    out = {}
    for cell in sorted(glob.glob(os.path.join(sweep, "runs", "*", "cell.json"))):
        c = json.load(open(cell))
        if c.get("status") != "complete":
            continue
        a = {x["path"]: x["value"] for x in c["assign"]}
        rows = list(csv.DictReader(open(os.path.join(os.path.dirname(cell), "summary.csv"))))
        per = {r["label"]: (float(r["fpsnr"]), float(r["fvvdp_jod"]), float(r["shaded_fraction"]))
               for r in rows if r["label"] != "full"}
        out.setdefault(a["scene.pattern"], {})[a["scene.angle"]] = per
    return out


def values(steps, label, k):
    if label == "rmfr_opt":  # the best RMFR of the grid at each step, per metric
        return [max(v[k] for lab, v in per.items() if lab.startswith("rmfr") and lab != "rmfr_auto")
                for per in steps]
    return [per[label][k] for per in steps]


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    data = load(sys.argv[1])
    if not data:
        sys.exit(f"ye2022_fig12.py: no complete cells under {sys.argv[1]}/runs")
    for pattern in ["stripes", "checker", "grating"]:
        if pattern not in data:
            continue
        fig = PATTERN[pattern]
        angles = sorted(data[pattern])
        steps = [data[pattern][a] for a in angles]
        print(f"\n#### Pattern ({fig}): `{pattern}`, {len(angles)} rotations "
              f"({angles[0]}-{angles[-1]} deg)\n")
        print("| method | shaded fraction | FPSNR dB (95% over rotations) | paper | "
              "FovVideoVDP JOD (95%) | paper |")
        print("|---|---|---|---|---|---|")
        jod = {}
        for label in ["rmfr_opt", "rmfr", "rmfr_auto", "kfr", "hyperbolic", "linear"]:
            fp, fpc = mean_ci(values(steps, label, 0))
            jm, jc = mean_ci(values(steps, label, 1))
            sf, _ = mean_ci(values(steps, "rmfr" if label == "rmfr_opt" else label, 2))
            jod[label] = jm
            key = "rmfr" if label == "rmfr_opt" else label
            paper = PAPER[fig].get(key) if label in FOUR else None
            pf = f"{paper[0]:.2f}" if paper else ""
            pj = f"{paper[1]:.2f}" if paper else ""
            print(f"| {NAME[label]} | {sf:.3f} | {fp:.2f} ± {fpc:.2f} | {pf} | {jm:.3f} ± {jc:.3f} "
                  f"| {pj} |")
        order = sorted(FOUR, key=lambda l: -jod[l])
        paper_order = ["rmfr_opt", "kfr", "hyperbolic", "linear"]
        same = order == paper_order
        print(f"\nFovVideoVDP order: {' > '.join(NAME[l] for l in order)} "
              f"({'the paper' + chr(39) + 's order' if same else 'the paper: RMFR > log-polar > hyperbolic > linear'}).")
        print("Adjacent pairs of the paper's order, paired over rotations (JOD, 95%):")
        for hi, lo in zip(paper_order, paper_order[1:]):
            d = [x - y for x, y in zip(values(steps, hi, 1), values(steps, lo, 1))]
            m, c = mean_ci(d)
            word = ("agrees" if m - c > 0 else "disagrees" if m + c < 0 else "unresolved")
            print(f"- {NAME[hi]} - {NAME[lo]}: {m:+.3f} ± {c:.3f} ({word})")


if __name__ == "__main__":
    main()
