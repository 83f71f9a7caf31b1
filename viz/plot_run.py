#!/usr/bin/python3
"""Plots of one fovsim result directory (docs/architecture.md "Outputs").

    /usr/bin/python3 viz/plot_run.py results/<name> [--out DIR]

Reads results/<name>/frames.csv, summary.csv and manifest.json (column names:
results/README.md) and writes PNGs plus an index.html to results/<name>/plots/ (or DIR):
  timeline.png          est_ms_total per frame and config, with the frame-budget line
                        (1000 / display.refresh_hz from manifest.json) and the budget
                        decision's line (summary.csv fit_threshold_ms: below it p_fit >=
                        fit_level, docs/cost_model.md "Budget decisions")
  quality_vs_cost.png   mean fpsnr / psnr / ssim vs mean est_ms_total per config, Pareto
                        front (lower cost, higher quality) drawn; error bars: the 95% intervals
                        `<col>_ci95` of summary.csv (both axes)
  quality_vs_budget.png best mean fpsnr / ssim attainable within a frame budget B, per method
                        (95% intervals) and over all methods, with the display's budget; a
                        configuration fits B at p_fit >= fit_level (the same decision)
  shaded_fraction.png   mean shaded_fraction per config, with its 95% interval
  paired_vs_baseline.png  every configuration minus the baseline (full), sorted by effect
  paired.png            paired.csv: per headline metric, the mean difference of every pair
                        of configs with its 95% interval (filled: the interval excludes 0)
  gaze.png              gaze path on the screen (pixels, row 0 on top)
  quality_timeline.png  fpsnr / psnr / ssim / flip per frame and config (configs with no finite
                        value, e.g. full's psnr = inf, are named in the panel, not drawn)
  passes.png            mean est_ms_<pass> stacked per config, est_ms_total with its interval
  eccentricity.png      mean rmse_ecc_<a>_<b> / flip_ecc_<a>_<b> per band and config (95% intervals)
  strip_<frame>.png     for images/frame_<n>/: reference and every config side by side, gaze
                        marked, insets at the gaze and in the periphery, error colour bar
  run.mp4               the saved frames side by side with the gaze (viz/make_video.py; needs
                        ffmpeg and two or more outputs.image_frames, else skipped with the reason)
  index.html            summary table (means ± 95% half-width), the plots, and images/frame_<n>/
Colours: one per method in every plot (common.method_color); several configurations of one
method differ by line style and marker. Intervals that are undefined (nan: fewer frames than the estimator's minimum) are not drawn.
A plot whose columns are missing is skipped with a message (and listed in index.html).
Means use finite values only (psnr is inf for identical images, temporal_error nan on the
first frame). Exit status: 0, or 2 when the directory has neither frames.csv nor summary.csv.
"""
import argparse
import html
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from common import finite_mean, log, plt, to_float  # noqa: E402

MAX_LEGEND = 14


class Skip(Exception):
    """A plot that cannot be drawn from the available data (reason in the message)."""


class Run:
    def __init__(self, d):
        self.dir = d
        self.fcols, self.frames = common.read_csv(os.path.join(d, "frames.csv"))
        self.scols, self.summary = common.read_csv(os.path.join(d, "summary.csv"))
        self.manifest = common.read_json(os.path.join(d, "manifest.json"))
        common.load_metric_registry(self.manifest)  # the C++'s metric declarations
        self.pcols, self.paired = common.read_csv(os.path.join(d, "paired.csv"))
        self.fcols = self.fcols or []
        self.scols = self.scols or []
        # Configurations in order of first appearance.
        self.configs, self.by_config = [], {}
        src = self.frames if self.frames else (self.summary or [])
        for row in src:
            cid = row.get("config_id") or row.get("label") or row.get("method") or "?"
            if cid not in self.by_config:
                self.configs.append(cid)
                self.by_config[cid] = []
            self.by_config[cid].append(row)
        if self.frames:
            for rows in self.by_config.values():
                rows.sort(key=lambda r: to_float(r.get("frame")))

    def has(self, col):
        return col in self.fcols

    def series(self, cid, col):
        return [to_float(r.get(col)) for r in self.by_config[cid]]

    def mean(self, cid, col):
        """Per-config value of summary.csv as the C++ wrote it (the mean, or a pooled value such as
        FovVideoVDP's JOD: the same number as the summary table and its `_ci95`); the finite mean
        of frames.csv only for a column the summary does not have."""
        if self.summary and col in self.scols:
            for r in self.summary:
                if (r.get("config_id") or r.get("label") or r.get("method")) == cid:
                    return to_float(r.get(col))
        if self.frames and self.has(col):
            return finite_mean(self.series(cid, col))
        return math.nan

    def ci(self, cid, col):
        """95% half-width `<col>_ci95` from summary.csv; nan when absent or undefined."""
        if self.summary and col + "_ci95" in self.scols:
            for r in self.summary:
                if (r.get("config_id") or r.get("label") or r.get("method")) == cid:
                    return to_float(r.get(col + "_ci95"))
        return math.nan

    def mean_available(self, col):
        return (self.frames and self.has(col)) or (self.summary and col in self.scols)

    def method(self, cid):
        rows = self.by_config[cid]
        return (rows[0].get("method") or cid) if rows else cid

    def methods(self):
        out = []
        for c in self.configs:
            m = self.method(c)
            if m not in out:
                out.append(m)
        return out

    def _styles(self):
        if getattr(self, "_sty", None) is None:
            self._sty = common.variant_styles([(c, self.method(c)) for c in self.configs])
        return self._sty

    def style(self, cid):
        """(marker, colour) of a configuration: colour per method (common.method_color, the same
        in every plot and script), marker per configuration of that method."""
        col, _, mk = self._styles()[cid]
        return mk, col

    def color(self, cid):
        return self._styles()[cid][0]

    def linestyle(self, cid):
        # Several configurations of one method share its colour; the line style tells them apart.
        return self._styles()[cid][1]


