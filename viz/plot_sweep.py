#!/usr/bin/python3
"""Plots of a fovsim sweep folder (results/<name>/ written by `fovsim sweep` or `fovsim merge`).

Writes into <dir>/plots/: pareto.png (declared objectives, front highlighted, every method,
95% intervals `<col>_ci95` as error bars; eccentricity profiles carry them too),
heat maps over sigma x alpha and fx x fy per method (Ye et al. 2022 Fig. 6/9 style), per-frame
timelines of the Pareto cells with the frame-budget line and gaze speed, error-vs-eccentricity
profiles, image strips with zoomed insets (when cells wrote images), and index.html linking
every plot, table and cell folder. Needs Debian's python3-matplotlib and python3-numpy.
See docs/sweeps.md.
"""
import argparse
import glob
import html
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from common import plt, to_float, log  # noqa: E402

import numpy as np  # noqa: E402

PARAMS = ["sigma", "alpha", "fx", "fy", "epsilon", "vpl_budget"]
PAIRS = [("sigma", "alpha"), ("fx", "fy"), ("sigma", "fx"), ("epsilon", "phi_f")]
TIMING = {"ref_ms", "sim_ms"}
MAX_STRIP_CONFIGS = 6  # strips show at most this many Pareto rows per cell frame (said in the title)


def axis_label(col):
    """Column name with its unit (results/README.md), shared with every viz script."""
    return common.metric_label(col)


class Skip(Exception):
    pass


NOTES = []  # caps and other things a reader should know, printed and listed in index.html


def note(msg):
    log(msg)
    NOTES.append(msg)


class Sweep:
    def __init__(self, d):
        self.dir = d
        self.cols, self.rows = common.read_csv(os.path.join(d, "summary.csv"))
        self.meta = common.read_json(os.path.join(d, "sweep_summary.json")) or {}
        self.sweep = common.read_json(os.path.join(d, "sweep.json")) or {}
        self.rows = self.rows or []
        self.cols = self.cols or []

    def num(self, r, c):
        return to_float(r.get(c))

    def labels(self):
        out = []
        for r in self.rows:
            if r.get("label") not in out:
                out.append(r.get("label"))
        return out

    def color(self, label):
        """The colour of the label's method (common.method_color): the same in every plot and script."""
        for r in self.rows:
            if r.get("label") == label:
                return common.method_color(r.get("method") or label)
        return common.method_color(label)

    def axes_cols(self):
        """Summary columns of the swept axes (named by their path, docs/sweeps.md)."""
        return [a for a in self.meta.get("axes", []) if a in self.cols]

    def params_text(self, r):
        """The swept values that apply to row r, e.g. "sigma=1.8 alpha=4" (its own method's)."""
        parts = []
        lab = r.get("label", "")
        for a in self.axes_cols():
            v = r.get(a, "")
            if v == "":
                continue
            # methods[<label>].<param>: show only the row's own method's parameters
            if a.startswith("methods[") and "]" in a and a[len("methods["):a.index("]")] not in (lab, r.get("method")):
                continue
            parts.append(f"{a.rsplit('.', 1)[-1]}={v}")
        return " ".join(parts)

    def distinct(self):
        """Rows with duplicates removed: a method not touched by any axis gives the same row in
        every cell; keep its first (returns the rows kept and how many were duplicates)."""
        seen, keep = set(), []
        for r in self.rows:
            key = (r.get("label"), r.get("gpu"), self.params_text(r),
                   tuple(r.get(c, "") for c in self.cols if c not in TIMING and c not in
                         ("config_id", "cell_id", "cell", "pareto") and c not in self.meta.get("axes", [])))
            if key in seen:
                continue
            seen.add(key)
            keep.append(r)
        return keep, len(self.rows) - len(keep)

    def row_name(self, r):
        """"kfr sigma=1.8" (label and its swept parameters), plus @gpu when several are costed."""
        gpus = {x.get("gpu", "") for x in self.rows}
        g = f" @{r.get('gpu')}" if len(gpus) > 1 else ""
        return f"{r.get('label')} {self.params_text(r)}".strip() + g

    def row_styles(self, rows):
        """{row_name: (colour, linestyle, marker)}: the method's colour, line style and marker per
        configuration of that method (common.variant_styles)."""
        return common.variant_styles([(self.row_name(r), r.get("method") or r.get("label")) for r in rows])

    def objectives(self):
        obj = []
        for o in self.meta.get("objectives", []):
            for k, v in o.items():
                obj.append((v, k == "maximize"))
        if len(obj) < 2:
            obj = [("est_ms_total", False), ("fpsnr", True)]
        return obj

    def budget(self):
        for r in self.rows:
            b = to_float(r.get("budget_ms"))
            if math.isfinite(b):
                return b
        return None


