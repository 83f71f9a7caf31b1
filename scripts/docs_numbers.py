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

DOCS = ["docs/intervals.md", "docs/python.md", "docs/latency.md", "docs/fidelity.md"]

# A marker, the number (unicode or ASCII minus, optional +), optionally " ± interval".
NUM = r"[+\-\u2212]?\d+(?:\.\d+)?"
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
