#!/usr/bin/python3
"""Tests of python/fovsim (results loader). Run by ctest (PythonResults); exits 77 (ctest
SKIP_RETURN_CODE) when numpy is not installed."""
import json
import math
import os
import sys
import tempfile
import unittest

try:
    import numpy as np
except ImportError:
    print("numpy not installed (apt-get install python3-numpy): skipped")
    sys.exit(77)

# The checkout's package first, installed (pip install -e python) or not: the tests check this tree.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import fovsim  # noqa: E402

FRAMES = """config_id,method,label,frame,t,sigma,psnr,ssim,est_ms_total
full,full,full,0,0,,inf,1,10.5
full,full,full,1,0.011,,inf,1,10.25
kfr,kfr,kfr,0,0,1.8,31.5,0.91,4.5
kfr,kfr,kfr,1,0.011,1.8,nan,0.93,4.75
"""
SUMMARY = """config_id,method,frames,psnr,psnr_ci95,est_ms_total
full,full,2,inf,nan,10.375
kfr,kfr,2,31.5,nan,4.625
"""


def write(d, name, text):
    with open(os.path.join(d, name), "w") as f:
        f.write(text)


class LoaderTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.d = self.tmp.name
        write(self.d, "frames.csv", FRAMES)
        write(self.d, "summary.csv", SUMMARY)
        write(self.d, "manifest.json", json.dumps({"display": {"refresh_hz": 90}}))

    def tearDown(self):
        self.tmp.cleanup()

    def test_types_and_values(self):
        f = fovsim.load_csv(os.path.join(self.d, "frames.csv"))
        self.assertEqual(f.dtype.names, ("config_id", "method", "label", "frame", "t", "sigma", "psnr", "ssim",
                                         "est_ms_total"))
        self.assertEqual(f.dtype["config_id"].kind, "U")
        self.assertEqual(f.dtype["sigma"].kind, "f")
        self.assertTrue(math.isnan(f["sigma"][0]))  # empty: method has no sigma
        self.assertEqual(f["sigma"][2], 1.8)
        self.assertTrue(math.isinf(f["psnr"][0]))  # exact image
        self.assertTrue(math.isnan(f["psnr"][3]))
        self.assertEqual(list(f["est_ms_total"]), [10.5, 10.25, 4.5, 4.75])

    def test_load_run(self):
        r = fovsim.load_run(self.d)
        self.assertEqual(len(r["frames"]), 4)
        self.assertEqual(len(r["summary"]), 2)
        self.assertIsNone(r["paired"])
        self.assertEqual(r["manifest"]["display"]["refresh_hz"], 90)
        self.assertEqual(list(fovsim.select(r["frames"], method="kfr")["frame"]), [0.0, 1.0])

    def test_missing_folder_is_an_error(self):
        with tempfile.TemporaryDirectory() as e:
            with self.assertRaisesRegex(FileNotFoundError, "no frames.csv or summary.csv"):
                fovsim.load_run(e)

    def test_ragged_row_names_line(self):
        write(self.d, "bad.csv", "a,b\n1,2\n3\n")
        with self.assertRaisesRegex(ValueError, r"bad.csv:3: 1 cells, header has 2"):
            fovsim.load_csv(os.path.join(self.d, "bad.csv"))

    def test_long_format(self):
        f = fovsim.load_csv(os.path.join(self.d, "frames.csv"))
        tidy = fovsim.long_format(f, ["config_id", "frame"], ["psnr", "ssim", "sigma"])
        self.assertEqual(tidy.dtype.names, ("config_id", "frame", "metric", "value"))
        # 4 psnr (one nan dropped -> 3) + 4 ssim + 2 sigma (full has none) = 9 rows
        self.assertEqual(len(tidy), 9)
        kfr_psnr = tidy[(tidy["config_id"] == "kfr") & (tidy["metric"] == "psnr")]
        self.assertEqual(list(kfr_psnr["value"]), [31.5])
        self.assertEqual(len(fovsim.long_format(f, ["config_id"], ["psnr"], drop_nan=False)), 4)
        # default value columns: every numeric column except the ids
        self.assertEqual(set(fovsim.long_format(f, ["config_id", "frame"])["metric"]),
                         {"t", "sigma", "psnr", "ssim", "est_ms_total"})
        with self.assertRaisesRegex(KeyError, "no column 'nope'"):
            fovsim.long_format(f, ["nope"])
        with self.assertRaisesRegex(TypeError, "'method' is text"):
            fovsim.long_format(f, ["config_id"], ["method"])

    def test_to_dataframe(self):
        f = fovsim.load_csv(os.path.join(self.d, "frames.csv"))
        try:
            import pandas  # noqa: F401
        except ImportError:
            with self.assertRaisesRegex(ImportError, "python3-pandas"):
                fovsim.to_dataframe(f)
            return
        df = fovsim.to_dataframe(fovsim.long_format(f, ["config_id", "frame"], ["ssim"]))
        self.assertEqual(list(df.columns), ["config_id", "frame", "metric", "value"])
        self.assertEqual(len(df), 4)

    def test_load_sweep(self):
        write(self.d, "pareto.csv", SUMMARY.splitlines()[0] + "\n" + SUMMARY.splitlines()[2] + "\n")
        os.makedirs(os.path.join(self.d, "runs", "0-abc"))
        cell = os.path.join(self.d, "runs", "0-abc")
        write(cell, "summary.csv", SUMMARY)
        write(cell, "cell.json", "{}")
        os.makedirs(os.path.join(self.d, "runs", "1-def"))  # incomplete cell: no cell.json
        s = fovsim.load_sweep(self.d, cells=True)
        self.assertEqual(len(s["summary"]), 2)
        self.assertEqual(list(s["pareto"]["config_id"]), ["kfr"])
        self.assertEqual(list(s["cells"]), ["0-abc"])
        self.assertIsNone(s["sweep"])