def plot_pareto(sw, out):
    (cx, _), (cy, maxy) = sw.objectives()[:2]
    if cx not in sw.cols or cy not in sw.cols:
        raise Skip(f"summary.csv lacks {cx} or {cy}")
    rows, dups = sw.distinct()
    b = sw.budget()
    entries = list(sw.labels()) + ["Pareto front"] + ([f"frame budget {b:.2f} ms"] if b is not None else [])
    fig, (ax,) = common.figure(1, height=3.6, legend=entries, title_lines=1)
    for lab in sw.labels():
        rs = [r for r in rows if r.get("label") == lab]
        col = sw.color(lab)
        ax.scatter([sw.num(r, cx) for r in rs], [sw.num(r, cy) for r in rs], s=22, alpha=0.8, color=col, label=lab,
                   zorder=3)
        # 95% intervals (<col>_ci95, docs/intervals.md); undefined ones (nan) are not drawn.
        for r in rs:
            ex, ey = sw.num(r, cx + "_ci95"), sw.num(r, cy + "_ci95")
            if math.isfinite(ex) or math.isfinite(ey):
                ax.errorbar([sw.num(r, cx)], [sw.num(r, cy)], xerr=[ex] if math.isfinite(ex) else None,
                            yerr=[ey] if math.isfinite(ey) else None, fmt="none", lw=0.8, alpha=0.6, ecolor=col)
    front = [r for r in rows if r.get("pareto") == "1"]
    labelled = front if len(rows) > 30 else rows  # label every point when few, else the front
    if front:
        front.sort(key=lambda r: sw.num(r, cx))
        ax.plot([sw.num(r, cx) for r in front], [sw.num(r, cy) for r in front], "k-", lw=1.2, label="Pareto front")
        ax.scatter([sw.num(r, cx) for r in front], [sw.num(r, cy) for r in front], s=60, facecolors="none",
                   edgecolors="k", zorder=4)
    if b is not None and cx == "est_ms_total":
        ax.axvline(b, color="red", ls="--", lw=1, label=f"frame budget {b:.2f} ms")
    hidden = sorted({f"{r.get('label')} {sw.params_text(r)}".strip() for r in rows
                     if not (math.isfinite(sw.num(r, cx)) and math.isfinite(sw.num(r, cy)))})
    ax.set_xlabel(common.wrap(axis_label(cx) + " — minimize", 80))
    ax.set_ylabel(common.wrap(axis_label(cy) + (" — maximize" if maxy else " — minimize"), 45))
    title = f"{sw.meta.get('name', '')}: {len(rows)} distinct configurations"
    if dups:
        title += f" ({dups} identical rows of unswept methods not repeated)"
    if hidden:  # in the title, where it cannot run into the data
        title += "\nnot drawn (non-finite, e.g. fpsnr = inf when exact): " + ", ".join(hidden[:4]) + \
            (" …" if len(hidden) > 4 else "")
    ax.set_title(common.wrap(title, 100))
    ax.grid(alpha=0.3)
    common.figure_legend(fig, [ax])
    # Labels (label and swept parameters) where they collide with nothing; the rest are named in
    # index.html's Pareto table.
    dropped = common.place_labels(ax, [(sw.num(r, cx), sw.num(r, cy), sw.row_name(r)) for r in labelled])
    if dropped:
        note(f"pareto: {len(dropped)} point labels left out where they would overlap (pareto.csv lists them)")
    common.save(fig, os.path.join(out, "pareto.png"))
    return ["pareto.png"]


