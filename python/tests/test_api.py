#!/usr/bin/python3
"""Tests of the Python API beyond run/sweep: predict/budget against the CLI's
`--json`, the AskTell search, the tidy form with parameter columns, and the example
python/examples/asktell_kfr.py. Run by ctest (PythonApi) with FOVSIM_PYTHON_EXT=<build>/python;
exits 77 (skipped) when numpy or the compiled module is missing. Tiny configs: seconds."""
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

# The checkout's package first, installed (pip install -e python) or not: the tests check this tree.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
try:
    import fovsim  # noqa: E402
    from fovsim import engine  # noqa: E402

    engine._module()
except ImportError as e:
    print(f"skipped: {e}")
    sys.exit(77)

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXT = os.environ.get("FOVSIM_PYTHON_EXT", os.path.join(REPO, "build", "python"))
CLI = os.path.join(os.path.dirname(os.path.abspath(EXT)), "fovsim")
CONFIG = {
    "name": "py_api_test",
    "display": fovsim.DEFAULT_DISPLAY,
    "render": {"scale": 0.05},
    "scene": {"type": "atrium", "complexity": 1},
    "trace": {"file": os.path.join(REPO, "tests/golden/golden_trace.csv")},
    "frames": {"count": 2},
    "methods": [{"method": "full"}, {"method": "kfr", "sigma": 1.8}],
    "outputs": {"print_summary": False},
}


def cli_json(args):
    p = subprocess.run([CLI] + args + ["--json"], capture_output=True, text=True, cwd=REPO)
    if p.returncode != 0:
        raise AssertionError(p.stderr)
    return json.loads(p.stdout)


def close(a, b):
    if isinstance(a, str) or isinstance(b, str):
        return str(a) == str(b) or (str(b) == "inf" and math.isinf(float(a)))
    return math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-12)