def need(run, *cols):
    if not run.frames:
        raise Skip("no frames.csv")
    missing = [c for c in cols if not run.has(c)]
    if missing:
        raise Skip("frames.csv has no column " + ", ".join(missing))


def legend(ax, n):
    if n <= MAX_LEGEND:
        common.legend_below(ax.figure, *ax.get_legend_handles_labels())


def legend_entries(run, *extra):
    """What the legend row of a figure holds: every configuration (when at most MAX_LEGEND) and
    the extra entries (budget line, Pareto front)."""
    return (list(run.configs) if len(run.configs) <= MAX_LEGEND else []) + [e for e in extra if e]


def tick_names(names, n=14):
    """Configuration names shortened for tick labels (the legend and index.html give them whole)."""
    return [common.short(c, n) for c in names]


def plot_timeline(run, out):
    need(run, "est_ms_total")
    xcol = "frame" if run.has("frame") else ("t" if run.has("t") else None)
    if xcol is None:
        raise Skip("frames.csv has neither frame nor t")
    b = common.budget_ms(run.manifest, run.summary)
    blabel = f"budget {b:.2f} ms ({1000 / b:.0f} Hz)" if b is not None else None
    rule = common.fit_rule(run.summary) if b is not None else None
    # The budget decision (docs/cost_model.md "Budget decisions"): below this line the p95 frame
    # fits with probability >= the level under the GPU profile's held-out errors.
    flabel = f"fits at p_fit ≥ {rule[0]:g}: ≤ {rule[1] * b:.2f} ms" if rule else None
    fig, (ax,) = common.figure(1, height=2.8, legend=legend_entries(run, blabel, flabel))
    for cid in run.configs:
        ax.plot(run.series(cid, xcol), run.series(cid, "est_ms_total"), lw=1, label=cid, color=run.color(cid),
                ls=run.linestyle(cid))
    if b is not None:
        ax.axhline(b, color="red", ls="--", lw=1.2, label=blabel)
    if rule:
        ax.axhline(rule[1] * b, color="red", ls=":", lw=1.2, label=flabel)
    else:
        log("timeline: no display.refresh_hz in manifest.json and no budget_ms in summary.csv; no budget line")
    ax.set_xlabel("frame [index]" if xcol == "frame" else "t [s]")
    ax.set_ylabel("estimated GPU frame time [ms]")
    ax.set_title("Estimated frame time per frame")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    legend(ax, len(run.configs) + 1)  # below the axes: never over a line
    common.save(fig, os.path.join(out, "timeline.png"))
    return "timeline.png"


def plot_quality_vs_cost(run, out):
    if not run.mean_available("est_ms_total"):
        raise Skip("no est_ms_total column")
    # Headline metrics where higher is better (the Pareto staircase assumes it).
    metrics = [m for m in common.headline_metrics() if common.higher_is_better(m) and run.mean_available(m)]
    if not metrics:
        raise Skip("no headline quality column (metric registry)")
    b = common.budget_ms(run.manifest, run.summary)
    fig, axes = common.figure(len(metrics), legend=legend_entries(run, "Pareto front", "budget" if b else None))
    for ax, m in zip(axes, metrics):
        pts = [(run.mean(c, "est_ms_total"), run.mean(c, m)) for c in run.configs]
        for cid, (x, y) in zip(run.configs, pts):
            if not (math.isfinite(x) and math.isfinite(y)):
                continue
            mk, col = run.style(cid)
            # Named by colour and marker in the legend: labels beside the points collide.
            ax.scatter([x], [y], marker=mk, color=col, s=30, label=cid, zorder=3)
            ex, ey = run.ci(cid, "est_ms_total"), run.ci(cid, m)
            if math.isfinite(ex) or math.isfinite(ey):
                ax.errorbar([x], [y], xerr=[ex] if math.isfinite(ex) else None,
                            yerr=[ey] if math.isfinite(ey) else None, fmt="none", ecolor=col, elinewidth=1,
                            capsize=2, zorder=2)
        front = common.pareto_front(pts)
        if front:
            fx = [pts[i][0] for i in front]
            fy = [pts[i][1] for i in front]
            # Staircase of the attainable set: at cost >= x_i, quality >= y_i is reachable.
            ax.step(fx, fy, where="post", color="k", ls="--", lw=1, zorder=2)
            ax.scatter(fx, fy, s=100, facecolors="none", edgecolors="k", lw=1, label="Pareto front", zorder=4)
        nonfinite = [c for c, (x, y) in zip(run.configs, pts) if not (math.isfinite(x) and math.isfinite(y))]
        title = f"{m} vs. frame time"
        if nonfinite:
            shown = ", ".join(common.short(c) for c in nonfinite[:3]) + (" …" if len(nonfinite) > 3 else "")
            title += f"\nnot drawn (no finite mean): {shown}"
        if b is not None:
            ax.axvline(b, color="red", ls=":", lw=1, label="budget")
        xs = [x for x, y in pts if math.isfinite(x) and x > 0]
        logx = xs and max(xs) > 4 * min(xs)  # e.g. flc's indirect light next to the others
        if logx:
            common.plain_log_x(ax)
        ax.set_xlabel("mean estimated frame time [ms" + (", log]" if logx else "]"))
        ax.set_ylabel(common.wrap("mean " + common.metric_label(m), 34))
        ax.set_title(title)
        ax.grid(alpha=0.3)
    if len(run.configs) <= MAX_LEGEND:  # one legend for the figure (every panel has the same entries)
        common.figure_legend(fig, axes)
    skipped = [m for m in ("fpsnr", "psnr") if m not in metrics]
    if skipped:
        log("quality_vs_cost: no column " + ", ".join(skipped) + " (panel left out)")
    common.save(fig, os.path.join(out, "quality_vs_cost.png"))
    return "quality_vs_cost.png"