def plot_quality_vs_budget(sw, out):
    """Best quality attainable within a frame budget B per label (distinct rows; one GPU at a
    time when several are costed)."""
    if "est_ms_total" not in sw.cols:
        raise Skip("summary.csv has no est_ms_total")
    metrics = [m for m in ("fpsnr", "ssim") if m in sw.cols]
    if not metrics:
        raise Skip("summary.csv has no fpsnr or ssim")
    rows, _ = sw.distinct()
    gpus = list(dict.fromkeys(r.get("gpu", "") for r in rows))
    made = []
    for g in gpus:
        rs = [r for r in rows if r.get("gpu", "") == g]
        b = sw.budget()
        # One line per label (a method entry), not per method: two entries of one method
        # (full and fir) stay apart.
        leg = list(dict.fromkeys(r.get("label") or r.get("method") for r in rs)) + ["best of all methods"] + \
            ([f"display budget {b:.2f} ms"] if b else [])
        fig, axes = common.figure(len(metrics), legend=leg, title_lines=1)
        for ax, m in zip(axes, metrics):
            entries = [(r.get("label") or r.get("method"), f"{r.get('label')} {sw.params_text(r)}".strip(),
                        sw.num(r, "est_ms_total"), sw.num(r, m), sw.num(r, m + "_ci95")) for r in rs]
            common.draw_quality_vs_budget(ax, entries, m, b, common.fit_rule(rs))
        common.figure_legend(fig, axes)
        fig.suptitle(common.wrap(f"{sw.meta.get('name', '')}: quality vs. frame budget" + (f" on {g}" if g else "") +
                                 f" ({len(rs)} distinct configurations)", 100))
        f = "quality_vs_budget.png" if len(gpus) == 1 else f"quality_vs_budget_{g}.png"
        common.save(fig, os.path.join(out, f))
        made.append(f)
    return made


def plot_heatmaps(sw, out):
    made = []
    metrics = [m for m in ("fpsnr", "ssim", "shaded_fraction", "est_ms_total") if m in sw.cols]
    for lab in sw.labels():
        rs = [r for r in sw.rows if r.get("label") == lab]
        varying = [p for p in PARAMS + ["phi_f"] if p in sw.cols and
                   len({r.get(p) for r in rs if math.isfinite(sw.num(r, p))}) >= 2]
        pairs = [p for p in PAIRS if p[0] in varying and p[1] in varying]
        if not pairs and len(varying) == 2:
            pairs = [tuple(varying)]
        for px, py in pairs:
            xs = sorted({sw.num(r, px) for r in rs})
            ys = sorted({sw.num(r, py) for r in rs})
            fig, axes = common.figure(len(metrics), height=2.6, title_lines=1)
            for ax, m in zip(axes, metrics):
                grid = np.full((len(ys), len(xs)), np.nan)
                cnt = np.zeros_like(grid)
                for r in rs:
                    v = sw.num(r, m)
                    if not math.isfinite(v):
                        continue
                    i, j = ys.index(sw.num(r, py)), xs.index(sw.num(r, px))
                    grid[i, j] = v if cnt[i, j] == 0 else grid[i, j] + v
                    cnt[i, j] += 1
                grid = np.where(cnt > 0, grid / np.maximum(cnt, 1), np.nan)  # mean over other axes
                im = ax.imshow(grid, origin="lower", aspect="auto", cmap="viridis" if m in ("fpsnr", "ssim") else "magma")
                ax.set_xticks(range(len(xs)))
                ax.set_xticklabels([f"{x:g}" for x in xs], fontsize=7 if len(xs) <= 8 else 6,
                                   rotation=0 if len(xs) <= 6 else 90)
                ax.set_yticks(range(len(ys)))
                ax.set_yticklabels([f"{y:g}" for y in ys], fontsize=7 if len(ys) <= 12 else 6)
                ax.set_xlabel(px)
                ax.set_ylabel(py)
                ax.set_title(common.wrap(axis_label(m), 40))
                fig.colorbar(im, ax=ax, shrink=0.9)  # unit in the panel title
                if len(xs) <= 6 and len(ys) <= 8:  # cell labels (6 pt) only where they fit
                    lo, hi = np.nanmin(grid), np.nanmax(grid)
                    for i in range(len(ys)):
                        for j in range(len(xs)):
                            if math.isfinite(grid[i, j]):
                                dark = hi > lo and (grid[i, j] - lo) / (hi - lo) < 0.5
                                ax.text(j, i, f"{grid[i, j]:.3g}", ha="center", va="center", fontsize=6,
                                        color="w" if dark else "k")
            fig.suptitle(f"{lab}: {px} x {py}")
            f = f"heatmap_{lab}_{px}_{py}.png"
            common.save(fig, os.path.join(out, f))
            made.append(f)
    if not made:
        raise Skip("no method has two swept parameters among " + ", ".join(PARAMS))
    return made