class CostTest(unittest.TestCase):
    @unittest.skipUnless(os.path.exists(CLI), "no fovsim binary beside the module")
    def test_predict_matches_cli(self):
        py = fovsim.predict(gpu=["gtx1080", "rtx2080ti"], workload="kfr_bistro", methods=["full", "kfr:sigma=2"],
                            as_frame=False)
        cli = cli_json(["predict", "--gpu", "gtx1080,rtx2080ti", "--workload", "kfr_bistro", "-m", "full", "-m",
                        "kfr:sigma=2"])
        self.assertEqual(len(py), len(cli))
        for p, c in zip(py, cli):
            self.assertEqual((p["gpu"], p["method"]), (c["gpu"], c["method"]))
            for k, v in c.items():
                if k.startswith("est_ms_") or k in ("speedup_vs_full", "interval_level"):
                    self.assertTrue(close(p[k], v), (k, p[k], v))
            # One library function (predict_rows) behind both: every key of the CLI's row is in
            # Python's, with the display and resource_ms as columns.
            for k, v in c.get("resource_ms", {}).items():
                self.assertEqual(p["resource_ms_" + k], v)
            self.assertEqual((p["display"], p["width"]), (c["display"]["name"], c["display"]["width"]))
            self.assertEqual(set(c) - {"resource_ms"} - set(p), set())

    @unittest.skipUnless(os.path.exists(CLI), "no fovsim binary beside the module")
    def test_budget_matches_cli(self):
        py = fovsim.budget(gpu="gtx1080", workload="twfr_sponza", methods=["full", "kfr", "twfr"], hz=120,
                           scale={"shading": 2}, as_frame=False)
        cli = cli_json(["budget", "--gpu", "gtx1080", "--workload", "twfr_sponza", "-m", "full", "-m", "kfr", "-m",
                        "twfr", "--hz", "120", "--scale-shading", "2"])
        self.assertEqual(len(py), 3)
        for p, c in zip(py, cli):
            for k in ("est_ms_total", "budget_ms", "headroom_ms", "verdict", "fits", "p_fit", "fit_level",
                      "factor_shading", "factor_geometry", "factor_fixed", "factor_all"):
                self.assertTrue(close(p[k], c[k]), (k, p[k], c[k]))
        # The level: the same decision as `--p`, the same probability.
        py9 = fovsim.budget(gpu="gtx1080", workload="twfr_sponza", methods=["full", "kfr", "twfr"], hz=120,
                            scale={"shading": 2}, p=0.95, as_frame=False)
        cli9 = cli_json(["budget", "--gpu", "gtx1080", "--workload", "twfr_sponza", "-m", "full", "-m", "kfr", "-m",
                         "twfr", "--hz", "120", "--scale-shading", "2", "--p", "0.95"])
        for p, c in zip(py9, cli9):
            self.assertEqual((p["verdict"], p["fits"], p["p_fit"]), (c["verdict"], c["fits"], c["p_fit"]))
            self.assertEqual(p["fits"], p["p_fit"] >= 0.95)
        with self.assertRaises(fovsim.FovsimError) as cm:
            fovsim.budget(gpu="gtx1080", workload="twfr_sponza", methods=["full"], p=0.3)
        self.assertIn("p: value 0.3 is out of range [0.5, 0.99]", str(cm.exception))

    def test_errors(self):
        with self.assertRaises(fovsim.FovsimError) as cm:
            fovsim.predict(gpu="gtx1080", workload="kfr_bistro", methods=["kfr:sigmaa=2"])
        self.assertIn("sigmaa", str(cm.exception))
        with self.assertRaises(fovsim.FovsimError) as cm:
            fovsim.budget(gpu="gtx1080", workload="kfr_bistro", methods=["full"], scale={"shadin": 2})
        self.assertIn("shadin", str(cm.exception))
        with self.assertRaises(ValueError):
            fovsim.predict(gpu="gtx1080", methods=["full"])  # a workload is required
        # The CLI flags' ranges (CostArgRanges through check_cost_args): what `fovsim predict`
        # refuses, Python refuses, with the same message.
        for kw, msg in (({"width": -5}, "width: value -5 is out of range [1, 1048576]"),
                        ({"eyes": 5}, "eyes: value 5 is out of range [1, 2]"),
                        ({"height": float("nan")}, "height: value nan is out of range")):
            with self.assertRaises(fovsim.FovsimError) as cm:
                fovsim.predict(gpu="gtx1080", workload="kfr_bistro", methods=["full"], **kw)
            self.assertIn(msg, str(cm.exception))
        # A profile with "passes": {} used to cost every method 0 ms and fit every budget; an
        # overflowing workload used to make a frame cheaper. Both are errors naming the file.
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(REPO, "models", "gpus", "gtx1080.json")) as f:
                prof = json.load(f)
            prof["passes"] = {}
            empty = os.path.join(d, "empty.json")
            with open(empty, "w") as f:
                json.dump(prof, f)
            with self.assertRaises(fovsim.FovsimError) as cm:
                fovsim.budget(gpu=empty, workload="kfr_bistro", methods=["full"])
            self.assertIn("empty.json: GPU profile 'gtx1080' has no coefficients for pass", str(cm.exception))
            self.assertIn("which method 'full' declares", str(cm.exception))
            big = os.path.join(d, "big.json")
            with open(big, "w") as f:
                json.dump({"name": "big", "lights": 1e300}, f)
            with self.assertRaises(fovsim.FovsimError) as cm:
                fovsim.predict(gpu="gtx1080", workload=big, methods=["full"])
            self.assertIn("big.json: lights: value 1e+300 is out of range [-1, 1e+06]", str(cm.exception))

    def test_dataframe_when_pandas(self):
        try:
            import pandas  # noqa: F401
        except ImportError:
            self.skipTest("no pandas")
        df = fovsim.predict(gpu="gtx1080", workload="kfr_bistro", methods=["full", "kfr"])
        self.assertEqual(list(df["method"]), ["full", "kfr"])
        self.assertIn("est_ms_gbuffer", df.columns)