def plot_quality_vs_budget(run, out):
    """Best mean quality attainable within a frame budget B (x), per configuration and over
    all of them: a configuration counts once its mean est_ms_total <= B (common.draw_quality_vs_budget)."""
    if not run.mean_available("est_ms_total"):
        raise Skip("no est_ms_total column")
    metrics = [m for m in common.headline_metrics() if m != "psnr" and run.mean_available(m)]
    if not metrics:
        raise Skip("no headline quality column (metric registry)")
    b = common.budget_ms(run.manifest, run.summary)
    # Keyed by configuration, not method: `full` and `fir` (method full) are two lines.
    entries = list(run.configs) + ["best of all methods"] + ([f"display budget {b:.2f} ms"] if b else [])
    fig, axes = common.figure(len(metrics), legend=entries, sharex=True, title_lines=1)
    for ax, m in zip(axes, metrics):
        entries = [(c, c, run.mean(c, "est_ms_total"), run.mean(c, m), run.ci(c, m))
                   for c in run.configs]
        common.draw_quality_vs_budget(ax, entries, m, b, common.fit_rule(run.summary))
    for i, ax in enumerate(axes):
        if i + common.MAX_COLUMNS < len(axes):
            ax.set_xlabel("")  # shared x: the label under each column's bottom panel only
    common.figure_legend(fig, axes)
    fig.suptitle("Quality vs. frame budget (best configuration of each method that fits)")
    common.save(fig, os.path.join(out, "quality_vs_budget.png"))
    return "quality_vs_budget.png"


def plot_shaded_fraction(run, out):
    if not run.mean_available("shaded_fraction"):
        raise Skip("no shaded_fraction column")
    vals = [run.mean(c, "shaded_fraction") for c in run.configs]
    n = len(vals)
    fig, (ax,) = common.figure(1, height=3.0, width=min(common.PAGE_WIDTH_IN, max(common.COLUMN_WIDTH_IN,
                                                                                0.35 * n + 1.2)))
    colors = [run.style(c)[1] for c in run.configs]
    errs = [run.ci(c, "shaded_fraction") for c in run.configs]
    bars = ax.bar(range(n), [v if math.isfinite(v) else 0 for v in vals], color=colors,
                  yerr=[e if math.isfinite(e) else 0 for e in errs], capsize=3, ecolor="k")
    for b, c in zip(bars, run.configs):  # the 2nd, 3rd ... configuration of a method: hatched
        if run.linestyle(c) != "-":
            b.set_hatch({"--": "//", ":": "..", "-.": "xx"}[run.linestyle(c)])
            b.set_edgecolor("white")
    for i, v in enumerate(vals):  # vertical when the bars are narrow, so values never touch
        ax.text(i, (v if math.isfinite(v) else 0) + 0.02, f"{v:.3f}" if math.isfinite(v) else "n/a",
                ha="center", va="bottom", fontsize=6, rotation=90 if n > 8 else 0)
    ax.set_xticks(range(n))
    # Vertical names when there are several: rotated text never runs into its neighbour.
    ax.set_xticklabels(tick_names(run.configs), rotation=90 if n > 3 else 0)
    ax.set_ylabel("mean shaded fraction [of W·H]")
    ax.set_ylim(0, max([1.05] + [v + (0.2 if n > 8 else 0.1) for v in vals if math.isfinite(v)]))
    ax.set_title(common.wrap("Shaded samples per configuration (error bars: 95% interval)", 44))
    ax.grid(axis="y", alpha=0.3)
    common.save(fig, os.path.join(out, "shaded_fraction.png"))
    return "shaded_fraction.png"