def cell_frames(sw, cell_id):
    _, rows = common.read_csv(os.path.join(sw.dir, "runs", cell_id, "frames.csv"))
    return rows or []


def selected(sw, limit=8):
    """The Pareto rows, plus the best row (by the quality objective) of every method label
    that has none on the front, so each method shows up; at most `limit`."""
    rows, _ = sw.distinct()
    rs = [r for r in rows if r.get("pareto") == "1"] or list(rows)
    (_, _), (cy, maxy) = sw.objectives()[:2]
    for lab in sw.labels():
        if any(r.get("label") == lab for r in rs):
            continue
        cand = [r for r in rows if r.get("label") == lab and math.isfinite(sw.num(r, cy))]
        if cand:
            rs.append(max(cand, key=lambda r: sw.num(r, cy) if maxy else -sw.num(r, cy)))
    return rs[:limit]


def deg_per_px(sw):
    m = common.read_json(glob.glob(os.path.join(sw.dir, "runs", "*", "manifest.json"))[0]) if glob.glob(
        os.path.join(sw.dir, "runs", "*", "manifest.json")) else None
    d = common.find_display(m) if m else None
    try:
        return float(d["fov_h_deg"]) / float(d["width"])
    except (TypeError, KeyError, ValueError):
        return None


def plot_timelines(sw, out):
    sel = selected(sw)
    if not sel:
        raise Skip("no rows")
    b = sw.budget()
    entries = [sw.row_name(r) for r in sel] + ([f"budget {b:.2f} ms"] if b is not None else []) + \
        ["gaze speed (right axis)"]
    fig, (ax,) = common.figure(1, height=3.0, legend=entries, title_lines=1)
    gaze = None
    sty = sw.row_styles(sel)
    for r in sel:
        fr = [x for x in cell_frames(sw, r.get("cell_id", "")) if x.get("label") == r.get("label")
              and x.get("gpu") == r.get("gpu")]
        if not fr:
            continue
        col, ls, _ = sty[sw.row_name(r)]
        ax.plot([to_float(x["frame"]) for x in fr], [to_float(x["est_ms_total"]) for x in fr], lw=1,
                color=col, ls=ls, label=sw.row_name(r))
        if gaze is None:
            gaze = fr
    if b is not None:
        ax.axhline(b, color="red", ls="--", lw=1.2, label=f"budget {b:.2f} ms")
    ax.set_xlabel("frame [index]")
    ax.set_ylabel("estimated frame time [ms]")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    if gaze and len(gaze) > 1:
        dpp = deg_per_px(sw) or 1.0
        t = np.array([to_float(x["t"]) for x in gaze])
        gx = np.array([to_float(x["gaze_x"]) for x in gaze])
        gy = np.array([to_float(x["gaze_y"]) for x in gaze])
        sp = np.hypot(np.diff(gx), np.diff(gy)) * dpp / np.maximum(np.diff(t), 1e-9)
        ax2 = ax.twinx()
        (gl,) = ax2.plot([to_float(x["frame"]) for x in gaze[1:]], sp, color="0.5", lw=0.8, ls=":",
                         label="gaze speed (right axis)")
        ax.plot([], [], color="0.5", lw=0.8, ls=":", label=gl.get_label())  # in the one legend
        ax2.set_ylabel("gaze speed [deg/s]" if deg_per_px(sw) else "gaze speed [px/s]", color="0.4")
    common.figure_legend(fig, [ax])  # below the axes: never over a line
    ax.set_title(common.wrap("Per-frame estimated time: Pareto configurations and each other method's best; "
                             "gaze speed", 100))
    common.save(fig, os.path.join(out, "timelines.png"))
    return ["timelines.png"]


