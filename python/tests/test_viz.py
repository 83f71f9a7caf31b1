#!/usr/bin/python3
"""Tests of viz/ plot fixes on small synthetic result folders. Run by ctest
(PythonViz); exits 77 (skipped) when matplotlib or numpy is missing."""
import math
import os
import shutil
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
import make_video  # noqa: E402
import plot_run  # noqa: E402
import plot_sweep  # noqa: E402

FRAMES = ["config_id,method,label,frame,t,gaze_x,gaze_y,psnr,fpsnr,ssim,est_ms_total"]
for f in range(4):
    FRAMES.append(f"full,full,full,{f},{f / 90},100,80,inf,inf,1,10")
    FRAMES.append(f"kfr,kfr,kfr,{f},{f / 90},100,80,{30 + f},{35 + f},0.9,4")
    FRAMES.append(f"rmfr,rmfr,rmfr,{f},{f / 90},100,80,{28 + f},{33 + f},0.88,5")
# budget_ms / fit_level / fit_threshold_ms: the budget decision (docs/cost_model.md "Budget
# decisions"), so every figure is also laid out with the p_fit line and shifted budget axis.
SUMMARY = """config_id,method,frames,est_ms_total,est_ms_total_ci95,psnr,fpsnr,ssim,shaded_fraction,budget_ms,fit_level,fit_threshold_ms
full,full,4,10,nan,inf,inf,1,1,11.11,0.8,9.24
kfr,kfr,4,4,0.1,31.5,36.5,0.9,0.3,11.11,0.8,9.24
rmfr,rmfr,4,5,0.2,29.5,34.5,0.88,0.4,11.11,0.8,9.24
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
        legends = [a.get_legend() for a in fig.axes if a.get_legend() is not None]
        self.assertEqual(len(legends), 1)  # one legend, in its own row below the panels
        legend_labels = [t.get_text() for t in legends[0].get_texts()]
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


SWEEP_SUMMARY = """config_id,cell_id,label,method,gpu,methods[kfr].sigma,sigma,frames,est_ms_total,est_ms_total_ci95,fpsnr,fpsnr_ci95,ssim,shaded_fraction,rmse_ecc_0_5,rmse_ecc_5_10,pareto,extra_col_a,extra_col_b,extra_col_c
0-a:full,0-a,full,full,gtx1080,,,2,10,0.1,inf,nan,1,1,0,0,0,1,2,3
0-a:kfr,0-a,kfr,kfr,gtx1080,1.2,1.2,2,6,0.1,30,0.5,0.9,0.5,0.01,0.02,1,1,2,3
1-b:full,1-b,full,full,gtx1080,,,2,10,0.1,inf,nan,1,1,0,0,0,1,2,3
1-b:kfr,1-b,kfr,kfr,gtx1080,2.4,2.4,2,4,0.1,25,0.5,0.8,0.25,0.01,0.04,1,1,2,3
"""


def make_sweep(d):
    write(os.path.join(d, "summary.csv"), SWEEP_SUMMARY)
    lines = SWEEP_SUMMARY.strip().split("\n")
    write(os.path.join(d, "pareto.csv"), "\n".join([lines[0]] + [x for x in lines[1:] if ",1,1,2,3" in x]) + "\n")
    write(os.path.join(d, "sweep_summary.json"),
          '{"name": "tiny", "cells": 2, "axes": ["methods[kfr].sigma"], '
          '"objectives": [{"minimize": "est_ms_total"}, {"maximize": "fpsnr"}]}')


class Palette(unittest.TestCase):
    def test_every_registered_method_has_its_own_colour(self):
        names = common.method_names()  # `fovsim info --json`, the C++ registration list
        if not names:
            self.skipTest("no fovsim binary (build/fovsim or FOVSIM_BINARY)")
        colours = [common.method_color(n) for n in names]
        self.assertEqual(len(set(colours)), len(names), dict(zip(names, colours)))

    def test_one_colour_per_method_everywhere(self):
        self.assertEqual(common.method_color("kfr"), common.method_color("kfr"))
        self.assertNotEqual(common.method_color("kfr"), common.method_color("rmfr"))
        self.assertEqual(common.method_color("kfr@gtx1080"), common.method_color("kfr"))
        st = common.variant_styles([("kfr_a", "kfr"), ("kfr_b", "kfr"), ("rmfr", "rmfr")])
        self.assertEqual(st["kfr_a"][0], st["kfr_b"][0])  # same method, same colour
        self.assertNotEqual(st["kfr_a"][1], st["kfr_b"][1])  # told apart by line style
        with tempfile.TemporaryDirectory() as d:
            write(os.path.join(d, "frames.csv"), "\n".join(FRAMES) + "\n")
            run = plot_run.Run(d)
            self.assertEqual(run.color("kfr"), common.method_color("kfr"))
            make_sweep(d)
            sw = plot_sweep.Sweep(d)
            self.assertEqual(sw.color("kfr"), common.method_color("kfr"))

    def test_units_on_labels(self):
        self.assertIn("[dB]", common.metric_label("fpsnr"))
        self.assertIn("[ms]", common.metric_label("est_ms_total"))
        self.assertIn("[ms]", common.metric_label("est_ms_gbuffer"))
        self.assertIn("5–10°", common.metric_label("rmse_ecc_5_10"))


class FitRule(unittest.TestCase):
    """The plots' budget line is the budget decision: summary.csv's fit_threshold_ms / budget_ms
    (the estimate below which p_fit reaches fit_level) moves each configuration to the budget it
    needs, and the timeline draws that threshold."""

    def test_rule_and_shifted_budget_axis(self):
        rows = [{"budget_ms": "11.11", "fit_level": "0.8", "fit_threshold_ms": "8.888"}]
        lv, f = common.fit_rule(rows)
        self.assertEqual(lv, 0.8)
        self.assertAlmostEqual(f, 0.8, places=9)
        self.assertIsNone(common.fit_rule([{"budget_ms": "11.11", "fit_level": "0.8", "fit_threshold_ms": "11.11"}]))
        self.assertIsNone(common.fit_rule([{"budget_ms": "11.11"}]))  # results from before the columns
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots()
        common.draw_quality_vs_budget(ax, [("kfr", "kfr", 4.0, 30.0), ("kfr", "kfr b", 8.0, 33.0)], "fpsnr",
                                      11.11, (0.8, 0.8))
        xs = sorted(set(round(x, 6) for line in ax.get_lines() for x in line.get_xdata()
                        if line.get_label() == "kfr"))
        self.assertEqual(xs[:2], [5.0, 10.0])  # 4 / 0.8 and 8 / 0.8: the budgets they need
        self.assertIn("p_fit ≥ 0.8", ax.get_xlabel())
        plt.close(fig)

    def test_timeline_draws_the_threshold(self):
        with tempfile.TemporaryDirectory() as d:
            write(os.path.join(d, "frames.csv"), "\n".join(FRAMES) + "\n")
            write(os.path.join(d, "summary.csv"), SUMMARY)
            seen = []
            import matplotlib.axes
            orig = matplotlib.axes.Axes.axhline

            def grab(self_, y=0, *a, **k):
                seen.append((round(y, 3), k.get("label")))
                return orig(self_, y, *a, **k)
            matplotlib.axes.Axes.axhline = grab
            try:
                plot_run.plot_timeline(plot_run.Run(d), d)
            finally:
                matplotlib.axes.Axes.axhline = orig
        self.assertIn((9.24, "fits at p_fit ≥ 0.8: ≤ 9.24 ms"), seen)


class SameMethodConfigs(unittest.TestCase):
    """full_tbds and fir are both method `full`: quality_vs_budget draws them as two lines under
    their own labels, never FIR's line under the legend "full"."""

    def test_quality_vs_budget_keys_by_configuration(self):
        rows = ["config_id,method,label,frame,t,gaze_x,gaze_y,psnr,fpsnr,ssim,est_ms_total"]
        for f in range(4):
            rows.append(f"full_tbds,full,full_tbds,{f},{f / 90},100,80,inf,inf,1,30")
            rows.append(f"fir,full,fir,{f},{f / 90},100,80,{30 + f},{35 + f},0.95,12")
            rows.append(f"kfr,kfr,kfr,{f},{f / 90},100,80,{28 + f},{33 + f},0.9,5")
        summary = ("config_id,method,label,frames,est_ms_total,psnr,fpsnr,ssim\n"
                   "full_tbds,full,full_tbds,4,30,inf,inf,1\nfir,full,fir,4,12,31.5,36.5,0.95\n"
                   "kfr,kfr,kfr,4,5,29.5,34.5,0.9\n")
        seen = []
        orig = common.draw_quality_vs_budget

        def grab(ax, entries, metric, budget=None, rule=None):
            seen.extend(e[0] for e in entries)
            return orig(ax, entries, metric, budget, rule)
        with tempfile.TemporaryDirectory() as d:
            write(os.path.join(d, "frames.csv"), "\n".join(rows) + "\n")
            write(os.path.join(d, "summary.csv"), summary)
            common.draw_quality_vs_budget = grab
            try:
                plot_run.plot_quality_vs_budget(plot_run.Run(d), d)
            finally:
                common.draw_quality_vs_budget = orig
        self.assertEqual(set(seen), {"full_tbds", "fir", "kfr"})


