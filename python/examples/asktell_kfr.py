#!/usr/bin/python3
"""Tune KFR's sigma with fovsim's ask/tell searcher driven from Python, then look at the best
point in tidy form and ask the cost model whether it fits 90 Hz on two GPUs.

    /usr/bin/python3 python/examples/asktell_kfr.py configs/quickstart.json \
        [--evaluations 8] [--out results/asktell_kfr] [key.path=value ...]

1. fovsim.AskTell: maximise fpsnr of the `kfr` row subject to shaded_fraction <= --max-shaded,
   over methods[kfr].sigma in [1.2, 3.0] (step 0.1); the loop below is what an outside
   optimiser would do (ask, evaluate — or run anything else — and tell).
2. fovsim.tidy: the best evaluation's frames.csv in long form (one row per frame x metric, the
   parameters as columns), averaged per metric (pandas when installed, else numpy).
3. fovsim.predict / fovsim.budget: the analytic cost model for the best sigma (workload
   kfr_bistro, HTC Vive Pro Eye) — what `fovsim predict` / `fovsim budget` print.
Run by ctest (PythonApi) on a 2-frame, 5%-resolution config. docs/python.md.
"""
import argparse
import math
import os
import sys

try:
    import fovsim  # installed: pip install --no-build-isolation --no-index -e python (docs/python.md)
except ImportError:  # run from a checkout without installing
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import fovsim  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("config")
    ap.add_argument("overrides", nargs="*", help="key.path=value applied to the config")
    ap.add_argument("--evaluations", type=int, default=8)
    ap.add_argument("--max-shaded", type=float, default=0.35, help="constraint on shaded_fraction")
    ap.add_argument("--out", default="results/asktell_kfr")
    ap.add_argument("--gpus", default="gtx1080,rtx2080ti")
    a = ap.parse_args(argv)

    # Only KFR is evaluated (the other methods of the config would not change the score).
    overrides = [f"methods={[{'method': 'kfr', 'alpha': 4}]}".replace("'", '"')] + a.overrides
    opt = fovsim.AskTell(a.config, overrides=overrides, out=a.out,
                         space={"methods[kfr].sigma": {"from": 1.2, "to": 3.0, "step": 0.1}},
                         maximize="fpsnr", subject_to={"shaded_fraction": {"max": a.max_shaded}},
                         label="kfr", batch=4, seed=1)
    print(f"search: maximize fpsnr subject to shaded_fraction <= {a.max_shaded}, {a.evaluations} evaluations")
    while len(opt.history) < a.evaluations:
        xs = opt.ask()
        if not xs:
            break  # converged: the step is below the space's resolution
        for x in xs[:a.evaluations - len(opt.history)]:
            rows = opt.evaluate(x)  # an outside optimiser could run anything here
            score, viol = opt.tell(x, rows)
            kfr = [r for r in rows if r["label"] == "kfr"][0]
            print(f"  sigma {x['methods[kfr].sigma']:.2f}: fpsnr {score:.3f} dB, shaded_fraction "
                  f"{kfr['shaded_fraction']:.3f}" + ("" if viol == 0 else f" (violates by {viol:.3f})"))
    best = opt.best
    if best is None:
        print("no evaluation")
        return 1
    sigma = best["x"]["methods[kfr].sigma"]
    print(f"best sigma {sigma:.2f}: fpsnr {best['score']:.3f} dB" +
          (" (feasible)" if best["violation"] == 0 else f" (infeasible by {best['violation']:.3f})"))

    # The best evaluation's folder (<out>/eval_<n>, n = its place in the tell order).
    n = [i for i, (x, s, v) in enumerate(opt.history) if x["methods[kfr].sigma"] == sigma][0]
    tidy = fovsim.tidy(os.path.join(a.out, f"eval_{n}"),
                       metrics=["est_ms_total", "shaded_fraction", "fpsnr", "ssim", "psnr"])
    print(f"tidy form of eval_{n}: {len(tidy)} rows (frame x metric), parameter columns "
          f"{fovsim.parameter_columns(fovsim.load_run(os.path.join(a.out, f'eval_{n}')))}")
    if hasattr(tidy, "groupby"):  # pandas
        means = tidy[tidy["value"].map(math.isfinite)].groupby("metric")["value"].mean()
        for m, v in means.items():
            print(f"  mean {m:16s} {v:.4f}")
    else:
        for m in sorted(set(tidy["metric"])):
            v = tidy["value"][(tidy["metric"] == m) & __import__("numpy").isfinite(tidy["value"])]
            print(f"  mean {m:16s} {v.mean():.4f}")

    gpus = a.gpus.split(",")
    meth = f"kfr:sigma={sigma:g},alpha=4"
    pred = fovsim.predict(gpu=gpus, workload="kfr_bistro", methods=["full", meth], as_frame=False)
    bud = fovsim.budget(gpu=gpus, workload="kfr_bistro", methods=[meth], hz=90, as_frame=False)
    print(f"cost model (workload kfr_bistro, {fovsim.DEFAULT_DISPLAY}, 90 Hz budget 11.11 ms):")
    for p in pred:
        if p["method"] == "kfr":
            b = [x for x in bud if x["gpu"] == p["gpu"]][0]
            print(f"  {p['gpu']:10s} {meth}: {p['est_ms_total']:.3f} ms, {p['speedup_vs_full']:.2f}x vs full, "
                  f"{b['verdict']} (headroom {b['headroom_ms']:+.3f} ms)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