class RunBased(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.d = cls.tmp.name
        cls.cfg = os.path.join(cls.d, "c.json")
        with open(cls.cfg, "w") as f:
            json.dump(CONFIG, f)
        cls.res = fovsim.run(cls.cfg, out=os.path.join(cls.d, "run"), threads=0)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_tidy_has_parameters_as_columns(self):
        t = fovsim.tidy(self.res["out_dir"], as_frame=False)
        names = t.dtype.names
        for c in ("config_id", "method", "frame", "sigma", "alpha", "metric", "value"):
            self.assertIn(c, names)
        self.assertNotIn("sim_ms", set(t["metric"]))  # wall clock left out
        kfr = t[(t["config_id"] == "kfr") & (t["metric"] == "est_ms_total")]
        self.assertEqual(len(kfr), 2)  # one row per frame
        self.assertTrue((kfr["sigma"] == 1.8).all())
        full = t[t["config_id"] == "full"]
        self.assertTrue(all(math.isnan(v) for v in full["sigma"]))  # full has no sigma
        self.assertIn("psnr", set(full["metric"]))  # inf kept
        run = fovsim.load_run(self.res["out_dir"])
        self.assertIn("sigma", fovsim.parameter_columns(run))

    def test_tidy_dataframe_and_load_as_frame(self):
        try:
            import pandas as pd
        except ImportError:
            self.skipTest("no pandas")
        df = fovsim.tidy(self.res["out_dir"])
        self.assertIsInstance(df, pd.DataFrame)
        kfr = df[(df.config_id == "kfr") & (df.metric == "est_ms_total")]["value"].mean()
        summ = fovsim.load_run(self.res["out_dir"], as_frame=True)["summary"]
        self.assertIsInstance(summ, pd.DataFrame)
        # summary.csv holds 10 significant digits (1e-8 at 14 ms); the frames vary with KFR's
        # TAA jitter, so their mean has more.
        self.assertAlmostEqual(kfr, float(summ[summ.config_id == "kfr"]["est_ms_total"].iloc[0]), places=7)

    def test_plots_from_python(self):
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            self.skipTest("no matplotlib")
        idx = fovsim.make_plots(self.res["out_dir"])
        self.assertTrue(os.path.exists(idx))
        self.assertTrue(os.path.exists(os.path.join(self.res["out_dir"], "plots", "quality_vs_budget.png")))

    def test_predict_from_results(self):
        rows = fovsim.predict(results=self.res["out_dir"], gpu="rtx2080ti", as_frame=False)
        self.assertEqual([r["config_id"] for r in rows], ["full", "kfr"])
        self.assertEqual([r["label"] for r in rows], ["full", "kfr"])
        self.assertEqual(list(rows[0])[0], "label")  # the label first
        self.assertLess(rows[1]["est_ms_total"], rows[0]["est_ms_total"])

    def test_two_configurations_of_one_method_stay_apart(self):
        # Two entries of method "full" under their own labels (as the quickstart's full_tbds and
        # fir): predict(results=...), the CLI and the tidy form keep them apart by label.
        cfg = os.path.join(self.d, "two_full.json")
        with open(cfg, "w") as f:
            json.dump(dict(CONFIG, methods=[{"method": "full", "label": "full_a"},
                                            {"method": "full", "label": "full_b"}]), f)
        res = fovsim.run(cfg, out=os.path.join(self.d, "two_full"), threads=0)
        rows = fovsim.predict(results=res["out_dir"], gpu="rtx2080ti", as_frame=False)
        self.assertEqual([(r["label"], r["method"]) for r in rows], [("full_a", "full"), ("full_b", "full")])
        t = fovsim.tidy(res["out_dir"], as_frame=False)
        self.assertEqual(t.dtype.names[0], "label")
        self.assertEqual(sorted(set(t["label"])), ["full_a", "full_b"])
        cli = cli_json(["predict", "--results", res["out_dir"], "--gpu", "rtx2080ti"])
        self.assertEqual([r["label"] for r in cli], ["full_a", "full_b"])


class AskTellTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.d = cls.tmp.name
        cls.cfg = os.path.join(cls.d, "c.json")
        with open(cls.cfg, "w") as f:
            json.dump(dict(CONFIG, methods=[{"method": "kfr"}]), f)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def space(self):
        return {"methods[kfr].sigma": {"from": 1.2, "to": 3.0, "step": 0.1}}

    def test_ask_tell_with_outside_scores(self):
        # Outside objective: a parabola with its peak at sigma = 2.0; the searcher finds it.
        opt = fovsim.AskTell(self.cfg, space=self.space(), maximize="fpsnr", batch=4, seed=3)
        self.assertEqual(opt.spec["space"][0]["path"], "methods[kfr].sigma")
        for _ in range(12):
            xs = opt.ask()
            if not xs:
                break
            for x in xs:
                self.assertTrue(1.2 - 1e-9 <= x["methods[kfr].sigma"] <= 3.0 + 1e-9)
                opt.tell(x, score=-(x["methods[kfr].sigma"] - 2.0) ** 2)
        self.assertAlmostEqual(opt.best["x"]["methods[kfr].sigma"], 2.0, places=6)
        # Same seed, same asks (deterministic).
        a = fovsim.AskTell(self.cfg, space=self.space(), maximize="fpsnr", batch=4, seed=3).ask()
        b = fovsim.AskTell(self.cfg, space=self.space(), maximize="fpsnr", batch=4, seed=3).ask()
        self.assertEqual(a, b)

    def test_evaluate_and_constraint(self):
        opt = fovsim.AskTell(self.cfg, space=self.space(), maximize="fpsnr",
                             subject_to={"shaded_fraction": {"max": 0.0}}, label="kfr", batch=2,
                             out=os.path.join(self.d, "at"))
        x = opt.ask()[0]
        rows = opt.evaluate(x)
        self.assertEqual(rows[0]["sigma"], x["methods[kfr].sigma"])
        score, viol = opt.tell(x, rows)
        self.assertEqual(score, rows[0]["fpsnr"])
        self.assertAlmostEqual(viol, rows[0]["shaded_fraction"])  # every point violates max 0
        self.assertTrue(os.path.exists(os.path.join(self.d, "at", "eval_0", "summary.csv")))

    def test_score_with_several_constraints(self):
        # subject_to with min and max on several columns, scored like `fovsim search`.
        rows = [{"label": "kfr", "est_ms_total": 5.0, "fvvdp_jod_fl": 9.25, "headroom_ms": -2.0}]
        cons = [{"column": "fvvdp_jod_fl", "min": 9.5, "max": math.inf},
                {"column": "headroom_ms", "min": 0.0, "max": math.inf}]
        self.assertEqual(engine._score(rows, "est_ms_total", "kfr", cons), (5.0, 0.25 + 2.0))
        rows[0]["fvvdp_jod_fl"], rows[0]["headroom_ms"] = 9.6, 1.0
        self.assertEqual(engine._score(rows, "est_ms_total", "kfr", cons), (5.0, 0.0))
        rows[0]["headroom_ms"] = math.nan  # a non-finite value is infinitely violated
        self.assertEqual(engine._score(rows, "est_ms_total", "kfr", cons)[1], math.inf)
        del rows[0]["headroom_ms"]  # a column the summary lacks is an error, as in `fovsim search`
        with self.assertRaises(KeyError):
            engine._score(rows, "est_ms_total", "kfr", cons)
        opt = fovsim.AskTell(self.cfg, space=self.space(), minimize="est_ms_total",
                             subject_to={"fvvdp_jod_fl": {"min": 9.5}, "headroom_ms": {"min": 0}})
        self.assertEqual([c["column"] for c in opt.spec["constraints"]], ["fvvdp_jod_fl", "headroom_ms"])
        self.assertEqual(opt.spec["constraints"][0]["min"], 9.5)
        self.assertEqual(opt.spec["constraints"][0]["max"], math.inf)

    def test_errors(self):
        with self.assertRaises(fovsim.FovsimError) as cm:
            fovsim.AskTell(self.cfg, space={"methods[kfr].sigma": [1, 2]}, maximize="fpsnr")
        self.assertIn("range", str(cm.exception))
        with self.assertRaises(fovsim.FovsimError):
            fovsim.AskTell(self.cfg)  # no sweep.search in the config, no space given
        with self.assertRaises(ValueError):
            fovsim.AskTell(self.cfg, space=self.space())  # no objective
        # An objective no summary can have is refused by the constructor, as by `fovsim search`.
        with self.assertRaises(fovsim.FovsimError) as cm:
            fovsim.AskTell(self.cfg, space=self.space(), maximize="fpsnr_typo", batch=2)
        self.assertIn('sweep.search.maximize: no numeric column "fpsnr_typo"', str(cm.exception))
        # An objective column the summary rows lack is refused, not scored NaN.
        opt = fovsim.AskTell(self.cfg, space=self.space(), maximize="fpsnr", batch=2)
        x = opt.ask()[0]
        with self.assertRaises(KeyError) as cm:
            opt.tell(x, [{"label": "kfr", "psnr": 30.0}])
        self.assertIn("fpsnr", str(cm.exception))

    def test_checked_like_fovsim_search(self):
        # The constructor: unknown parameters, labels and ranges, before any evaluation.
        for space, msg in (({"methods[kfr].sigmaa": {"from": 1.2, "to": 3.0}}, 'unknown parameter "sigmaa"'),
                           ({"methods[kfx].sigma": {"from": 1.2, "to": 3.0}}, 'has label "kfx"'),
                           ({"methods[kfr].sigma": {"from": 0.5, "to": 3.0}}, "sigma")):
            with self.assertRaises(fovsim.FovsimError) as cm:
                fovsim.AskTell(self.cfg, space=space, maximize="fpsnr")
            self.assertIn(msg, str(cm.exception))
        with self.assertRaises(fovsim.FovsimError) as cm:
            fovsim.AskTell(self.cfg, space=self.space(), maximize="fpsnr", label="nope")
        self.assertIn('sweep.search.label: no method entry has label "nope" (labels: kfr)', str(cm.exception))
        # tell: finite scores, violations >= 0, points inside the space (ValueError).
        opt = fovsim.AskTell(self.cfg, space=self.space(), maximize="fpsnr", batch=2)
        x = opt.ask()[0]
        for score, viol, msg in ((math.inf, 0.0, "score inf is not a finite number"),
                                 (math.nan, 0.0, "score nan is not a finite number"),
                                 (1.0, -1.0, "violation -1 is not a number >= 0"),
                                 (1.0, math.nan, "violation nan is not a number >= 0")):
            with self.assertRaises(ValueError) as cm:
                opt.tell(x, score=score, violation=viol)
            self.assertIn(msg, str(cm.exception))
        with self.assertRaises(ValueError) as cm:
            opt.tell({"methods[kfr].sigma": 5.0}, score=1.0)
        self.assertIn("methods[kfr].sigma = 5 is outside the search space [1.2, 3]", str(cm.exception))
        self.assertEqual(opt.history, [])  # nothing refused was recorded
        opt.tell(x, score=1.0, violation=math.inf)  # inf: infinitely violated, accepted
        self.assertEqual(len(opt.history), 1)

    def test_budget_refuses_generic_like_the_cli(self):
        for f in (fovsim.budget, fovsim.predict):
            with self.assertRaises(fovsim.FovsimError) as cm:
                f(gpu="gtx1080", workload="generic", methods=["full"])
            self.assertIn("workload: 'generic' describes no scene", str(cm.exception))


class ExampleScript(unittest.TestCase):
    def test_asktell_example(self):
        with tempfile.TemporaryDirectory() as d:
            cfg = os.path.join(d, "c.json")
            with open(cfg, "w") as f:
                json.dump(CONFIG, f)
            env = dict(os.environ)
            p = subprocess.run(["/usr/bin/python3", os.path.join(REPO, "python", "examples", "asktell_kfr.py"), cfg,
                                "--evaluations", "3", "--out", os.path.join(d, "out")],
                               capture_output=True, text=True, env=env, cwd=REPO)
            self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
            self.assertIn("best sigma", p.stdout)
            self.assertIn("mean fpsnr", p.stdout)
            self.assertIn("gtx1080", p.stdout)
            self.assertTrue(os.path.exists(os.path.join(d, "out", "eval_2", "frames.csv")))


if __name__ == "__main__":
    unittest.main()