def plot_gaze(run, out):
    need(run, "gaze_x", "gaze_y")
    cid = run.configs[0]  # the gaze is the same for every configuration
    xs, ys = run.series(cid, "gaze_x"), run.series(cid, "gaze_y")
    valid = run.series(cid, "gaze_valid") if run.has("gaze_valid") else [1.0] * len(xs)
    tcol = "t" if run.has("t") else "frame"
    ts = run.series(cid, tcol) if run.has(tcol) else list(range(len(xs)))
    ok = [i for i in range(len(xs)) if math.isfinite(xs[i]) and math.isfinite(ys[i]) and valid[i] != 0]
    bad = [i for i in range(len(xs)) if math.isfinite(xs[i]) and math.isfinite(ys[i]) and valid[i] == 0]
    if not ok and not bad:
        raise Skip("no finite gaze samples")
    fig, (ax,) = common.figure(1, height=3.6, width=4.6)
    ax.plot([xs[i] for i in ok], [ys[i] for i in ok], color="0.7", lw=0.8, zorder=1)
    sc = ax.scatter([xs[i] for i in ok], [ys[i] for i in ok], c=[ts[i] for i in ok], cmap="viridis", s=8, zorder=2)
    if ok:
        fig.colorbar(sc, ax=ax, label="t [s]" if tcol == "t" else "frame [index]", shrink=0.9)
    if bad:
        ax.scatter([xs[i] for i in bad], [ys[i] for i in bad], marker="x", color="red", s=12, label="gaze_valid = 0")
    d = common.find_display(run.manifest)
    if d and isinstance(d.get("width"), (int, float)) and isinstance(d.get("height"), (int, float)):
        w, h = d["width"], d["height"]
        ax.plot([0, w, w, 0, 0], [0, 0, h, h, 0], color="k", lw=1)
        ax.set_title(f"Gaze path on the {int(w)}×{int(h)} screen" + ("\n(red x: gaze_valid = 0)" if bad else ""))
    else:
        ax.set_title("Gaze path (screen size unknown)" + ("\n(red x: gaze_valid = 0)" if bad else ""))
    ax.set_aspect("equal", adjustable="datalim")
    ax.invert_yaxis()  # row 0 on top (sim/core/math.h)
    ax.set_xlabel("gaze_x [px]")
    ax.set_ylabel("gaze_y [px]")
    common.save(fig, os.path.join(out, "gaze.png"))
    return "gaze.png"


def plot_quality_timeline(run, out):
    if not run.frames:
        raise Skip("no frames.csv")
    metrics = [m for m in common.headline_metrics() if run.has(m)]
    if not metrics:
        raise Skip("frames.csv has no headline metric column (metric registry)")
    xcol = "frame" if run.has("frame") else "t"
    if not run.has(xcol):
        raise Skip("frames.csv has neither frame nor t")
    fig, axes = common.figure(len(metrics), height=2.1, legend=legend_entries(run), sharex=True, title_lines=1)
    # Colour per configuration fixed across panels (run.style); one figure-level legend built from
    # every configuration, so a configuration missing from a panel (psnr inf) cannot shift labels.
    handles = {}
    not_drawn = {}
    for ax, m in zip(axes, metrics):
        for cid in run.configs:
            x, y = run.series(cid, xcol), run.series(cid, m)
            pts = [(a, b) for a, b in zip(x, y) if math.isfinite(b)]
            col = run.color(cid)
            if pts:
                full = run.method(cid) == "full"  # the reference pipeline on top (it often sits at ssim 1)
                # One full-sampling config is the dotted reference line; several (full_tbds, fir)
                # keep their own line styles so they stay apart.
                lone = full and sum(run.method(c) == "full" for c in run.configs) == 1
                (h,) = ax.plot([p[0] for p in pts], [p[1] for p in pts], lw=1.4 if full else 1, color=col,
                               ls=":" if lone else run.linestyle(cid), label=cid, zorder=5 if full else 2)
                handles.setdefault(cid, h)
            else:
                not_drawn.setdefault(m, []).append(cid)
        ax.set_ylabel(common.wrap(common.metric_label(m), 26))
        title = m
        if m in not_drawn:
            title += "\nnot drawn (no finite value): " + ", ".join(common.short(c) for c in not_drawn[m][:3]) + \
                (" …" if len(not_drawn[m]) > 3 else "")
        ax.set_title(title, color="0.2")
        ax.grid(alpha=0.3)
    for i, ax in enumerate(axes):
        if i + common.MAX_COLUMNS >= len(axes):  # the bottom panel of each column
            ax.set_xlabel("frame [index]" if xcol == "frame" else "t [s]")
    if len(handles) <= MAX_LEGEND:
        hs = [handles[c] for c in run.configs if c in handles]
        common.legend_below(fig, hs, [h.get_label() for h in hs])
    fig.suptitle("Quality per frame (non-finite values not drawn)")
    common.save(fig, os.path.join(out, "quality_timeline.png"))
    return "quality_timeline.png"


def _paired_panels(n_panels, n_rows):
    """The grid of the paired plots: one panel per metric, one row per pair, the pairs' names on
    the first column only."""
    return common.figure(n_panels, height=0.17 * n_rows + 0.9, sharey=True, title_lines=3)