def plot_profiles(sw, out):
    # Band means only: not their `_ci95` half-widths nor per-phase means (`_saccade`, docs/latency.md).
    bands = [c for c in sw.cols if re.fullmatch(r"rmse_ecc_[0-9p.]+_[0-9p.]+", c)]
    if not bands:
        raise Skip("no rmse_ecc_<a>_<b> columns")

    def mid(c):
        a, b = c[len("rmse_ecc_"):].replace("p", ".").split("_")
        return 0.5 * (float(a) + float(b))

    sel = selected(sw)
    fig, (ax,) = common.figure(1, height=3.0, legend=[sw.row_name(r) for r in sel])
    sty = sw.row_styles(sel)
    for r in sel:
        err = [sw.num(r, c + "_ci95") for c in bands]
        col, ls, mk = sty[sw.row_name(r)]
        ax.errorbar([mid(c) for c in bands], [sw.num(r, c) for c in bands], marker=mk, lw=1, capsize=2, ls=ls,
                    yerr=[e if math.isfinite(e) else 0 for e in err], color=col, label=sw.row_name(r))
    ax.set_xlabel("eccentricity [deg] (band centre)")
    ax.set_ylabel("RMSE [display-encoded, 0–1]")
    ax.set_title("Error vs. eccentricity: Pareto configurations and each other method's best\n"
                 "(error bars: 95% interval)")
    ax.grid(alpha=0.3)
    common.figure_legend(fig, [ax])
    common.save(fig, os.path.join(out, "eccentricity_profiles.png"))
    return ["eccentricity_profiles.png"]


strip_geometry = common.strip_geometry  # kept for tests and callers