class RunFiles(unittest.TestCase):
    """plot_run.py on a tiny run folder produces every plot its columns allow."""

    def test_all_plots(self):
        import matplotlib.pyplot as plt
        with tempfile.TemporaryDirectory() as d:
            write(os.path.join(d, "frames.csv"), "\n".join(FRAMES) + "\n")
            write(os.path.join(d, "summary.csv"), SUMMARY)
            write(os.path.join(d, "manifest.json"),
                  '{"display": {"width": 200, "height": 160, "refresh_hz": 90}}')
            for f in (0, 2):
                fd = os.path.join(d, "images", f"frame_{f}")
                os.makedirs(fd)
                for name, v in (("reference", 1.0), ("kfr", 0.5), ("rmfr", 0.2)):
                    plt.imsave(os.path.join(fd, name + ".png"), np.full((40, 50, 3), v))
            self.assertEqual(plot_run.main([d]), 0)
            out = os.path.join(d, "plots")
            for f in ("timeline.png", "quality_vs_cost.png", "quality_vs_budget.png", "quality_timeline.png",
                      "shaded_fraction.png", "gaze.png", "strip_0.png", "strip_2.png", "index.html"):
                self.assertTrue(os.path.exists(os.path.join(out, f)), f)
            with open(os.path.join(out, "index.html")) as fh:
                page = fh.read()
            self.assertIn("quality_vs_budget.png", page)
            if shutil.which("ffmpeg"):
                self.assertTrue(os.path.exists(os.path.join(out, "run.mp4")))
                self.assertIn("<video", page)
            else:
                self.assertIn("ffmpeg not found", page)

    def test_eccentricity_bands_with_foveation_loss_columns(self):
        # Band columns <fam><a>_<b> sit beside their _ci95 and _fl (foveation loss) forms;
        # only the bands themselves are plotted (a _fl column once broke the band parsing).
        with tempfile.TemporaryDirectory() as d:
            cols = ["rmse_ecc_0_5", "rmse_ecc_0_5_ci95", "rmse_ecc_0_5_fl", "rmse_ecc_5_12p5",
                    "rmse_ecc_5_12p5_ci95", "rmse_ecc_5_12p5_fl"]
            rows = [f"{c},{c},4," + ",".join(["0.1"] * len(cols)) for c in ("kfr", "rmfr")]
            write(os.path.join(d, "frames.csv"), "\n".join(FRAMES) + "\n")
            write(os.path.join(d, "summary.csv"),
                  "config_id,method,frames," + ",".join(cols) + "\n" + "\n".join(rows) + "\n")
            write(os.path.join(d, "manifest.json"), "{}")
            self.assertEqual(plot_run.plot_eccentricity(plot_run.Run(d), d), "eccentricity.png")
            self.assertTrue(os.path.exists(os.path.join(d, "eccentricity.png")))

    def test_pdf_dpi_and_configs(self):
        """--format pdf writes every figure as PDF next to its PNG; --configs keeps only the named
        configurations (the strip then shows only them); an unknown name is an error listing them."""
        import matplotlib.pyplot as plt
        with tempfile.TemporaryDirectory() as d:
            write(os.path.join(d, "frames.csv"), "\n".join(FRAMES) + "\n")
            write(os.path.join(d, "summary.csv"), SUMMARY)
            write(os.path.join(d, "manifest.json"),
                  '{"display": {"width": 200, "height": 160, "refresh_hz": 90}}')
            fd = os.path.join(d, "images", "frame_0")
            os.makedirs(fd)
            for name, v in (("reference", 1.0), ("kfr", 0.5), ("rmfr", 0.2)):
                plt.imsave(os.path.join(fd, name + ".png"), np.full((40, 50, 3), v))
            try:
                self.assertEqual(plot_run.main([d, "--format", "pdf", "--dpi", "150", "--configs", "kfr"]), 0)
            finally:
                common.OUTPUT.update({"format": "png", "dpi": 110})
            out = os.path.join(d, "plots")
            pngs = [f for f in os.listdir(out) if f.endswith(".png")]
            self.assertTrue(pngs)
            for f in pngs:
                self.assertTrue(os.path.exists(os.path.join(out, f[:-4] + ".pdf")), f)
            with self.assertRaises(SystemExit) as e:
                plot_run.main([d, "--configs", "nope"])
            self.assertIn("available:", str(e.exception.code))

    def test_video_skipped_without_ffmpeg_or_frames(self):
        with tempfile.TemporaryDirectory() as d:
            write(os.path.join(d, "frames.csv"), "\n".join(FRAMES) + "\n")
            orig = make_video.shutil.which
            make_video.shutil.which = lambda name: None
            try:
                with self.assertRaisesRegex(make_video.NoVideo, "ffmpeg not found"):
                    make_video.make_video(d, d)
            finally:
                make_video.shutil.which = orig
            if shutil.which("ffmpeg"):
                with self.assertRaisesRegex(make_video.NoVideo, "0 saved frame"):
                    make_video.make_video(d, d)


