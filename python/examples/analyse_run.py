#!/usr/bin/python3
"""Worked example (docs/python.md): load a fovsim run with the pure-Python loader, print the
mean of each metric per method from the long (tidy) form, and — when the compiled module is
built — drive a tiny outside optimiser over KFR's sigma through the evaluation hook.

    /usr/bin/python3 python/examples/analyse_run.py results/quickstart
    /usr/bin/python3 python/examples/analyse_run.py results/quickstart --optimise configs/quickstart.json
"""
import argparse
import os
import sys

try:
    import fovsim  # installed: pip install --no-build-isolation --no-index -e python (docs/python.md)
except ImportError:  # run from a checkout without installing
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import numpy as np  # noqa: E402

import fovsim  # noqa: E402


def per_method_means(run_dir, metrics=("est_ms_total", "shaded_fraction", "fpsnr", "ssim")):
    """{(config_id, metric): mean over frames of finite values} from frames.csv in long form."""
    run = fovsim.load_run(run_dir)
    frames = run["frames"]
    metrics = [m for m in metrics if m in frames.dtype.names]
    tidy = fovsim.long_format(frames, ["config_id", "frame"], metrics)
    out = {}
    for cid in dict.fromkeys(tidy["config_id"]):
        for m in metrics:
            v = tidy["value"][(tidy["config_id"] == cid) & (tidy["metric"] == m)]
            v = v[np.isfinite(v)]
            out[(str(cid), m)] = float(v.mean()) if len(v) else float("nan")
    return out, metrics


def optimise_sigma(config, out, budget_fraction=0.35, rounds=2):
    """Outside optimiser (a bracketing search over sigma, ask/tell style): maximise fpsnr of
    KFR subject to shaded_fraction <= budget_fraction. Returns (best sigma, its summary row)."""
    ev = fovsim.Evaluator(config, overrides={"methods": [{"method": "kfr"}]}, out=out)
    lo, hi, best = 1.2, 3.0, None
    for _ in range(rounds):
        asks = [lo + (hi - lo) * k / 3 for k in range(4)]                # ask
        rows = ev.evaluate([{"methods[0].sigma": s} for s in asks])     # evaluate
        for s, summ in zip(asks, rows):                                 # tell
            r = summ[0]
            ok = r["shaded_fraction"] <= budget_fraction
            if ok and (best is None or r["fpsnr"] > best[1]["fpsnr"]):
                best = (s, r)
        if best is None:
            lo, hi = hi, hi * 1.5
        else:
            step = (hi - lo) / 3
            lo, hi = max(1.01, best[0] - step), best[0] + step
    return best


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run_dir")
    ap.add_argument("--optimise", metavar="CONFIG", help="also optimise KFR's sigma on this run config")
    ap.add_argument("--out", default="results/example_optimise")
    a = ap.parse_args(argv)
    means, metrics = per_method_means(a.run_dir)
    cids = list(dict.fromkeys(c for c, _ in means))
    print("config".ljust(14) + "".join(m.rjust(18) for m in metrics))
    for c in cids:
        print(c.ljust(14) + "".join(f"{means[(c, m)]:18.4f}" for m in metrics))
    if a.optimise:
        best = optimise_sigma(a.optimise, a.out)
        if best is None:
            print("no sigma met the shaded-fraction budget")
        else:
            print(f"best sigma {best[0]:.3f}: fpsnr {best[1]['fpsnr']:.3f} dB, "
                  f"shaded_fraction {best[1]['shaded_fraction']:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
