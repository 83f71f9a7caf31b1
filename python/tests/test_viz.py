#!/usr/bin/python3
"""Tests of viz/ plot fixes (issue 18) on small synthetic result folders. Run by ctest
(PythonViz); exits 77 (skipped) when matplotlib or numpy is missing."""
import math
import os
import sys
import tempfile
import unittest

try:
    import matplotlib  # noqa: F401
    import numpy as np  # noqa: F401
except ImportError as e:
    print(f"skipped: {e}")
    sys.exit(77)

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "viz"))
import common  # noqa: E402
import plot_run  # noqa: E402
import plot_sweep  # noqa: E402

FRAMES = ["config_id,method,label,frame,t,gaze_x,gaze_y,psnr,fpsnr,ssim,est_ms_total"]
for f in range(4):
    FRAMES.append(f"full,full,full,{f},{f / 90},100,80,inf,inf,1,10")
    FRAMES.append(f"kfr,kfr,kfr,{f},{f / 90},100,80,{30 + f},{35 + f},0.9,4")
    FRAMES.append(f"rmfr,rmfr,rmfr,{f},{f / 90},100,80,{28 + f},{33 + f},0.88,5")
SUMMARY = """config_id,method,frames,est_ms_total,est_ms_total_ci95,psnr,fpsnr,ssim,shaded_fraction
full,full,4,10,nan,inf,inf,1,1
kfr,kfr,4,4,0.1,31.5,36.5,0.9,0.3
rmfr,rmfr,4,5,0.2,29.5,34.5,0.88,0.4
"""


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


class RunPlots(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.d = self.tmp.name
        write(os.path.join(self.d, "frames.csv"), "\n".join(FRAMES) + "\n")
        write(os.path.join(self.d, "summary.csv"), SUMMARY)

    def tearDown(self):
        self.tmp.cleanup()

    def test_quality_timeline_colours_match_across_panels(self):
        run = plot_run.Run(self.d)
        captured = {}
        orig = common.save

        def grab(fig, path):
            captured["fig"] = fig
            return orig(fig, path)

        common.save = grab
        try:
            plot_run.plot_quality_timeline(run, self.d)
        finally:
            common.save = orig
        fig = captured["fig"]
        colours = {}
        for ax in fig.axes:
            for line in ax.get_lines():
                colours.setdefault(line.get_label(), set()).add(matplotlib.colors.to_hex(line.get_color()))
        # `full` (psnr inf) is absent from the dB panels but present in ssim; every config keeps
        # one colour everywhere, and colours differ between configs.
        self.assertEqual(set(colours), {"full", "kfr", "rmfr"})
        self.assertTrue(all(len(c) == 1 for c in colours.values()), colours)
        self.assertEqual(len({next(iter(c)) for c in colours.values()}), 3)
        self.assertIn("[dB]", fig.axes[0].get_ylabel())
        legend_labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
        self.assertEqual(legend_labels, ["full", "kfr", "rmfr"])

    def test_index_has_summary_table_and_images(self):
        import matplotlib.pyplot as plt
        os.makedirs(os.path.join(self.d, "images", "frame_0"))
        plt.imsave(os.path.join(self.d, "images", "frame_0", "reference.png"), np.ones((40, 40, 3)))
        plt.imsave(os.path.join(self.d, "images", "frame_0", "kfr.png"), np.zeros((40, 40, 3)))
        self.assertEqual(plot_run.main([self.d]), 0)
        with open(os.path.join(self.d, "plots", "index.html")) as f:
            html = f.read()
        self.assertIn("<table>", html)
        self.assertIn("4 ± 0.1", html)  # kfr est_ms_total with its 95% half-width
        self.assertIn("../images/frame_0/kfr.png", html)
        self.assertTrue(os.path.exists(os.path.join(self.d, "plots", "quality_timeline.png")))
        self.assertTrue(os.path.exists(os.path.join(self.d, "plots", "strip_0.png")))  # reference | kfr
        self.assertNotIn("failed", html)

    def test_pass_columns_and_stacked_plot(self):
        write(os.path.join(self.d, "summary.csv"),
              "config_id,method,est_ms_total,est_ms_total_ci95,est_ms_total_lo,est_ms_total_p95,"
              "est_ms_gbuffer,est_ms_gbuffer_ci95,est_ms_lighting\n"
              "kfr,kfr,4,0.1,3.5,4.5,1.5,0.01,2.5\n")
        run = plot_run.Run(self.d)
        self.assertEqual(plot_run.pass_columns(run), ["est_ms_gbuffer", "est_ms_lighting"])
        self.assertEqual(plot_run.plot_passes(run, self.d), "passes.png")
        self.assertTrue(os.path.exists(os.path.join(self.d, "passes.png")))


class Geometry(unittest.TestCase):
    def test_clamp_box_stays_inside(self):
        for cx, cy in [(-50, -50), (0, 0), (100, 60), (199, 119), (500, 500)]:
            x0, y0, x1, y1 = common.clamp_box(cx, cy, 30, 200, 120)
            self.assertGreaterEqual(x0, 0)
            self.assertGreaterEqual(y0, 0)
            self.assertLessEqual(x1, 200)
            self.assertLessEqual(y1, 120)
            self.assertEqual(x1 - x0, 60)
            self.assertEqual(y1 - y0, 60)

    def test_periphery_inset_away_from_gaze(self):
        fov, per = plot_sweep.strip_geometry(200, 120, 190, 60)  # gaze at the right edge
        self.assertLess(per[0], 100)  # periphery box on the left half
        fov, per = plot_sweep.strip_geometry(200, 120, 10, 60)
        self.assertGreater(per[2], 100)


class FidelityPlot(unittest.TestCase):
    def test_log_log_plot_of_a_ladder(self):
        import plot_fidelity

        head = ("rung,config_id,method,output,rung_index,wall_s,wall_ratio,cpu_s,cpu_ratio,"
                "frames,top,value,err,err_rel,err_ci95,err_ci95_paired,ranking_same,"
                "ranking_resolved_swaps")
        lines = [head]
        for i, (rung, wall, e) in enumerate([("analytic", 0.1, 0.3), ("scale=0.25", 10, 0.02),
                                              ("scale=0.5", 40, 0.0)]):
            for o in ["est_ms_total", "psnr"]:
                ci = "nan" if rung == "analytic" else "0.1"
                lines.append(f"{rung},kfr,kfr,{o},{i},{wall},{wall / 40},{wall},{wall / 40},"
                             f"90,10,{10 + e},{e},{e / 10},{ci},nan,1,0")
        with tempfile.TemporaryDirectory() as d:
            write(os.path.join(d, "fidelity.csv"), "\n".join(lines) + "\n")
            sys.argv = ["plot_fidelity.py", d]
            self.assertEqual(plot_fidelity.main(), 0)
            self.assertTrue(os.path.exists(os.path.join(d, "plots", "fidelity.png")))
            sys.argv = ["plot_fidelity.py", os.path.join(d, "missing")]
            self.assertEqual(plot_fidelity.main(), 2)


if __name__ == "__main__":
    unittest.main()