def plot_strips(sw, out):
    """Side-by-side strip per cell frame: reference and the cell's selected methods, each with
    the gaze marked, a zoomed inset at the gaze and one in the periphery, and the error map
    (|luma error|, turbo 0–0.25, with its colour bar)."""
    made = []
    cells = list(dict.fromkeys(r.get("cell_id", "") for r in selected(sw, 16)))  # cells of the front
    with_images = [c for c in cells if glob.glob(os.path.join(sw.dir, "runs", c, "images", "frame_*"))]
    if not with_images:
        raise Skip("no cell of the selected configurations wrote images (set outputs.image_frames)")
    if len(with_images) > 4:
        note(f"strips: {len(with_images)} cells with images hold front configurations; strips drawn for "
             "the first 4")
    for cid in with_images[:4]:
        # every method of the cell side by side (Pareto rows first), at most MAX_STRIP_CONFIGS
        rows = [r for r in sw.rows if r.get("cell_id", "") == cid]
        rows.sort(key=lambda r: r.get("pareto") != "1")
        shown = rows[:MAX_STRIP_CONFIGS]
        m = common.read_json(os.path.join(sw.dir, "runs", cid, "manifest.json")) or {}
        disp = common.find_display(m) or {}
        frames_rows = cell_frames(sw, cid)
        for fdir in sorted(glob.glob(os.path.join(sw.dir, "runs", cid, "images", "frame_*")))[:2]:
            ref = os.path.join(fdir, "reference.png")
            if not os.path.exists(ref):
                continue
            frame = fdir.rsplit("_", 1)[-1]
            cols = [("reference", plt.imread(ref), None)]
            for r in shown:
                lab = r.get("label", "")
                img = os.path.join(fdir, lab + ".png")
                if os.path.exists(img):
                    err = os.path.join(fdir, lab + "_error.png")
                    star = " (Pareto)" if r.get("pareto") == "1" else ""
                    cols.append((" ".join(x for x in (lab, sw.params_text(r), star.strip()) if x), plt.imread(img),
                                 plt.imread(err) if os.path.exists(err) else None))
            if len(cols) < 2:
                continue
            h, w = cols[0][1].shape[:2]
            gx, gy = w / 2, h / 2
            fr = [x for x in frames_rows if x.get("frame") == frame]
            if fr and disp.get("width"):
                sc = w / float(disp["width"])
                gx, gy = to_float(fr[0]["gaze_x"]) * sc, to_float(fr[0]["gaze_y"]) * sc
            title = f"cell {cid}, frame {frame}: gaze +"
            if len(rows) > len(shown):
                title += f" ({len(shown)} of {len(rows)} configurations shown)"
            colors = {c[0]: sw.color(r.get("label")) for c, r in zip(cols[1:], [r for r in shown if os.path.exists(
                os.path.join(fdir, r.get("label", "") + ".png"))])}
            fig = common.draw_strip(cols, gx, gy, title, colors)
            f = f"strip_{cid}_{frame}.png"
            common.save(fig, os.path.join(out, f))
            made.append(f)
    if not made:
        raise Skip("no cell wrote images (set outputs.image_frames)")
    return made


def plot_latency(sw, out):
    # Quality vs latency per method (docs/latency.md), only for sweeps with a latency block.
    import latency  # noqa: E402  (viz/latency.py)
    try:
        return [latency.plot_latency(sw.dir, out, "rmse_fovea", report=log)]
    except latency.NoLatency as e:
        raise Skip(str(e))


PLOTS = [("Pareto front", plot_pareto),
         ("Quality vs. frame budget", plot_quality_vs_budget),
         ("Heat maps", plot_heatmaps),
         ("Timelines with budget and gaze speed", plot_timelines),
         ("Error vs. eccentricity", plot_profiles),
         ("Image strips with zoomed insets", plot_strips),
         ("Foveal quality vs latency", plot_latency)]


def csv_table(path, limit=60, first=(), all_columns=False):
    """HTML table: the `first` columns (keys, axes, objectives), then the others (up to 24 in
    all unless all_columns; wall-clock timing columns left out). limit=None: every row."""
    cols, rows = common.read_csv(path)
    if not cols:
        return ""
    lead = [c for c in first if c in cols]
    keep = lead + [c for c in cols if c not in TIMING and c not in lead]
    if not all_columns:
        keep = keep[:max(24, len(lead))]
    if limit is None:
        limit = len(rows)
    h = ["<table border=1 cellspacing=0 cellpadding=2 style='font-size:11px'><tr>"]
    h += [f"<th>{html.escape(c)}</th>" for c in keep] + ["</tr>"]
    for r in rows[:limit]:
        h.append("<tr>" + "".join(f"<td>{html.escape(r.get(c, ''))}</td>" for c in keep) + "</tr>")
    h.append("</table>")
    if len(rows) > limit:
        h.append(f"<p>({len(rows) - limit} more rows in the CSV)</p>")
    return "".join(h)