class SweepFiles(unittest.TestCase):
    def test_pareto_budget_and_index(self):
        with tempfile.TemporaryDirectory() as d:
            make_sweep(d)
            self.assertEqual(plot_sweep.main([d]), 0)
            out = os.path.join(d, "plots")
            for f in ("pareto.png", "quality_vs_budget.png", "eccentricity_profiles.png", "index.html"):
                self.assertTrue(os.path.exists(os.path.join(out, f)), f)
            sw = plot_sweep.Sweep(d)
            rows, dups = sw.distinct()
            self.assertEqual(dups, 1)  # the unswept `full` of cell 1-b is not repeated
            self.assertEqual(sw.params_text(rows[1]), "sigma=1.2")
            with open(os.path.join(out, "index.html")) as fh:
                page = fh.read()
            pareto_part = page[page.index("<h2>pareto.csv</h2>"):]
            for col in ("est_ms_total", "fpsnr", "extra_col_c"):  # every column of the Pareto table
                self.assertIn(f"<th>{col}</th>", pareto_part[:pareto_part.index("</table>")])


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

    def test_periphery_inset_at_the_detail(self):
        ref = np.zeros((120, 200, 3))
        ref[90:120, 0:40] = np.indices((30, 40)).sum(axis=0)[..., None] % 2  # checkerboard bottom-left
        fov, per = common.strip_geometry(200, 120, 100, 60, ref)
        self.assertLess(per[0], 40)
        self.assertGreater(per[3], 90)

    def test_strip_with_gaze_off_screen_stays_on_image(self):
        im = np.full((60, 80, 3), 0.5)
        fig = common.draw_strip([("reference", im, None), ("kfr", im, None)], -30, 200, "t", {"kfr": "#1f77b4"})
        ax = fig.axes[0]
        self.assertEqual(ax.get_xlim(), (-0.5, 79.5))
        self.assertEqual(ax.get_ylim(), (59.5, -0.5))
        self.assertIn("off the screen", fig._suptitle.get_text())
        self.assertEqual(fig.axes[1].title.get_color(), "#1f77b4")


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
            self.assertEqual(plot_fidelity.main([d, "--format", "pdf"]), 0)
            self.assertTrue(os.path.exists(os.path.join(d, "plots", "fidelity.png")))
            self.assertTrue(os.path.exists(os.path.join(d, "plots", "fidelity.pdf")))
            common.OUTPUT.update({"format": "png", "dpi": 110})
            self.assertEqual(plot_fidelity.main([os.path.join(d, "missing")]), 2)