def plot_paired(run, out):
    if not run.paired:
        raise Skip("no paired.csv (or a single configuration)")
    metrics = []
    for r in run.paired:
        if r.get("metric") not in metrics:
            metrics.append(r.get("metric"))
    pairs = []
    for r in run.paired:
        p = (r.get("config_a"), r.get("config_b"))
        if p not in pairs and p[0] in run.configs and p[1] in run.configs:
            pairs.append(p)
    # One row per pair, the same rows in every panel (shared y): its labels only on the left.
    fig, axes = _paired_panels(len(metrics), len(pairs))
    for ax, m in zip(axes, metrics):
        by = {(r.get("config_a"), r.get("config_b")): r for r in run.paired if r.get("metric") == m}
        rows = [by.get(p, {}) for p in pairs]
        for i, r in enumerate(rows):
            d, h = to_float(r.get("diff")), to_float(r.get("diff_ci95"))
            if not math.isfinite(d):
                continue
            filled = to_float(r.get("differs")) == 1
            ax.errorbar([d], [i], xerr=[h] if math.isfinite(h) else None, fmt="o", ms=3.5, capsize=2,
                        color="C0" if filled else "0.5", mfc="C0" if filled else "white")
        ax.axvline(0, color="k", lw=0.8)
        ax.set_title(m)
        ax.set_xlabel(common.wrap("A − B, " + common.metric_label(m), 40))
        ax.grid(axis="x", alpha=0.3)
        ax.xaxis.set_major_locator(matplotlib_ticker().MaxNLocator(4))
    axes[0].set_yticks(range(len(pairs)))
    axes[0].set_yticklabels([f"{common.short(a, 12)} − {common.short(b, 12)}" for a, b in pairs], fontsize=6)
    axes[0].set_ylim(len(pairs) - 0.5, -0.5)
    fig.suptitle(common.wrap("Paired differences A − B (same frames, same gaze), 95% intervals; filled: the "
                             "interval excludes 0; not drawn: a difference that is not finite (e.g. PSNR "
                             "against an identical image)", 100))
    common.save(fig, os.path.join(out, "paired.png"))
    return ["paired.png"] + plot_paired_baseline(run, out, metrics)


def plot_paired_baseline(run, out, metrics):
    """paired_vs_baseline.png: every configuration minus one baseline (the first configuration;
    `full` when present), one colour per configuration, rows sorted by the effect on the first
    metric (largest first): the plot a paper shows instead of all pairs."""
    base = next((c for c in run.configs if run.method(c) == "full"), run.configs[0] if run.configs else None)
    rows = {}
    for r in run.paired:
        a, b = r.get("config_a"), r.get("config_b")
        if a not in run.configs or b not in run.configs or base not in (a, b) or a == b:
            continue
        other, sign = (a, 1.0) if b == base else (b, -1.0)
        rows.setdefault(other, {})[r.get("metric")] = (sign * to_float(r.get("diff")), to_float(r.get("diff_ci95")),
                                                      to_float(r.get("differs")) == 1)
    if not rows:
        return []
    m0 = metrics[0]
    order = sorted(rows, key=lambda c: -abs(rows[c].get(m0, (0, 0, 0))[0])
                   if math.isfinite(rows[c].get(m0, (math.nan,))[0]) else 0)
    fig, axes = _paired_panels(len(metrics), len(order))
    for ax, m in zip(axes, metrics):
        for i, c in enumerate(order):
            d, h, sig = rows[c].get(m, (math.nan, math.nan, False))
            if not math.isfinite(d):
                continue
            col = run.color(c)
            ax.errorbar([d], [i], xerr=[h] if math.isfinite(h) else None, fmt=run.style(c)[0], ms=4, capsize=2,
                        color=col, mfc=col if sig else "white")
        ax.axvline(0, color="k", lw=0.8)
        ax.set_title(m)
        ax.set_xlabel(common.wrap(f"configuration − {base}, " + common.metric_label(m), 40))
        ax.grid(axis="x", alpha=0.3)
        ax.xaxis.set_major_locator(matplotlib_ticker().MaxNLocator(4))
    axes[0].set_yticks(range(len(order)))
    axes[0].set_yticklabels(tick_names(order, 18), fontsize=6)
    axes[0].set_ylim(len(order) - 0.5, -0.5)
    fig.suptitle(common.wrap(f"Each configuration vs. {base} (paired: same frames, same gaze), 95% intervals, "
                             f"sorted by |effect| on {m0}; filled: the interval excludes 0; not drawn: not finite",
                             100))
    common.save(fig, os.path.join(out, "paired_vs_baseline.png"))
    return ["paired_vs_baseline.png"]


def matplotlib_ticker():
    from matplotlib import ticker

    return ticker


def pass_columns(run):
    """est_ms_<pass> columns of summary.csv (not the total, its interval or percentiles)."""
    return [c for c in run.scols if c.startswith("est_ms_") and not c.startswith("est_ms_total")
            and not c.endswith(("_ci95", "_lo", "_hi"))]


