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

Runs of a minute or more (a worked example on a shipped config) are in SLOW_RUNS and are
reproduced only with `--slow` (`make docs` and `make docs-check`, never ctest): their numbers
are skipped without it. Besides CSV cells, a number may come from a JSON file of the run
(`where` = (list of keys to a list of objects, filter dict); `col` the object's key) or from the
command's stdout (`file` "stdout", `where` a regular expression, `col` its group). Words that
must match a run (an order of configurations) sit between `<!--s:ID-->` and `<!--/s-->` and
are given by TEXTS: (run, "stdout" or a JSON file, a function of the parsed output).

    scripts/docs_numbers.py [--fovsim build/fovsim] [--check | --update] [--slow]
"""
import json
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

# Slow runs (`--slow` only): name -> fovsim arguments, or {"cmd": [...]} with "{fovsim}" and
# "{out}" replaced (a Python example; /usr/bin/python3 as in docs/python.md).
SLOW_RUNS = {
    # docs/intervals.md "The ranking target" (about a minute on 2 cores)
    "rank_long": ["run", "configs/target_long.json", "--target", "ranking:fpsnr", "--no-plots", "-q"],
    # docs/python.md "Worked examples": asktell_kfr.py on a 10-frame quickstart at 0.25
    "asktell": {"cmd": ["/usr/bin/python3", "python/examples/asktell_kfr.py", "configs/quickstart.json",
                        "frames.count=10", "render.scale=0.25", "--evaluations", "8", "--out", "{out}"]},
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

# docs/intervals.md "The ranking target": the neighbour pairs of the ranking run.
_RANK = ["target", "achieved", "ranking:fpsnr", "pairs"]
for _a, _b in (("full", "fvrs"), ("fvrs", "rmfr"), ("rmfr", "kfr")):
    NUMBERS[f"rk_{_a}_{_b}"] = ("rank_long", "manifest.json", (_RANK, {"a": _a, "b": _b}), "diff", "ci95", 2)
NUMBERS["rk_frames"] = ("rank_long", "manifest.json", (["target"], {}), "frames_used", None, 0)
NUMBERS["rk_warmup"] = ("rank_long", "manifest.json", (["target"], {}), "warmup_frames", None, 0)
NUMBERS["rk_common"] = ("rank_long", "manifest.json", (_RANK, {"a": "fvrs", "b": "rmfr"}), "frames", None, 0)

# docs/python.md: asktell_kfr.py's printed answer.
_N = r"([+\-]?\d+(?:\.\d+)?)"
NUMBERS["at_sigma"] = ("asktell", "stdout", r"best sigma " + _N, 1, None, 2)
NUMBERS["at_fpsnr"] = ("asktell", "stdout", r"best sigma \S+: fpsnr " + _N, 1, None, 3)
for _m, _i in (("est_ms_total", "at_est_ms_total"), ("fpsnr", "at_mean_fpsnr"), ("ssim", "at_ssim"),
               ("shaded_fraction", "at_shaded_fraction")):
    NUMBERS[_i] = ("asktell", "stdout", r"mean " + _m + r"\s+" + _N, 1, None, 4)
for _g in ("gtx1080", "rtx2080ti"):
    NUMBERS[f"at_{_g}_ms"] = ("asktell", "stdout", _g + r"\s+kfr:\S+ " + _N + " ms", 1, None, 3)
    NUMBERS[f"at_{_g}_x"] = ("asktell", "stdout", _g + r"\s+kfr:\S+ \S+ ms, " + _N + "x", 1, None, 2)


def _rank_order(man):
    order = man["target"]["achieved"]["ranking:fpsnr"]["order"]
    return " > ".join(next(iter(order.values())))


TEXTS = {
    "rk_order": ("rank_long", "manifest.json", _rank_order),
    "at_asks": ("asktell", "stdout",
                lambda out: ", ".join(f"{float(x):g}" for x in re.findall(r"^  sigma (\S+): fpsnr", out, re.M))),
}

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


def _json_rows(path, where):
    keys, filt = where
    with open(path) as fh:
        node = json.load(fh)
    for k in keys:
        node = node[k]
    rows = node if isinstance(node, list) else [node]
    return [r for r in rows if all(r.get(k) == v for k, v in filt.items())]


def reproduce(fovsim, out, runs):
    values, texts = {}, {}
    tables, stdout = {}, {}
    for name, args in runs.items():
        d = os.path.join(out, name)
        if isinstance(args, dict):
            cmd = [a.replace("{fovsim}", fovsim).replace("{out}", d) for a in args["cmd"]]
        else:
            cmd = [fovsim] + args + ["--out", d]
        r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"docs_numbers: {' '.join(cmd)} failed:\n{r.stdout}{r.stderr}")
        tables[name] = d
        stdout[name] = r.stdout
    for nid, (run, f, where, col, ci, dec) in NUMBERS.items():
        if run not in runs:
            continue
        if f == "stdout":
            m = re.search(where, stdout[run], re.M)
            if not m:
                sys.exit(f"docs_numbers: {nid}: /{where}/ not in the output of {run}:\n{stdout[run]}")
            values[nid] = (float(m.group(col)), None, dec)
            continue
        path = os.path.join(tables[run], f)
        if f.endswith(".json"):
            rows = _json_rows(path, where)
        else:
            with open(path, newline="") as fh:
                rows = [r for r in csv.DictReader(fh) if all(r.get(k) == v for k, v in where.items())]
        if len(rows) != 1:
            sys.exit(f"docs_numbers: {nid}: {len(rows)} rows of {f} match {where}")
        values[nid] = (float(rows[0][col]), float(rows[0][ci]) if ci else None, dec)
    for tid, (run, f, fn) in TEXTS.items():
        if run not in runs:
            continue
        if f == "stdout":
            texts[tid] = fn(stdout[run])
        else:
            with open(os.path.join(tables[run], f)) as fh:
                texts[tid] = fn(json.load(fh))
    return values, texts


TEXT = re.compile(r"<!--s:(\w+)-->(.*?)<!--/s-->", re.S)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fovsim", default=os.path.join(ROOT, "build", "fovsim"))
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--check", action="store_true", default=True)
    g.add_argument("--update", action="store_true")
    ap.add_argument("--slow", action="store_true",
                    help="also the slow runs (SLOW_RUNS, a minute or more each): make docs, make docs-check")
    a = ap.parse_args()
    runs = dict(RUNS, **(SLOW_RUNS if a.slow else {}))
    skipped = {nid for nid, n in NUMBERS.items() if n[0] not in runs} | \
              {tid for tid, t in TEXTS.items() if t[0] not in runs}
    with tempfile.TemporaryDirectory(prefix="fovsim_docs_") as tmp:
        values, texts = reproduce(a.fovsim, tmp, runs)
    failures, seen = [], set()
    for doc in DOCS:
        path = os.path.join(ROOT, doc)
        text = open(path, encoding="utf-8").read()

        def check(m):
            nid = m.group(1)
            if nid in skipped:
                return m.group(0)
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

        def check_text(m):
            tid = m.group(1)
            if tid in skipped:
                return m.group(0)
            if tid not in texts:
                failures.append(f"{doc}: unknown text id {tid}")
                return m.group(0)
            seen.add(tid)
            if a.update:
                return f"<!--s:{tid}-->{texts[tid]}<!--/s-->"
            if m.group(2) != texts[tid]:
                failures.append(f"{doc}: {tid} is \"{m.group(2)}\" in the page, the run gives "
                                f"\"{texts[tid]}\"; run `make docs`")
            return m.group(0)

        new_text = TEXT.sub(check_text, PATTERN.sub(check, text))
        if a.update and new_text != text:
            open(path, "w", encoding="utf-8").write(new_text)
            print(f"updated {doc}")
    for nid in list(NUMBERS) + list(TEXTS):
        if nid not in seen and nid not in skipped:
            failures.append(f"number {nid} is quoted in none of {', '.join(DOCS)}")
    if failures:
        print("\n".join(failures), file=sys.stderr)
        return 1
    print(f"docs_numbers: {len(seen)} numbers {'updated' if a.update else 'reproduce'}" +
          (f" ({len(skipped)} of the slow runs not checked: --slow)" if skipped else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