LAT_CELLS = [("0000-t0", 0), ("0001-t20", 20), ("0002-t50", 50), ("0003-t80", 80)]


def make_latency_sweep(d):
    """A latency sweep's summary.csv and paired.csv: kfr's rmse_fovea_fl rises by +0.0037 at
    50 ms with a paired interval of +-0.010 (not a degradation) and by +0.02 +- 0.004 at 80 ms
    (one); rmfr's paired.csv rows are missing (undecided)."""
    head = "config_id,cell_id,label,method,gpu,latency.tracker_ms,latency_ms,frames,rmse_fovea_fl,rmse_fovea_fl_ci95"
    lines = [head]
    for cell, ms in LAT_CELLS:
        i = cell[:4]
        lines.append(f"{i}/kfr,{cell},kfr,kfr,gtx1080,{ms},{ms},40,{0.05 + {0: 0, 20: 0.001, 50: 0.0037, 80: 0.02}[ms]},0.02")
        lines.append(f"{i}/rmfr,{cell},rmfr,rmfr,gtx1080,{ms},{ms},40,0.04,0.02")
    write(os.path.join(d, "summary.csv"), "\n".join(lines) + "\n")
    p = ["kind,cell_a_id,cell_b_id,config_a,config_b,gpu,metric,axis,value_a,value_b,cell_a,cell_b,frames,"
         "mean_a,mean_b,diff,diff_ci95,diff_lo,diff_hi,differs"]
    # cell a is the low latency one for 20 and 50 ms, the high one for 80 ms (either order is read)
    for idx, cell, ms, diff, ci in ((1, "0001-t20", 20, -0.001, 0.002), (2, "0002-t50", 50, -0.0037, 0.010)):
        p.append(f"across,0000-t0,{cell},kfr,kfr,gtx1080,rmse_fovea_fl,latency.tracker_ms,0,{ms},0,{idx},"
                 f"40,0.05,{0.05 - diff},{diff},{ci},{diff - ci},{diff + ci},{int(abs(diff) > ci)}")
    p.append("across,0003-t80,0000-t0,kfr,kfr,gtx1080,rmse_fovea_fl,latency.tracker_ms,80,0,3,0,40,0.07,0.05,"
             "0.02,0.004,0.016,0.024,1")
    write(os.path.join(d, "paired.csv"), "\n".join(p) + "\n")
    write(os.path.join(d, "sweep_summary.json"), '{"name": "lat", "axes": ["latency.tracker_ms"]}')