def plot_passes(run, out):
    """Stacked mean estimated time per pass and configuration (summary.csv), with the total
    and its 95% interval as a black marker (left), and each pass's share of the frame (right:
    readable when one configuration, e.g. flc, costs far more than the others)."""
    if not run.summary:
        raise Skip("no summary.csv")
    passes = pass_columns(run)
    if not passes:
        raise Skip("summary.csv has no est_ms_<pass> columns")
    cfgs = run.configs
    cmap = plt.get_cmap("tab20")
    table = []
    for k, pcol in enumerate(passes):
        vals = [run.mean(c, pcol) for c in cfgs]
        vals = [v if math.isfinite(v) else 0.0 for v in vals]
        if any(vals):
            table.append((pcol[len("est_ms_"):], cmap(k % 20), vals))
    b = common.budget_ms(run.manifest, run.summary)
    entries = [t[0] for t in table] + ["est_ms_total (95% interval)"] + ([f"budget {b:.2f} ms"] if b else [])
    fig, (ax, axp) = common.figure(2, height=2.8, legend=entries, title_lines=1)
    sums = [sum(t[2][i] for t in table) for i in range(len(cfgs))]
    bottom, bottom_p = [0.0] * len(cfgs), [0.0] * len(cfgs)
    for name, col, vals in table:
        ax.bar(range(len(cfgs)), vals, bottom=bottom, color=col, label=name, edgecolor="white", lw=0.5)
        share = [100 * v / t if t > 0 else 0 for v, t in zip(vals, sums)]
        axp.bar(range(len(cfgs)), share, bottom=bottom_p, color=col, edgecolor="white", lw=0.5)
        bottom = [x + v for x, v in zip(bottom, vals)]
        bottom_p = [x + v for x, v in zip(bottom_p, share)]
    tot = [run.mean(c, "est_ms_total") for c in cfgs]
    err = [run.ci(c, "est_ms_total") for c in cfgs]
    ax.errorbar(range(len(cfgs)), tot, yerr=[e if math.isfinite(e) else 0 for e in err], fmt="_", color="k",
                ms=10, capsize=3, label="est_ms_total (95% interval)")
    if b is not None:
        ax.axhline(b, color="red", ls="--", lw=1, label=f"budget {b:.2f} ms")
    for a in (ax, axp):
        a.set_xticks(range(len(cfgs)))
        a.set_xticklabels(tick_names(cfgs, 12), rotation=90 if len(cfgs) > 2 else 0,
                          fontsize=6 if len(cfgs) > 8 else 7)
        for lbl, c in zip(a.get_xticklabels(), cfgs):
            lbl.set_color(run.color(c))  # the method's colour, as in every plot
        a.grid(axis="y", alpha=0.3)
    ax.set_ylabel("mean estimated GPU time [ms]")
    ax.set_title("Estimated frame time per pass (stacked)")
    axp.set_ylabel("share of the frame time [%]")
    axp.set_ylim(0, 100)
    axp.set_title("Share of each pass")
    common.figure_legend(fig, [ax])  # one legend, below both panels
    fig.suptitle("Cost model per pass (docs/cost_model.md)")
    common.save(fig, os.path.join(out, "passes.png"))
    return "passes.png"


def plot_eccentricity(run, out):
    """Mean RMSE and LDR-FLIP per eccentricity band and configuration, 95% intervals."""
    # The band families are the registry's (family declarations: rmse_ecc_, flip_ecc_, ...).
    fams = [f for f in common.metric_families()
            if any(re.match(re.escape(f) + r"[0-9p]+_[0-9p]+$", c) for c in run.scols)]
    if not run.summary or not fams:
        raise Skip("summary.csv has no rmse_ecc_<a>_<b> / flip_ecc_<a>_<b> columns")
    fig, axes = common.figure(len(fams), height=2.6, legend=legend_entries(run))
    for ax, fam in zip(axes, fams):
        # <fam><a>_<b> only: not the _ci95 half-widths nor the _fl foveation-loss columns.
        band = re.compile(re.escape(fam) + r"[0-9p]+_[0-9p]+$")
        bands = [c for c in run.scols if band.match(c)]

        def mid(c):
            a, b = c[len(fam):].replace("p", ".").split("_")
            return 0.5 * (float(a) + float(b))

        xs = [mid(c) for c in bands]
        for cid in run.configs:
            ys = [run.mean(cid, c) for c in bands]
            es = [run.ci(cid, c) for c in bands]
            mk, col = run.style(cid)
            ax.errorbar(xs, ys, yerr=[e if math.isfinite(e) else 0 for e in es], marker=mk, ms=4, lw=1,
                        capsize=2, color=col, ls=run.linestyle(cid), label=cid)
        ax.set_xlabel("eccentricity [deg] (band centre)")
        short = {"rmse_ecc_": ("RMSE", "RMSE [display-encoded, 0–1]"),
                 "flip_ecc_": ("LDR-FLIP", "LDR-FLIP [0–1]")}.get(fam)
        label = (common.metric_decl(fam + "0_1") or {}).get("label", fam)
        ax.set_ylabel(short[1] if short else label)
        ax.set_title((short[0] if short else fam.rstrip("_")) + " vs. eccentricity (95% intervals)")
        ax.grid(alpha=0.3)
    if len(run.configs) <= MAX_LEGEND:  # one legend, below the panels
        common.figure_legend(fig, axes)
    common.save(fig, os.path.join(out, "eccentricity.png"))
    return "eccentricity.png"


def plot_strips(run, out):
    """strip_<frame>.png for each images/frame_<n>/: reference and every configuration side by
    side with the gaze marked, insets at the gaze and in the periphery, error maps with a colour
    bar (common.draw_strip); at most 8 configurations per strip; more go on further pages
    (strip_<frame>_p2.png, ...), never dropped; --configs chooses which and in what order."""
    img_root = os.path.join(run.dir, "images")
    if not os.path.isdir(img_root):
        raise Skip("no images/ (set outputs.image_frames)")
    d = common.find_display(run.manifest) or {}
    made = []
    for fdir in sorted(os.listdir(img_root), key=lambda x: (len(x), x)):
        full = os.path.join(img_root, fdir)
        ref = os.path.join(full, "reference.png")
        if not fdir.startswith("frame_") or not os.path.exists(ref):
            continue
        frame = fdir[len("frame_"):]
        cols = [("reference", plt.imread(ref), None)]
        labels = [run.by_config[c][0].get("label") or c for c in run.configs]
        shown = [lab for lab in labels if os.path.exists(os.path.join(full, lab + ".png"))]
        pages = [shown[i:i + 8] for i in range(0, len(shown), 8)]  # a second page, never dropped
        if not pages:
            continue
        for page, labs in enumerate(pages):
            cols = [cols[0]]
            for lab in labs:
                err = os.path.join(full, lab + "_error.png")
                cols.append((lab, plt.imread(os.path.join(full, lab + ".png")),
                             plt.imread(err) if os.path.exists(err) else None))
            made.append(_strip_page(run, d, frame, cols, page, len(pages), out))
    if not made:
        raise Skip("images/ has no frame_<n>/reference.png")
    return made


