#!/usr/bin/python3
"""Tests of fovsim's compiled module through python/fovsim (run, sweep, Evaluator). Run by
ctest (PythonEngine) with FOVSIM_PYTHON_EXT set to <build>/python; exits 77 (skipped) when
numpy or the module is missing. Tiny configs (5% resolution, 2-3 frames): seconds."""
import json
import math
import os
import sys
import tempfile
import unittest

# The checkout's package first, installed (pip install -e python) or not: the tests check this tree.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
try:
    import fovsim  # noqa: E402  (imports numpy)
    from fovsim import engine  # noqa: E402

    engine._module()
except ImportError as e:
    print(f"skipped: {e}")
    sys.exit(77)

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CONFIG = {
    "name": "py_engine_test",
    "display": fovsim.DEFAULT_DISPLAY,
    "render": {"scale": 0.05},
    "scene": {"type": "atrium", "complexity": 1},
    "trace": {"file": os.path.join(REPO, "tests/golden/golden_trace.csv")},
    "frames": {"count": 2},
    "methods": [{"method": "full"}, {"method": "kfr", "sigma": 1.8}],
    "outputs": {"print_summary": False},
}


def without_wall_clock(rows):
    return [{k: v for k, v in r.items() if k not in ("ref_ms", "sim_ms")} for r in rows]


def same(a, b):
    """Row dicts equal, nan == nan."""
    if a.keys() != b.keys():
        return False
    for k in a:
        x, y = a[k], b[k]
        if isinstance(x, float) and isinstance(y, float) and math.isnan(x) and math.isnan(y):
            continue
        if x != y:
            return False
    return True


class EngineTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.d = cls.tmp.name
        cls.cfg = os.path.join(cls.d, "c.json")
        with open(cls.cfg, "w") as f:
            json.dump(CONFIG, f)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_run_matches_files_and_is_thread_independent(self):
        r1 = fovsim.run(self.cfg, out=os.path.join(self.d, "r1"), threads=1)
        r2 = fovsim.run(self.cfg, out=os.path.join(self.d, "r2"), threads=2)
        self.assertEqual([r["config_id"] for r in r1["summary"]], ["full", "kfr"])
        self.assertEqual(r1["frame_rows"], 4)  # 2 frames x 2 methods
        a, b = without_wall_clock(r1["summary"]), without_wall_clock(r2["summary"])
        for x, y in zip(a, b):
            self.assertTrue(same(x, y), (x, y))
        # The returned summary is the one written to summary.csv.
        loaded = fovsim.load_run(r1["out_dir"])
        self.assertEqual(len(loaded["frames"]), 4)
        kfr = fovsim.select(loaded["summary"], config_id="kfr")
        self.assertAlmostEqual(kfr["est_ms_total"][0], r1["summary"][1]["est_ms_total"], places=6)
        self.assertLess(r1["summary"][1]["shaded_fraction"], 1.0)  # kfr shades fewer samples than full

    def test_overrides_dict_and_error(self):
        r = fovsim.run(self.cfg, overrides={"methods[1].sigma": 2.4}, out=os.path.join(self.d, "ov"))
        self.assertEqual(r["summary"][1]["sigma"], 2.4)
        with self.assertRaises(fovsim.FovsimError) as cm:
            fovsim.run(self.cfg, overrides={"render.scale": 7}, out=os.path.join(self.d, "bad"))
        self.assertIn("render.scale", str(cm.exception))

    def test_run_options_are_the_clis(self):
        # The CLI's run options (RunControl): --target's manifest record, --watchdog's range.
        r = fovsim.run(self.cfg, out=os.path.join(self.d, "tgt"), targets=["est_ms_total:50%"], watchdog=30)
        with open(os.path.join(r["out_dir"], "manifest.json")) as f:
            target = json.load(f)["target"]
        self.assertEqual(target["targets"], ["est_ms_total:50%"])
        self.assertEqual(target["frames_used"], 2)  # fewer frames than a unit: all of them
        with self.assertRaises(fovsim.FovsimError) as cm:
            fovsim.run(self.cfg, out=os.path.join(self.d, "wd"), watchdog=-1)
        self.assertIn("watchdog: value -1 is out of range [1, 86400] s (0: off)", str(cm.exception))
        with self.assertRaises(fovsim.FovsimError) as cm:
            fovsim.run(self.cfg, out=os.path.join(self.d, "bt"), targets=["nope"])
        self.assertIn("--target nope", str(cm.exception))

    def test_evaluator_hook(self):
        ev = fovsim.Evaluator(self.cfg, overrides={"methods": [{"method": "kfr"}]}, out=os.path.join(self.d, "ev"))
        res = ev.evaluate([{"methods[0].sigma": 1.5}, {"methods[0].sigma": 2.5}])
        self.assertEqual(ev.evaluations, 2)
        self.assertEqual([r[0]["sigma"] for r in res], [1.5, 2.5])
        # A larger sigma compresses the periphery more: fewer shaded samples (KFR, Meng et al. 2018).
        self.assertGreater(res[0][0]["shaded_fraction"], res[1][0]["shaded_fraction"])
        # The run options are run()'s, checked the same way (RunControl).
        with self.assertRaises(fovsim.FovsimError) as cm:
            fovsim.Evaluator(self.cfg, out=os.path.join(self.d, "ev2"), watchdog=-1)
        self.assertIn("watchdog: value -1 is out of range [1, 86400] s (0: off)", str(cm.exception))
        with self.assertRaises(fovsim.FovsimError) as cm:
            fovsim.Evaluator(self.cfg, out=os.path.join(self.d, "ev3"), targets=["nope"])
        self.assertIn("--target nope", str(cm.exception))

    def test_sweep(self):
        cfg = dict(CONFIG, name="py_sweep_test", methods=[{"method": "kfr"}],
                   sweep={"axes": [{"grid": {"methods[kfr].sigma": [1.4, 2.6]}}],
                          "objectives": [{"minimize": "shaded_fraction"}, {"maximize": "fpsnr"}]})
        path = os.path.join(self.d, "s.json")
        with open(path, "w") as f:
            json.dump(cfg, f)
        rep = fovsim.sweep(path, out=os.path.join(self.d, "sw"))
        self.assertTrue(rep["complete"])
        self.assertEqual(rep["cells_total"], 2)
        s = fovsim.load_sweep(rep["out_dir"], cells=True)
        self.assertEqual(len(s["summary"]), 2)
        self.assertEqual(len(s["cells"]), 2)
        again = fovsim.sweep(path, out=os.path.join(self.d, "sw"))
        self.assertEqual(again["cells_done_before"], 2)  # resumed, nothing recomputed
        self.assertEqual(again["cells_other_build"], 0)
        # A cell another build of fovsim computed is computed again, as `fovsim sweep` does.
        runs = os.path.join(rep["out_dir"], "runs")
        cell = os.path.join(runs, sorted(os.listdir(runs))[0], "cell.json")
        with open(cell) as f:
            text = f.read()
        self.assertIn('"git_commit": "', text)
        with open(cell, "w") as f:
            f.write(text.replace('"git_commit": "', '"git_commit": "older-', 1))
        third = fovsim.sweep(path, out=os.path.join(self.d, "sw"))
        self.assertEqual(third["cells_other_build"], 1)
        self.assertEqual(third["cells_done_before"], 1)
        self.assertEqual(third["cells_run"], 1)

    def test_example_script(self):
        sys.path.insert(0, os.path.join(REPO, "python", "examples"))
        import analyse_run

        r = fovsim.run(self.cfg, out=os.path.join(self.d, "ex"))
        means, metrics = analyse_run.per_method_means(r["out_dir"])
        self.assertIn("est_ms_total", metrics)
        kfr_row = [x for x in r["summary"] if x["config_id"] == "kfr"][0]
        self.assertAlmostEqual(means[("kfr", "est_ms_total")], kfr_row["est_ms_total"], places=6)
        best = analyse_run.optimise_sigma(self.cfg, os.path.join(self.d, "opt"), budget_fraction=1.0, rounds=1)
        self.assertIsNotNone(best)
        self.assertTrue(any(abs(best[0] - v) < 1e-9 for v in (1.2, 1.8, 2.4, 3.0)), best[0])


if __name__ == "__main__":
    unittest.main()