class SameMethodTwoConfigsTest(unittest.TestCase):
    """Two configurations of one method (the quickstart's full_tbds and fir are both method
    `full`): the tidy form carries the label first, and grouping by it keeps them apart."""

    def test_tidy_label_first_and_groups_by_label(self):
        with tempfile.TemporaryDirectory() as d:
            write(d, "frames.csv", "config_id,method,label,frame,t,ssim,est_ms_total\n"
                                   "full_tbds,full,full_tbds,0,0,1,30\n"
                                   "full_tbds,full,full_tbds,1,0.011,1,32\n"
                                   "fir,full,fir,0,0,0.8,12\n"
                                   "fir,full,fir,1,0.011,0.82,14\n")
            write(d, "manifest.json", "{}")
            t = fovsim.tidy(d, as_frame=False)
            self.assertEqual(t.dtype.names[:3], ("label", "config_id", "method"))
            ms = t[t["metric"] == "est_ms_total"]
            by_label = {lab: ms["value"][ms["label"] == lab].mean() for lab in set(ms["label"])}
            self.assertEqual(by_label, {"full_tbds": 31.0, "fir": 13.0})
            self.assertEqual(set(ms["method"]), {"full"})  # by method they would be one row
            try:
                import pandas  # noqa: F401
            except ImportError:
                return
            df = fovsim.tidy(d)
            self.assertEqual(list(df.columns[:2]), ["label", "config_id"])
            g = df[df.metric == "est_ms_total"].groupby(["label"])["value"].mean()
            self.assertEqual(dict(g), {"fir": 13.0, "full_tbds": 31.0})


class TidySweepTest(unittest.TestCase):
    def test_one_row_per_cell_config_metric_with_axes_and_ci(self):
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "summary.csv"), "w") as f:
                f.write("config_id,cell_id,method,label,gpu,methods[kfr].sigma,frames,est_ms_total,"
                        "est_ms_total_ci95,fpsnr,fpsnr_ci95,pareto,sim_ms\n"
                        "full,0-a,full,full,g,1.4,20,10,0.1,inf,nan,1,5\n"
                        "kfr,0-a,kfr,kfr,g,1.4,20,6,0.2,,,0,5\n"
                        "kfr,1-b,kfr,kfr,g,2.4,20,4,0.3,25,0.5,1,5\n")
            with open(os.path.join(d, "sweep_summary.json"), "w") as f:
                json.dump({"axes": ["methods[kfr].sigma"]}, f)
            t = fovsim.tidy_sweep(d, as_frame=False)
            self.assertEqual(set(t["metric"]), {"est_ms_total", "fpsnr"})  # no _ci95, pareto, sim_ms
            self.assertIn("methods[kfr].sigma", t.dtype.names)
            est = t[t["metric"] == "est_ms_total"]
            self.assertEqual(list(est["value"]), [10, 6, 4])
            self.assertEqual(list(est["ci95"]), [0.1, 0.2, 0.3])
            fp = t[t["metric"] == "fpsnr"]  # the kfr row of cell 0-a has no fpsnr: no row
            self.assertEqual(list(fp["cell_id"]), ["0-a", "1-b"])
            self.assertTrue(math.isinf(fp["value"][0]))
            self.assertTrue(math.isnan(fp["ci95"][0]))
            self.assertEqual(fp["ci95"][1], 0.5)
            self.assertEqual(fp["methods[kfr].sigma"][1], 2.4)
            self.assertEqual(fp["lo"][1], 24.5)  # value -+ ci95
            self.assertEqual(fp["hi"][1], 25.5)
            # The sweep's paired.csv (within- and across-cell differences) comes with load_sweep.
            with open(os.path.join(d, "paired.csv"), "w") as f:
                f.write("kind,cell_a_id,cell_b_id,config_a,config_b,gpu,metric,axis,value_a,value_b,cell_a,"
                        "cell_b,frames,mean_a,mean_b,diff,diff_ci95,diff_lo,diff_hi,differs\n"
                        "across,0-a,1-b,kfr,kfr,g,fpsnr,latency.tracker_ms,0,50,0,1,24,25,24,1,0.5,0.5,1.5,1\n")
            p = fovsim.load_sweep(d)["paired"]
            self.assertEqual(list(p["kind"]), ["across"])
            self.assertEqual(p["diff_lo"][0], 0.5)


if __name__ == "__main__":
    unittest.main()