def _strip_page(run, d, frame, cols, page, pages, out):
    h, w = cols[0][1].shape[:2]
    gx, gy = w / 2, h / 2
    rows = [r for r in run.frames or [] if r.get("frame") == frame]
    if rows and isinstance(d.get("width"), (int, float)) and d["width"] > 0:
        sc = w / float(d["width"])
        x, y = to_float(rows[0].get("gaze_x")), to_float(rows[0].get("gaze_y"))
        if math.isfinite(x) and math.isfinite(y):
            gx, gy = x * sc, y * sc
    title = f"frame {frame}: gaze +"
    if pages > 1:
        title += f" (page {page + 1} of {pages})"
    f = f"strip_{frame}.png" if page == 0 else f"strip_{frame}_p{page + 1}.png"
    colors = {run.by_config[c][0].get("label") or c: run.color(c) for c in run.configs}
    common.save(common.draw_strip(cols, gx, gy, title, colors), os.path.join(out, f))
    return f


def plot_video(run, out):
    """run.mp4 of the saved frames (viz/make_video.py) when ffmpeg is present and two or more
    frames were saved; otherwise skipped with the reason."""
    import make_video  # noqa: E402  (viz/make_video.py)
    try:
        return make_video.make_video(run.dir, out, report=lambda m: None)  # main() logs the file
    except make_video.NoVideo as e:
        raise Skip(str(e))


PLOTS = [
    ("Estimated frame time per frame", plot_timeline),
    ("Quality vs. cost", plot_quality_vs_cost),
    ("Quality vs. frame budget", plot_quality_vs_budget),
    ("Shaded fraction per configuration", plot_shaded_fraction),
    ("Gaze path", plot_gaze),
    ("Quality per frame", plot_quality_timeline),
    ("Paired differences between configurations", plot_paired),
    ("Estimated time per pass", plot_passes),
    ("Error vs. eccentricity", plot_eccentricity),
    ("Methods side by side", plot_strips),
    ("Video of the saved frames", plot_video),
]


SUMMARY_COLS = ["method", "frames", "est_ms_total", "shaded_fraction"]  # + the headline metrics


def summary_table(run):
    """HTML table of summary.csv's headline columns (mean ± 95% half-width where present)."""
    if not run.summary:
        return "<p>No summary.csv.</p>"
    cols = [c for c in SUMMARY_COLS + common.headline_metrics() if c in run.scols]
    head = "<tr><th>config</th>" + "".join(f"<th>{html.escape(c)}</th>" for c in cols) + "</tr>"
    rows = []
    for r in run.summary:
        cid = r.get("config_id") or r.get("label") or r.get("method") or "?"
        cells = []
        for c in cols:
            v = r.get(c, "")
            ci = to_float(r.get(c + "_ci95"))
            f = to_float(v)
            if c == "method" or not math.isfinite(f):
                txt = v
            else:
                txt = f"{f:.4g}" + (f" ± {ci:.2g}" if math.isfinite(ci) else "")
            cells.append(f"<td>{html.escape(txt)}</td>")
        rows.append(f"<tr><td>{html.escape(cid)}</td>" + "".join(cells) + "</tr>")
    return ("<table><caption>summary.csv: per-configuration means ± 95% half-width (units: "
            "results/README.md; ms, dB)</caption>" + head + "".join(rows) + "</table>")


def image_sections(run, out):
    """Sections for images/frame_<n>/*.png, linked relative to the plots folder."""
    img_root = os.path.join(run.dir, "images")
    if not os.path.isdir(img_root):
        return []
    rel = os.path.relpath(img_root, out)
    parts = []
    frames = sorted((d for d in os.listdir(img_root) if os.path.isdir(os.path.join(img_root, d))),
                    key=lambda d: (len(d), d))
    for d in frames:
        pngs = sorted(f for f in os.listdir(os.path.join(img_root, d)) if f.endswith(".png"))
        if not pngs:
            continue
        # reference first, then per-configuration images in name order
        pngs.sort(key=lambda f: (f != "reference.png", f))
        parts.append(f"<h3>{html.escape(d)}</h3><div class='grid'>")
        for f in pngs:
            src = html.escape(f"{rel}/{d}/{f}")
            parts.append(f"<figure><a href='{src}'><img src='{src}' alt='{html.escape(f)}'></a>"
                         f"<figcaption>{html.escape(f)}</figcaption></figure>")
        parts.append("</div>")
    if parts:
        head = ["<h2 id='images'>Images (error maps: |luma error| turbo 0–0.25, FLIP magma 0–1)</h2>"]
        try:
            bar = colorbar_legend(out)
            head.append(f"<p><img src='{bar}' alt='colour bars of the error maps' style='max-width:520px;border:0'></p>")
        except Exception as e:  # the legend is a help, never a reason to lose the page
            log(f"colour bar legend not drawn: {e!r}")
        parts = head + parts
    return parts


