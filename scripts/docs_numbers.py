#!/usr/bin/env python3
"""Worked numbers of docs/ that cannot go stale (`make docs`; checked by the test
Workflow.DocsNumbersReproduce).

Every number quoted in a worked example is written in the page right after a marker
`<!--n:ID-->`, e.g. `<!--n:iv_psnr-->−0.89 ± 0.12 dB`. NUMBERS below says which small run
produces it (a tiny config in docs/examples/, seconds on a laptop), which CSV row and column,
and how many decimals are printed. `--check` (the default) reruns those runs and fails when a
committed number differs from the reproduced one by more than its stated interval (the `± x`
printed with it), or, without an interval, by more than half a unit of its last printed digit.
`--update` rewrites the numbers in the pages instead.

    scripts/docs_numbers.py [--fovsim build/fovsim] [--check | --update]
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Runs: name -> fovsim arguments (relative to the repository root).
RUNS = {
    "pairs_tiny": ["run", "docs/examples/pairs_tiny.json", "-q", "--no-plots"],
    "latency_tiny": ["sweep", "docs/examples/latency_tiny.json", "-q", "--no-plots"],
    "converge_tiny": ["converge", "docs/examples/converge_tiny.json"],
}

# id -> (run, csv file, row filter, column, interval column or None, decimals)
NUMBERS = {
    # docs/intervals.md "Paired differences"
    "iv_psnr": ("pairs_tiny", "paired.csv", {"config_a": "rmfr", "config_b": "fvrs", "metric": "psnr"}, "diff", "diff_ci95", 2),
    "iv_fpsnr": ("pairs_tiny", "paired.csv", {"config_a": "rmfr", "config_b": "fvrs", "metric": "fpsnr"}, "diff", "diff_ci95", 2),
    "iv_ms": ("pairs_tiny", "paired.csv", {"config_a": "rmfr", "config_b": "fvrs", "metric": "est_ms_total"}, "diff", "diff_ci95", 3),
    "iv_ssim": ("pairs_tiny", "paired.csv", {"config_a": "rmfr", "config_b": "fvrs", "metric": "ssim"}, "diff", "diff_ci95", 4),
    "iv_rmfr_psnr": ("pairs_tiny", "summary.csv", {"label": "rmfr"}, "psnr", "psnr_ci95", 2),
    "iv_fvrs_psnr": ("pairs_tiny", "summary.csv", {"label": "fvrs"}, "psnr", "psnr_ci95", 2),
    # docs/python.md "Worked examples" (analyse_run.py prints the summary means)
    "py_kfr_ms": ("pairs_tiny", "summary.csv", {"label": "kfr"}, "est_ms_total", None, 4),
    "py_kfr_frac": ("pairs_tiny", "summary.csv", {"label": "kfr"}, "shaded_fraction", None, 4),
    "py_kfr_fpsnr": ("pairs_tiny", "summary.csv", {"label": "kfr"}, "fpsnr", None, 4),
    "py_kfr_ssim": ("pairs_tiny", "summary.csv", {"label": "kfr"}, "ssim", None, 4),
    # docs/latency.md (50 ms tracker latency in the tiny config)
    "lat_fvrs_rmse": ("pairs_tiny", "summary.csv", {"label": "fvrs"}, "rmse_fovea", "rmse_fovea_ci95", 4),
    "lat_kfr_rmse": ("pairs_tiny", "summary.csv", {"label": "kfr"}, "rmse_fovea", "rmse_fovea_ci95", 4),
    "lat_rmfr_rmse": ("pairs_tiny", "summary.csv", {"label": "rmfr"}, "rmse_fovea", "rmse_fovea_ci95", 4),
    # docs/fidelity.md (the run's simulated fraction of display pixels at render.scale 0.05)
    "fid_full_ms": ("pairs_tiny", "summary.csv", {"label": "full"}, "est_ms_total", None, 3),
}

# docs/latency.md "Checked table": the tiny latency sweep, per method and tracker latency.
for _m in ("kfr", "rmfr", "fvrs"):
    for _l in ("0", "20", "50", "80"):
        _w = {"label": _m, "latency.tracker_ms": _l}
        _i = f"lt_{_m}_{_l}"
        NUMBERS[_i + "_rmse"] = ("latency_tiny", "summary.csv", _w, "rmse_fovea", "rmse_fovea_ci95", 4)
        for _p, _s in (("saccade", "sac"), ("suppression", "sup"), ("fixation", "fix")):
            NUMBERS[f"{_i}_{_s}"] = ("latency_tiny", "summary.csv", _w, "rmse_fovea_" + _p, None, 4)
        NUMBERS[_i + "_fpsnr"] = ("latency_tiny", "summary.csv", _w, "fpsnr", None, 2)
for _l in ("0", "20", "50", "80"):
    NUMBERS[f"lt_gaze_{_l}"] = ("latency_tiny", "summary.csv", {"label": "kfr", "latency.tracker_ms": _l}, "gaze_error_deg", None, 2)
for _p, _s in (("saccade", "sac"), ("suppression", "sup"), ("fixation", "fix")):
    NUMBERS[f"lt_n_{_s}"] = ("latency_tiny", "summary.csv", {"label": "kfr", "latency.tracker_ms": "0"}, "frames_" + _p, None, 0)
for _b in ("50", "80"):
    NUMBERS[f"lt_kfr_fpsnr_0_{_b}"] = ("latency_tiny", "paired.csv", {"kind": "across", "config_a": "kfr", "metric": "fpsnr", "value_a": "0", "value_b": _b}, "diff", "diff_ci95", 2)

# docs/metrics.md "Reference convergence": the tiny convergence study.
for _m in ("full_tbds", "flc", "kfr", "rmfr", "fvrs", "twfr"):
    for _s in ("1", "4", "16", "64"):
        _w = {"label": _m, "spp": _s}
        if not (_m == "full_tbds" and _s == "1"):  # inf: the reference itself
            NUMBERS[f"cv_{_m}_{_s}_psnr"] = ("converge_tiny", "convergence.csv", _w, "psnr", None, 3)
            NUMBERS[f"cv_{_m}_{_s}_fpsnr"] = ("converge_tiny", "convergence.csv", _w, "fpsnr", None, 3)
        NUMBERS[f"cv_{_m}_{_s}_flip"] = ("converge_tiny", "convergence.csv", _w, "flip", None, 4)
for _s in ("1", "4", "16"):
    NUMBERS[f"cv_ok_{_s}"] = ("converge_tiny", "convergence.csv", {"label": "kfr", "spp": _s}, "level_ok", None, 0)

DOCS = ["docs/intervals.md", "docs/python.md", "docs/latency.md", "docs/fidelity.md", "docs/metrics.md"]

# A marker, the number (unicode or ASCII minus, optional +; "inf" for an image equal to its
# reference), optionally " ± interval".
NUM = r"[+\-\u2212]?(?:\d+(?:\.\d+)?|inf)"
PATTERN = re.compile(r"<!--n:(\w+)-->(" + NUM + r")(?:( ± )(" + NUM + r"))?")


def parse(s):
    return float(s.replace("\u2212", "-"))


def fmt(v, decimals, signed):
    s = f"{v:+.{decimals}f}" if signed else f"{v:.{decimals}f}"
    return s.replace("-", "\u2212")


def reproduce(fovsim, out):
    values = {}
    tables = {}
    for name, args in RUNS.items():
        d = os.path.join(out, name)
        r = subprocess.run([fovsim] + args + ["--out", d], cwd=ROOT, capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"docs_numbers: fovsim {' '.join(args)} failed:\n{r.stdout}{r.stderr}")
        tables[name] = d
    for nid, (run, f, where, col, ci, dec) in NUMBERS.items():
        with open(os.path.join(tables[run], f), newline="") as fh:
            rows = [r for r in csv.DictReader(fh) if all(r.get(k) == v for k, v in where.items())]
        if len(rows) != 1:
            sys.exit(f"docs_numbers: {nid}: {len(rows)} rows of {f} match {where}")
        values[nid] = (float(rows[0][col]), float(rows[0][ci]) if ci else None, dec)
    return values


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fovsim", default=os.path.join(ROOT, "build", "fovsim"))
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--check", action="store_true", default=True)
    g.add_argument("--update", action="store_true")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="fovsim_docs_") as tmp:
        values = reproduce(a.fovsim, tmp)
    failures, seen = [], set()
    for doc in DOCS:
        path = os.path.join(ROOT, doc)
        text = open(path, encoding="utf-8").read()

        def check(m):
            nid = m.group(1)
            if nid not in values:
                failures.append(f"{doc}: unknown number id {nid}")
                return m.group(0)
            seen.add(nid)
            v, ci, dec = values[nid]
            signed = m.group(2)[0] in "+-\u2212"
            new = fmt(v, dec, signed) + (" ± " + fmt(ci, dec, False) if m.group(4) else "")
            if a.update:
                return f"<!--n:{nid}-->" + new
            committed = parse(m.group(2))
            stated = parse(m.group(4)) if m.group(4) else 0.0
            tol = max(stated, 0.5 * 10 ** -dec) + 1e-12
            if abs(committed - v) > tol:
                failures.append(f"{doc}: {nid} is {m.group(2)} in the page, the run gives "
                                f"{fmt(v, dec, signed)} (allowed difference {tol:.{dec}g}); "
                                "run `make docs`")
            return m.group(0)

        new_text = PATTERN.sub(check, text)
        if a.update and new_text != text:
            open(path, "w", encoding="utf-8").write(new_text)
            print(f"updated {doc}")
    for nid in NUMBERS:
        if nid not in seen:
            failures.append(f"number {nid} is quoted in none of {', '.join(DOCS)}")
    if failures:
        print("\n".join(failures), file=sys.stderr)
        return 1
    print(f"docs_numbers: {len(seen)} numbers {'updated' if a.update else 'reproduce'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