class LatencyDecision(unittest.TestCase):
    """viz/latency.py decides a degradation from the paired interval, not the relative change."""

    def test_degradation_needs_the_paired_interval(self):
        import latency
        with tempfile.TemporaryDirectory() as d:
            make_latency_sweep(d)
            said = []
            latency.plot_latency(d, os.path.join(d, "plots"), "rmse_fovea_fl", report=said.append)
            kfr = next(x for x in said if x.startswith("kfr"))
            rmfr = next(x for x in said if x.startswith("rmfr"))
            # +0.0037 at 50 ms is +7% of the mean but its interval (+-0.010) contains 0: the first
            # degradation is at 80 ms, where the pair is listed high latency first.
            self.assertIn("at 80 ms", kfr)
            self.assertIn("+0.02 worse (95% [+0.016, +0.024])", kfr)
            self.assertIn("no paired interval", rmfr)
            _, rows = common.read_csv(os.path.join(d, "plots", "latency_rmse_fovea_fl.csv"))
            deg = {(r["line"], r["latency_ms"]): r["degraded"] for r in rows}
            self.assertEqual(deg[("kfr", "50")], "0")
            self.assertEqual(deg[("kfr", "80")], "1")
            self.assertEqual(deg[("rmfr", "80")], "")
            # A threshold beyond the interval's near end: no degradation at all.
            said = []
            latency.plot_latency(d, os.path.join(d, "plots"), "rmse_fovea_fl", threshold=0.02, report=said.append)
            self.assertIn("no swept latency degrades it", next(x for x in said if x.startswith("kfr")))
            self.assertIn("least favourable change at 80 ms", next(x for x in said if x.startswith("kfr")))

    def test_orientation_for_higher_is_better(self):
        import latency
        paired = [{"kind": "across", "metric": "fpsnr", "config_a": "kfr", "gpu": "g", "cell_a_id": "lo",
                   "cell_b_id": "hi", "diff": "0.5", "diff_lo": "0.2", "diff_hi": "0.8"}]
        ch = latency.paired_change(paired, "fpsnr", "kfr", "g", "lo", "hi", True)
        self.assertEqual(ch, (0.5, 0.2, 0.8))  # lo - hi = +0.5 dB: worse at the higher latency
        self.assertEqual(latency.degraded(ch), 1)
        ch = latency.paired_change(paired, "fpsnr", "kfr", "g", "lo", "hi", False)
        self.assertEqual(ch, (-0.5, -0.8, -0.2))
        self.assertEqual(latency.degraded(ch), 0)
        self.assertIsNone(latency.degraded(None))

    def test_cli_format_and_bad_threshold(self):
        import subprocess
        with tempfile.TemporaryDirectory() as d:
            make_latency_sweep(d)
            script = os.path.join(REPO, "viz", "latency.py")
            r = subprocess.run([sys.executable, script, d, "--metric", "rmse_fovea_fl", "--format", "svg"],
                               capture_output=True, text=True)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertTrue(os.path.exists(os.path.join(d, "plots", "latency_rmse_fovea_fl.svg")))
            r = subprocess.run([sys.executable, script, d, "--threshold", "-1"], capture_output=True, text=True)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("--threshold -1", r.stderr)