def colorbar_legend(out):
    """error_colorbars.png: the colour bars of the error maps that images/frame_<n>/ holds
    (|luma error| turbo 0–0.25, LDR-FLIP magma 0–1; results/README.md), shown above them."""
    from matplotlib import cm, colors

    fig = plt.figure(figsize=(common.COLUMN_WIDTH_IN * 1.4, 1.5), layout="constrained")
    axes = fig.subplots(2, 1)
    for ax, (cmap, hi, label) in zip(axes, (("turbo", 0.25, "<label>_error.png: |luma error| (display-encoded)"),
                                            ("magma", 1.0, "<label>_flip.png: LDR-FLIP error"))):
        fig.colorbar(cm.ScalarMappable(norm=colors.Normalize(0, hi), cmap=cmap), cax=ax, orientation="horizontal")
        ax.set_title(label, fontsize=7)
        ax.tick_params(labelsize=6)
    common.save(fig, os.path.join(out, "error_colorbars.png"))
    return "error_colorbars.png"


def write_index(run, out, made, skipped):
    name = os.path.basename(os.path.normpath(run.dir))
    parts = [
        "<!DOCTYPE html>",
        f"<html><head><meta charset='utf-8'><title>fovsim: {html.escape(name)}</title>",
        "<style>body{font-family:sans-serif;margin:2em}img{max-width:100%;border:1px solid #ccc}"
        "table{border-collapse:collapse;font-size:90%}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}"
        ".grid{display:flex;flex-wrap:wrap;gap:8px}.grid figure{width:300px;margin:0;font-size:80%}</style>",
        f"</head><body><h1>fovsim results: {html.escape(name)}</h1>",
        f"<p>{len(run.configs)} configuration(s): {html.escape(', '.join(run.configs))}</p>",
        "<h2 id='summary'>Summary</h2>", summary_table(run),
    ]
    if made:
        parts.append("<ul>" + "".join(f"<li><a href='#{f}'>{html.escape(t)}</a></li>" for t, f in made) + "</ul>")
    for title, f in made:
        if f.endswith(".mp4"):
            parts.append(f"<h2 id='{f}'>{html.escape(title)}</h2><video src='{f}' controls loop "
                         f"style='max-width:100%'></video><p><a href='{f}'>{f}</a></p>")
        else:
            parts.append(f"<h2 id='{f}'>{html.escape(title)}</h2><a href='{f}'><img src='{f}' "
                         f"alt='{html.escape(title)}'></a>")
    parts += image_sections(run, out)
    if skipped:
        parts.append("<h2>Skipped</h2><ul>")
        parts += [f"<li>{html.escape(t)}: {html.escape(r)}</li>" for t, r in skipped]
        parts.append("</ul>")
    parts.append("</body></html>\n")
    common.write_text_atomic(os.path.join(out, "index.html"), "\n".join(parts))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("results_dir", help="results/<name> with frames.csv, summary.csv, manifest.json")
    ap.add_argument("--out", help="output directory (default: RESULTS_DIR/plots)")
    common.add_output_args(ap)
    a = ap.parse_args(argv)
    common.set_output(a)
    run = Run(a.results_dir)
    if a.configs:  # --configs: only these, in this order (every plot, strips included)
        labels = {(run.by_config[c][0].get("label") or c): c for c in run.configs}
        names = list(run.configs) + [n for n in labels if n not in run.configs]
        run.configs = [labels.get(c, c) for c in common.pick_configs(names, a.configs)]
    if run.frames is None and run.summary is None:
        print(f"plot_run: error: {a.results_dir}: no frames.csv or summary.csv", file=sys.stderr)
        return 2
    if not run.configs:
        print(f"plot_run: error: {a.results_dir}: frames.csv and summary.csv have no rows", file=sys.stderr)
        return 2
    out = a.out or os.path.join(a.results_dir, "plots")
    os.makedirs(out, exist_ok=True)
    made, skipped = [], []
    for title, fn in PLOTS:
        try:
            fs = fn(run, out)
            for f in fs if isinstance(fs, list) else [fs]:
                made.append((title, f))
                log(f"wrote {os.path.join(out, f)}")
        except Skip as e:
            skipped.append((title, str(e)))
            log(f"skipped '{title}': {e}")
        except Exception as e:  # a plot must never hide the others (e.g. an unreadable PNG)
            skipped.append((title, f"failed: {e!r}"))
            log(f"failed '{title}': {e!r}")
    write_index(run, out, made, skipped)
    if not a.out:  # the run folder's own index.html opens the report
        common.write_text_atomic(os.path.join(a.results_dir, "index.html"),
                                 "<!DOCTYPE html><html><head><meta charset='utf-8'>"
                                 "<meta http-equiv='refresh' content='0; url=plots/index.html'></head>"
                                 "<body><a href='plots/index.html'>plots/index.html</a></body></html>\n")
    log(f"wrote {os.path.join(out, 'index.html')} ({len(made)} plots, {len(skipped)} skipped)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