def write_index(sw, out, made, skipped):
    name = sw.meta.get("name") or os.path.basename(os.path.normpath(sw.dir))
    p = ["<!DOCTYPE html><html><head><meta charset='utf-8'>",
         f"<title>fovsim sweep: {html.escape(name)}</title>",
         "<style>body{font-family:sans-serif;margin:2em}img{max-width:100%;border:1px solid #ccc}</style></head><body>",
         f"<h1>fovsim sweep: {html.escape(name)}</h1>",
         f"<p>{sw.meta.get('cells', '?')} cells, {len(sw.rows)} configurations; axes: "
         f"{html.escape(', '.join(sw.meta.get('axes', [])))}</p><h2>Tables</h2><ul>"]
    for t in ("summary.csv", "pareto.csv", "iso_budget.csv", "search_best.csv", "search_history.csv", "sweep.json"):
        if os.path.exists(os.path.join(sw.dir, t)):
            p.append(f"<li><a href='../{t}'>{t}</a></li>")
    p.append("</ul><h2>Plots</h2><ul>")
    p += [f"<li><a href='#{f}'>{html.escape(t)}: {f}</a></li>" for t, f in made]
    p.append("</ul>")
    for t in ("iso_budget.csv", "pareto.csv"):
        if os.path.exists(os.path.join(sw.dir, t)):
            lead = ["config_id", "label", "gpu"] + sw.axes_cols()
            for o, _ in sw.objectives():
                lead += [o, o + "_ci95"]
            full = t == "pareto.csv"  # the whole Pareto table: every row and column
            p.append(f"<h2>{t}</h2><div style='overflow-x:auto'>" +
                     csv_table(os.path.join(sw.dir, t), limit=None if full else 60, first=lead + ["pareto"],
                               all_columns=full) + "</div>")
    for t, f in made:
        p.append(f"<h3 id='{f}'>{html.escape(t)}: {f}</h3><a href='{f}'><img src='{f}'></a>")
    if NOTES:
        p.append("<h2>Notes</h2><ul>" + "".join(f"<li>{html.escape(n)}</li>" for n in NOTES) + "</ul>")
    if skipped:
        p.append("<h2>Skipped</h2><ul>" + "".join(f"<li>{html.escape(t)}: {html.escape(r)}</li>" for t, r in skipped)
                 + "</ul>")
    p.append("<h2>Cells</h2><ul>")
    for d in sorted(glob.glob(os.path.join(sw.dir, "runs", "*"))):
        c = os.path.basename(d)
        p.append(f"<li><a href='../runs/{c}/'>{c}</a></li>")
    p.append("</ul></body></html>\n")
    common.write_text_atomic(os.path.join(out, "index.html"), "\n".join(p))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("sweep_dir", help="results/<name> with summary.csv and sweep_summary.json")
    ap.add_argument("--out", help="output directory (default: SWEEP_DIR/plots)")
    common.add_output_args(ap)
    a = ap.parse_args(argv)
    common.set_output(a)
    sw = Sweep(a.sweep_dir)
    if a.configs:  # --configs: only these labels (every plot, strips included)
        labels = list(dict.fromkeys(r.get("label", "") for r in sw.rows))
        keep = set(common.pick_configs(labels, a.configs, "label"))
        sw.rows = [r for r in sw.rows if r.get("label", "") in keep]
    if not sw.rows:
        print(f"plot_sweep: error: {a.sweep_dir}: no summary.csv rows (run fovsim merge first?)", file=sys.stderr)
        return 2
    out = a.out or os.path.join(a.sweep_dir, "plots")
    os.makedirs(out, exist_ok=True)
    made, skipped = [], []
    for title, fn in PLOTS:
        try:
            for f in fn(sw, out):
                made.append((title, f))
        except Skip as e:
            skipped.append((title, str(e)))
        except Exception as e:  # a plot must never hide the others
            skipped.append((title, f"failed: {e!r}"))
    write_index(sw, out, made, skipped)
    log(f"wrote {os.path.join(out, 'index.html')} ({len(made)} plots, {len(skipped)} skipped)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