class Layout(unittest.TestCase):
    """Every shipped figure, rendered from the small test data, is PAGE_WIDTH_IN wide, keeps every
    text inside the canvas and no two texts overlap (matplotlib's renderer: the drawn texts'
    window extents)."""

    def setUp(self):
        if not common.load_metric_registry():  # no fovsim binary: the registry's headline rows
            common.set_metric_registry([
                {"name": "psnr", "label": "PSNR [dB]", "better": "higher", "headline": True},
                {"name": "fpsnr", "label": "FPSNR [dB]", "better": "higher", "headline": True, "show_fl": True},
                {"name": "ssim", "label": "SSIM [0-1]", "better": "higher", "headline": True},
                {"name": "flip", "label": "LDR-FLIP [0-1, lower is better]", "better": "lower", "headline": True},
                {"name": "rmse_fovea", "label": "RMSE in the fovea [0-1]", "better": "lower", "paired": True}])

    def collect(self, fn):
        got = []
        orig = common.save

        def grab(fig, path):
            got.append((os.path.basename(path), common.layout_problems(fig), fig.get_size_inches()[0]))
            return orig(fig, path)

        common.save = grab
        try:
            fn()
        finally:
            common.save = orig
        return got

    def check(self, got, want):
        names = [g[0] for g in got]
        for w in want:
            self.assertIn(w, names)
        bad = [f"{name}: {p}" for name, problems, _ in got for p in problems]
        bad += [f"{name}: {w:.2f} in wide" for name, _, w in got if w > common.PAGE_WIDTH_IN + 1e-6]
        self.assertEqual(bad, [], "\n".join(bad))

    def test_run_figures(self):
        import matplotlib.pyplot as plt
        with tempfile.TemporaryDirectory() as d:
            frames = [FRAMES[0] + ",shaded_fraction,flip"]
            names = ["full", "full_tbds", "kfr", "kfr_sigma_2.4_long_label", "rmfr", "rmfr_fx_0.3_fy_0.3"]
            meth = ["full", "full", "kfr", "kfr", "rmfr", "rmfr"]
            for f in range(24):
                for k, (n, m) in enumerate(zip(names, meth)):
                    ps = "inf" if n == "full" else 28 + k + 0.1 * f
                    frames.append(f"{n},{m},{n},{f},{f / 90},{100 + f},{80 - f},{ps},{ps},{0.9 + 0.01 * k},"
                                  f"{4 + k + 0.05 * (f % 3)},{0.3 + 0.1 * k},{0.1 - 0.01 * k}")
            write(os.path.join(d, "frames.csv"), "\n".join(frames) + "\n")
            summ = ["config_id,method,label,frames,est_ms_total,est_ms_total_ci95,psnr,psnr_ci95,fpsnr,fpsnr_ci95,"
                    "ssim,ssim_ci95,flip,shaded_fraction,shaded_fraction_ci95,est_ms_gbuffer,est_ms_lighting,"
                    "est_ms_tonemap,rmse_ecc_0_5,rmse_ecc_5_10,rmse_ecc_10_20,flip_ecc_0_5,flip_ecc_5_10"]
            for k, (n, m) in enumerate(zip(names, meth)):
                ps = "inf" if n == "full" else 28 + k
                summ.append(f"{n},{m},{n},24,{4 + k * 0.3},0.05,{ps},0.3,{ps},0.3,{0.9 + 0.01 * k},0.01,0.1,"
                            f"{0.3 + 0.1 * k},0.01,{1 + 0.1 * k},{2 + 0.2 * k},0.3,0.01,0.02,0.03,0.05,0.06")
            write(os.path.join(d, "summary.csv"), "\n".join(summ) + "\n")
            pr = ["config_a,config_b,gpu,metric,frames,mean_a,mean_b,diff,diff_ci95,diff_lo,diff_hi,differs"]
            for i in range(len(names)):
                for j in range(i + 1, len(names)):
                    for m in ("est_ms_total", "ssim", "fpsnr"):
                        pr.append(f"{names[i]},{names[j]},g,{m},24,1,1,{0.1 * (j - i)},0.05,0,0.2,1")
            write(os.path.join(d, "paired.csv"), "\n".join(pr) + "\n")
            write(os.path.join(d, "manifest.json"), '{"display": {"width": 200, "height": 160, "refresh_hz": 90}}')
            fd = os.path.join(d, "images", "frame_0")
            os.makedirs(fd)
            for name, v in (("reference", 1.0), ("kfr", 0.5), ("rmfr", 0.2)):
                plt.imsave(os.path.join(fd, name + ".png"), np.full((40, 50, 3), v))
            got = self.collect(lambda: plot_run.main([d]))
        self.check(got, ["timeline.png", "quality_vs_cost.png", "quality_vs_budget.png", "quality_timeline.png",
                         "shaded_fraction.png", "gaze.png", "paired.png", "paired_vs_baseline.png", "passes.png",
                         "eccentricity.png", "strip_0.png"])

    def test_sweep_figures(self):
        with tempfile.TemporaryDirectory() as d:
            make_sweep(d)
            got = self.collect(lambda: plot_sweep.main([d]))
        self.check(got, ["pareto.png", "quality_vs_budget.png", "eccentricity_profiles.png"])

    def test_latency_figure(self):
        import latency
        with tempfile.TemporaryDirectory() as d:
            make_latency_sweep(d)
            got = self.collect(lambda: latency.plot_latency(d, d, "rmse_fovea_fl", report=lambda s: None))
        self.check(got, ["latency_rmse_fovea_fl.png"])

    def test_fidelity_figure(self):
        import plot_fidelity
        head = ("rung,config_id,method,output,rung_index,wall_s,wall_ratio,cpu_s,cpu_ratio,"
                "frames,top,value,err,err_rel,err_ci95,err_ci95_paired,ranking_same,ranking_resolved_swaps")
        lines = [head]
        for i, (rung, wall, e) in enumerate([("analytic", 0.1, 0.3), ("scale=0.125", 9, 0.05),
                                              ("scale=0.25", 10, 0.02), ("scale=0.5", 40, 0.0)]):
            for o in ["est_ms_total", "psnr", "ssim"]:
                lines.append(f"{rung},kfr,kfr,{o},{i},{wall},{wall / 40},{wall},{wall / 40},90,10,{10 + e},{e},"
                             f"{e / 10},0.01,nan,1,0")
        with tempfile.TemporaryDirectory() as d:
            write(os.path.join(d, "fidelity.csv"), "\n".join(lines) + "\n")
            got = self.collect(lambda: plot_fidelity.main([d]))
        self.check(got, ["fidelity.png"])

    def test_density_and_cost_figures(self):
        import plot_cost
        import plot_density
        with tempfile.TemporaryDirectory() as d:
            rows = ["method,direction_deg,ecc_deg,density_capped"]
            for m in ("kfr", "rmfr", "fvrs"):
                for dd in (0, 45, 90):
                    for e in range(0, 50, 5):
                        rows.append(f"{m},{dd},{e},{max(0.05, 1 - e / 50)}")
            write(os.path.join(d, "density.csv"), "\n".join(rows) + "\n")
            got = self.collect(lambda: plot_density.main([os.path.join(d, "density.csv"),
                                                          os.path.join(d, "density.png")]))
            cost = ["experiment,kind,gpu,table,passes,published_ms,model_ms,model_lo_ms,model_hi_ms"]
            for g in ("gtx1080", "rtx2080ti"):
                for k, p in enumerate(("gbuffer", "lighting", "tonemap")):
                    cost.append(f"cross:seed,predicted,{g},kfr,{p},{1 + k},{1.1 + k},{0.8 + k},{1.4 + k}")
                    cost.append(f"calibration,fit,{g},kfr,{p},{1 + k},{1.05 + k},nan,nan")
                cost.append(f"cross:seed,total,{g},kfr,gbuffer+lighting,5,5.5,4.5,6.5")
            write(os.path.join(d, "cost.csv"), "\n".join(cost) + "\n")
            got += self.collect(lambda: plot_cost.main([os.path.join(d, "cost.csv"), os.path.join(d, "cost.png")]))
        self.check(got, ["density.png", "cost.png"])


if __name__ == "__main__":
    unittest.main()
