"""Shared helpers for fovsim's plotting scripts (Debian python3 + numpy + matplotlib).

CSV values follow results/README.md: numbers written with %.10g, `inf`/`nan` spelled so,
empty cells for parameters a method does not have.
"""
import csv
import json
import math
import os

import matplotlib

matplotlib.use("Agg")  # no display needed; must precede pyplot imports
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.transforms  # noqa: E402,F401  (place_labels)


def log(msg):
    print(f"plot: {msg}", flush=True)


def to_float(s):
    """Parses a CSV cell; empty or non-numeric cells become NaN."""
    if s is None:
        return math.nan
    s = s.strip()
    if not s:
        return math.nan
    try:
        return float(s)
    except ValueError:
        return math.nan


def read_csv(path):
    """Returns (columns, rows) with rows as dicts of raw strings, or (None, None) if absent."""
    if not os.path.exists(path):
        return None, None
    with open(path, newline="") as f:
        r = csv.DictReader(f)
        rows = list(r)
        return (r.fieldnames or []), rows


def read_json(path):
    if not os.path.exists(path):
        return None
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        log(f"cannot read {path}: {e}")
        return None


def finite_mean(values):
    v = [x for x in values if math.isfinite(x)]
    return sum(v) / len(v) if v else math.nan


def find_display(manifest):
    """The display object of a manifest: top level "display", else inside "resolved"/"config"."""
    if not isinstance(manifest, dict):
        return None
    for holder in (manifest, manifest.get("resolved"), manifest.get("config")):
        if isinstance(holder, dict) and isinstance(holder.get("display"), dict):
            return holder["display"]
    return None


def budget_ms(manifest, summary_rows=None):
    """Frame budget 1000 / display.refresh_hz from the manifest, else summary.csv's budget_ms."""
    d = find_display(manifest)
    if d is not None:
        hz = d.get("refresh_hz")
        if isinstance(hz, (int, float)) and hz > 0:
            return 1000.0 / hz
    for row in summary_rows or []:
        b = to_float(row.get("budget_ms"))
        if math.isfinite(b) and b > 0:
            return b
    return None


def fit_rule(summary_rows):
    """The run's budget decision (docs/cost_model.md "Budget decisions"): (level, fraction) where a
    configuration fits a budget B at p_fit >= level when its estimate <= fraction * B
    (summary.csv's fit_threshold_ms / budget_ms, the same for every budget), from the first row
    that has them; None for results without the columns, or with no interval (fraction 1)."""
    for row in summary_rows or []:
        t, b, lv = to_float(row.get("fit_threshold_ms")), to_float(row.get("budget_ms")), to_float(row.get("fit_level"))
        if math.isfinite(t) and math.isfinite(b) and b > 0 and math.isfinite(lv):
            f = t / b
            return (lv, f) if f < 1 - 1e-9 else None
    return None


def pareto_front(points):
    """Indices of the non-dominated points for (cost to minimise, quality to maximise),
    ordered by increasing cost."""
    idx = [i for i, (c, q) in enumerate(points) if math.isfinite(c) and math.isfinite(q)]
    idx.sort(key=lambda i: (points[i][0], -points[i][1]))
    front, best = [], -math.inf
    for i in idx:
        if points[i][1] > best:
            front.append(i)
            best = points[i][1]
    return front


# One colour per method, the same in every plot of every script (run, sweep, latency, video),
# derived from the C++ registration order (sim/foveation/method_list.h, through `fovsim info
# --json`): method i of the list gets PALETTE[i] (the first, `full`, black). No per-method table
# here: a new method gets the next colour. Names the list does not hold (no binary, or a label
# whose method is unknown) take the colours after the list's, in order of first use (stable
# within a process). The reference image is grey.
PALETTE = ["#000000", "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
           "#bcbd22", "#17becf", "#aec7e8", "#ffbb78", "#98df8a", "#ff9896", "#c5b0d5", "#c49c94",
           "#f7b6d2", "#dbdb8d", "#9edae5"]
REFERENCE_COLOR = "#7f7f7f"
_extra_used = {}


def method_color(method):
    """Colour of a method (factory name; a label `kfr_s2` or `kfr@gpu` falls back to its
    method prefix when the row's method is unknown): by its place in `fovsim info --json`'s
    method list, so it keeps that colour in every plot and every process."""
    m = (method or "").strip()
    if m == "reference":
        return REFERENCE_COLOR
    names = method_names()
    for sep in ("", "@", ":", " "):
        base = m.split(sep)[0] if sep else m
        if base in names:
            return PALETTE[names.index(base) % len(PALETTE)]
    if m not in _extra_used:
        _extra_used[m] = PALETTE[(len(names) + len(_extra_used)) % len(PALETTE)]
    return _extra_used[m]


LINESTYLES = ["-", "--", ":", "-."]
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*", "<", ">", "h"]


def variant_styles(keys_methods):
    """{key: (colour, linestyle, marker)} for configurations given as [(key, method)] in order:
    the colour is the method's (method_color); the 2nd, 3rd, ... configuration of the same
    method gets the next line style and marker, so configurations stay apart."""
    out, count = {}, {}
    for key, meth in keys_methods:
        if key in out:
            continue
        k = count.get(meth, 0)
        count[meth] = k + 1
        out[key] = (method_color(meth), LINESTYLES[k % len(LINESTYLES)], MARKERS[k % len(MARKERS)])
    return out


def column_units():
    """{column: {"label", "unit"}} of the non-metric result columns, as the C++ declares them
    (sim/experiment/info.h result_column_decls, through `fovsim info --json`); {} without a
    binary. Metrics carry their own labels (the registry, metric_label)."""
    return fovsim_info().get("columns") or {}


# The metric registry of the C++ (sim/metrics/registry.h): name, unit, label, better direction,
# pooling, headline. Read from what the C++ wrote, never copied here: a run's manifest.json
# ("metrics"), else `fovsim info --json` of the build beside this repository (FOVSIM_BINARY
# overrides the binary).
_REGISTRY = {}


def set_metric_registry(decls):
    """Installs the registry from a list of declarations (manifest.json "metrics")."""
    global _REGISTRY
    if isinstance(decls, list) and decls:
        _REGISTRY = {d["name"]: d for d in decls if isinstance(d, dict) and "name" in d}


def load_metric_registry(manifest=None):
    """The registry of `manifest` (a dict or a run folder), else of `fovsim info --json`.
    Returns {name: declaration}; {} when neither is available (labels are then plain names)."""
    if isinstance(manifest, str):
        manifest = read_json(os.path.join(manifest, "manifest.json"))
    if isinstance(manifest, dict) and manifest.get("metrics"):
        set_metric_registry(manifest["metrics"])
        return _REGISTRY
    if not _REGISTRY and fovsim_info().get("metrics"):
        set_metric_registry(fovsim_info()["metrics"])
    return _REGISTRY


_INFO = None


def fovsim_info():
    """`fovsim info --json` of the build beside this repository (FOVSIM_BINARY overrides the
    binary), read once: the method list, the metric registry, the CPU code paths. {} without a
    binary."""
    global _INFO
    if _INFO is None:
        import subprocess
        here = os.path.dirname(os.path.abspath(__file__))
        binary = os.environ.get("FOVSIM_BINARY") or os.path.join(here, "..", "build", "fovsim")
        try:
            out = subprocess.run([binary, "info", "--json"], capture_output=True, text=True,
                                 timeout=30, check=True).stdout
            _INFO = json.loads(out)
        except (OSError, ValueError, subprocess.SubprocessError):
            _INFO = {}
    return _INFO


def method_names():
    """The registered methods in registration order (sim/foveation/method_list.h, through
    `fovsim info --json`); [] without a binary."""
    return list(fovsim_info().get("methods") or [])


FL_SUFFIX = "_fl"  # against full at the method's sampling rate (registry.h kFoveationLossSuffix)


def metric_decl(col):
    """The registry declaration of a column (exact, pooled column, or family prefix, each with an
    optional foveation-loss suffix "_fl"), or None."""
    reg = _REGISTRY or load_metric_registry()
    if col.endswith(FL_SUFFIX) and col[:-len(FL_SUFFIX)]:
        d = metric_decl(col[:-len(FL_SUFFIX)])
        if d is not None:
            return d
    for d in reg.values():
        if d.get("family") and col.startswith(d["name"]) and len(col) > len(d["name"]):
            return d
        if col == d["name"] or (d.get("pooled_column") and col == d["pooled_column"]):
            return d
    return None


def higher_is_better(col):
    """Direction of a column: the registry's for metrics, lower-is-better for costs and counts."""
    d = metric_decl(col)
    if d is None:
        return False
    base = col[:-len(FL_SUFFIX)] if col.endswith(FL_SUFFIX) and col != d["name"] else col
    if d.get("pooled_column") == base and base != d["name"]:
        return d.get("better") != "higher"  # FovVideoVDP's Q: larger Q, lower JOD
    return d.get("better") == "higher"


def headline_metrics(available=None, with_fl=True):
    """The registry's headline metrics in its order, then the foveation-loss columns it shows
    (`<name>_fl`, show_fl), restricted to `available` columns."""
    reg = _REGISTRY or load_metric_registry()
    names = [d["name"] for d in reg.values() if d.get("headline")]
    if with_fl:
        names += [d["name"] + FL_SUFFIX for d in reg.values() if d.get("headline") and d.get("show_fl")]
    return [n for n in names if available is None or n in available]


def metric_families():
    """The registry's column families (prefixes such as rmse_ecc_, flip_ecc_), in its order."""
    reg = _REGISTRY or load_metric_registry()
    return [d["name"] for d in reg.values() if d.get("family")]


def metric_label(col):
    """Axis label of a results column with its unit (results/README.md), e.g. "FPSNR [dB]"."""
    c = column_units().get(col)
    if c:
        return f"{c['label']} [{c['unit']}]"
    d = metric_decl(col)
    if d is not None and not d.get("family") and col == d["name"]:
        return d.get("label") or col
    if d is not None and not d.get("family") and col == d["name"] + FL_SUFFIX:
        return (d.get("label") or d["name"]) + " vs. full at the same sampling"
    if col.startswith("est_ms_"):
        return f"estimated time of pass {col[len('est_ms_'):]} [ms]"
    if col.startswith("rmse_ecc_"):
        return f"RMSE in band {col[len('rmse_ecc_'):].replace('_', '–').replace('p', '.')}° [0–1]"
    if col.startswith("flip_ecc_"):
        return f"LDR-FLIP in band {col[len('flip_ecc_'):].replace('_', '–').replace('p', '.')}° [0–1]"
    if col.startswith("rmse_"):
        return f"{col} [RMSE, 0–1]"
    return col


def config_color(i):
    """Deprecated: colour by position. Use method_color (one palette keyed by method)."""
    return f"C{i % 10}"


def dedup_legend(ax, **kw):
    """Legend with one entry per label (first handle wins)."""
    handles, labels = ax.get_legend_handles_labels()
    seen, hs, ls = set(), [], []
    for h, lab in zip(handles, labels):
        if lab in seen or lab.startswith("_"):
            continue
        seen.add(lab)
        hs.append(h)
        ls.append(lab)
    if hs:
        ax.legend(hs, ls, **kw)


def plain_log_x(ax):
    """Log-scaled x axis with plain tick labels (10, 20, 50 ms; not 2×10¹)."""
    from matplotlib import ticker

    ax.set_xscale("log")
    ax.xaxis.set_major_locator(ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
    ax.xaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    ax.xaxis.set_minor_formatter(ticker.NullFormatter())


def draw_quality_vs_budget(ax, entries, metric, budget=None, rule=None):
    """Quality vs. budget on `ax`: entries = [(method, name, mean cost [ms], mean quality[,
    95% half-width of the quality])]; the half-widths (when finite) are error bars on the steps.
    For a budget B on the x axis, each method's step line is the best quality among its
    configurations that fit B (starts at its cheapest configuration); the black line is the
    best over all methods. Non-finite entries (fpsnr inf for `full`) are named, not drawn.
    `rule` = fit_rule(summary): a configuration fits B when its cost <= fraction * B (p_fit >=
    level), so each is drawn at the budget it needs, cost / fraction; without it, at its cost.
    Returns the names not drawn."""
    higher = higher_is_better(metric)
    if rule:
        entries = [(e[0], e[1], e[2] / rule[1]) + tuple(e[3:]) for e in entries]
    ok = [e for e in entries if math.isfinite(e[2]) and math.isfinite(e[3])]
    bad = [e[1] for e in entries if e not in ok]
    if not ok:
        ax.text(0.5, 0.5, "no finite values", transform=ax.transAxes, ha="center")
        return bad
    costs = [e[2] for e in entries if math.isfinite(e[2])]  # every configuration, same x range in every panel
    xmax = max(costs + ([budget] if budget else [])) * 1.15
    xmin = min(costs + ([budget] if budget else [])) * 0.95

    def staircase(es, with_ci=False):
        es = sorted(es, key=lambda e: e[2])
        xs, ys, cis, best = [], [], [], None
        for e in es:
            if best is None or (e[3] > best if higher else e[3] < best):
                best = e[3]
                xs.append(e[2])
                ys.append(best)
                ci = e[4] if len(e) > 4 else math.nan
                cis.append(ci if math.isfinite(ci) else 0.0)
        if with_ci:
            return xs + [xmax], ys + [ys[-1]], cis
        return xs + [xmax], ys + [ys[-1]]

    methods = list(dict.fromkeys(e[0] for e in ok))
    for meth in methods:
        xs, ys, cis = staircase([e for e in ok if e[0] == meth], with_ci=True)
        ax.step(xs, ys, where="post", color=method_color(meth), lw=1.4, label=meth)
        ax.errorbar(xs[:-1], ys[:-1], yerr=cis, fmt="o", color=method_color(meth), ms=4, capsize=2, lw=1)
    xs, ys = staircase(ok)
    ax.step(xs, ys, where="post", color="k", lw=2.5, alpha=0.25, label="best of all methods", zorder=1)
    if budget:
        ax.axvline(budget, color="red", ls="--", lw=1, label=f"display budget {budget:.2f} ms")
    ax.set_xlim(xmin, xmax)
    logx = xmax > 4 * xmin  # a wide range (flc's indirect light next to the others): log scale
    if logx:
        plain_log_x(ax)
    fits = (f"that fit B at p_fit ≥ {rule[0]:g}: mean estimated frame time ≤ {rule[1]:.3f} B" if rule
            else "with mean estimated frame time ≤ B")
    ax.set_xlabel(wrap("frame budget B [ms" + (", log scale" if logx else "") + "] (configurations " + fits + ")",
                       46))
    ax.set_ylabel(wrap(f"best mean {metric_label(metric)}", 34))
    title = metric + (" (higher is better)" if higher else " (lower is better)")
    if bad:  # in the title, where it cannot run into the data or the tick labels
        title += "\nnot drawn (no finite mean): " + ", ".join(short(b) for b in bad[:3]) + (" …" if len(bad) > 3 else "")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    return bad


def clamp_box(cx, cy, half, w, h):
    """Square crop of half-size `half` centred near (cx, cy), moved (not cut) to lie inside a
    w×h image; returns integer (x0, y0, x1, y1) with x1 - x0 == y1 - y0 == min(2*half, w, h)."""
    size = int(min(2 * half, w, h))
    x0 = int(round(cx - size / 2))
    y0 = int(round(cy - size / 2))
    x0 = max(0, min(x0, w - size))
    y0 = max(0, min(y0, h - size))
    return x0, y0, x0 + size, y0 + size


def strip_geometry(w, h, gx, gy, ref=None):
    """Inset boxes (x0, y0, x1, y1), clamped inside the w×h image: one centred on the gaze, one
    in the periphery. Without `ref` the periphery box is the candidate (edge middles, corners)
    farthest from the gaze; with the reference image, the candidate with the most detail (mean
    absolute luma gradient: texture and edges, where foveation error shows) among those whose
    box does not overlap the gaze box and lies at least a third of the image from the gaze
    (else the farthest)."""
    half = max(8, min(w, h) // 6)
    fov = clamp_box(gx, gy, half, w, h)
    cands = [(w * 0.12, h * 0.5), (w * 0.88, h * 0.5), (w * 0.5, h * 0.12), (w * 0.5, h * 0.88),
             (w * 0.15, h * 0.15), (w * 0.85, h * 0.15), (w * 0.15, h * 0.85), (w * 0.85, h * 0.85)]

    def dist2(c):
        return (c[0] - gx) ** 2 + (c[1] - gy) ** 2

    far = max(cands, key=dist2)
    best = far
    if ref is not None:
        import numpy as np

        lum = np.asarray(ref, dtype=float)
        lum = lum[..., :3].mean(axis=2) if lum.ndim == 3 else lum

        def overlaps(b):
            return not (b[2] <= fov[0] or b[0] >= fov[2] or b[3] <= fov[1] or b[1] >= fov[3])

        ok = []
        for c in cands:
            b = clamp_box(c[0], c[1], half, w, h)
            if not overlaps(b) and dist2(c) >= (min(w, h) / 3.0) ** 2:
                patch = lum[b[1]:b[3], b[0]:b[2]]
                detail = float(np.abs(np.diff(patch, axis=0)).mean() + np.abs(np.diff(patch, axis=1)).mean())
                ok.append((detail, -dist2(c), c))
        if ok:
            best = max(ok)[2]
    per = clamp_box(best[0], best[1], half, w, h)
    return fov, per


def draw_strip(cols, gx, gy, title, colors=None):
    """Side-by-side strip: cols = [(name, image, error image or None)], the first usually the
    reference. Row 1: images with the gaze (red +; a gaze off the screen is drawn at the edge as
    a red x and said in the title), a green box at the gaze and an orange box in the periphery
    (both inside the image); rows 2-3: those boxes zoomed (the gaze marked in the first); row 4
    (when any error image): the error maps with a colour bar (|luma error|, turbo 0–0.25).
    `colors` {name: colour} colours the column titles (the method's colour). Returns the figure."""
    from matplotlib import cm, colors as mcolors

    h, w = cols[0][1].shape[:2]
    (fx0, fy0, fx1, fy1), (px0, py0, px1, py1) = strip_geometry(w, h, gx, gy, cols[0][1])
    off = not (0 <= gx < w and 0 <= gy < h)
    mx, my = min(max(gx, 0), w - 1), min(max(gy, 0), h - 1)
    has_err = any(c[2] is not None for c in cols)
    nrow = 4 if has_err else 3
    # The page width whatever the number of columns: narrower columns, titles wrapped to fit.
    colw = min(PAGE_WIDTH_IN / len(cols), 2.4)
    chars = max(8, int(colw * 72 / (0.55 * 6.5)))
    fig, axes = plt.subplots(nrow, len(cols), figsize=(colw * len(cols), (colw * h / w + 0.35) * nrow + 0.5),
                             squeeze=False, layout="constrained")
    for k, (name, im, err) in enumerate(cols):
        a = axes[0][k]
        a.imshow(im)
        a.add_patch(plt.Rectangle((fx0 - 0.5, fy0 - 0.5), fx1 - fx0, fy1 - fy0, fill=False, ec="lime", lw=1.2))
        a.add_patch(plt.Rectangle((px0 - 0.5, py0 - 0.5), px1 - px0, py1 - py0, fill=False, ec="orange", lw=1.2))
        a.plot([mx], [my], marker="x" if off else "+", color="red", ms=8, mew=1.5)
        a.set_xlim(-0.5, w - 0.5)  # the image, nothing around it
        a.set_ylim(h - 0.5, -0.5)
        a.set_title(wrap(name, chars), fontsize=6.5, color=(colors or {}).get(name, "k"))
        z = axes[1][k]
        z.imshow(im[fy0:fy1, fx0:fx1], interpolation="nearest")
        if not off:
            z.plot([gx - fx0], [gy - fy0], marker="+", color="red", ms=10, mew=1.5)
            z.set_xlim(-0.5, fx1 - fx0 - 0.5)
            z.set_ylim(fy1 - fy0 - 0.5, -0.5)
        z.set_title("gaze (green)", fontsize=6)
        axes[2][k].imshow(im[py0:py1, px0:px1], interpolation="nearest")
        axes[2][k].set_title("periphery (orange)", fontsize=6)
        if has_err:
            if err is not None:
                axes[3][k].imshow(err)
                axes[3][k].set_title("|luma error|", fontsize=6)
            axes[3][k].axis("off")
        for a in (axes[0][k], axes[1][k], axes[2][k]):
            a.set_xticks([])
            a.set_yticks([])
    if has_err:  # colour bar in the reference's (empty) error slot, so columns stay aligned
        sm = cm.ScalarMappable(norm=mcolors.Normalize(0, 0.25), cmap="turbo")
        cax = axes[3][0].inset_axes([0.55, 0.05, 0.1, 0.9])
        cb = fig.colorbar(sm, cax=cax)
        cb.ax.tick_params(labelsize=5)
        axes[3][0].text(0.3, 0.5, "|luma error|", rotation=90, ha="center", va="center", fontsize=6,
                        transform=axes[3][0].transAxes)
    fig.suptitle(wrap(title + (" (gaze off the screen: x at the nearest edge)" if off else ""), 100), fontsize=8)
    return fig


# Figure output of every plot script (--format, --dpi): the PNG that index.html shows is always
# written; --format pdf|svg writes the same figure next to it as PDF/SVG (vector: for a paper).
OUTPUT = {"format": "png", "dpi": 110}
FORMATS = ("png", "pdf", "svg")

# Layout for a paper: every figure is PAGE_WIDTH_IN wide (a two-column paper's text width, the
# IEEE and ACM templates' 7 in; COLUMN_WIDTH_IN for one column) at any --dpi, panels in a grid
# of at most MAX_COLUMNS columns, fonts of 7-9 pt, legends below the panels (never over the
# data), long labels wrapped or shortened. `figure()` builds the grid, `legend_below()` fills
# its legend row, `place_labels()` labels points without collisions, and `layout_problems()`
# (python/tests/test_viz.py) checks a drawn figure: no text outside the canvas, no two texts
# overlapping.
PAGE_WIDTH_IN = 7.0
COLUMN_WIDTH_IN = 3.5
PANEL_HEIGHT_IN = 2.5
MAX_COLUMNS = 2
matplotlib.rcParams.update({"font.size": 8, "axes.titlesize": 8, "axes.labelsize": 8, "xtick.labelsize": 7,
                            "ytick.labelsize": 7, "legend.fontsize": 7, "figure.titlesize": 9,
                            "legend.title_fontsize": 7})
_LEGEND_FONT_IN = 7 / 72.0  # legend.fontsize in inches


def wrap(text, width=90):
    """`text` broken into lines of at most `width` characters (a title or axis label that would
    run past its panel)."""
    import textwrap

    if not text:
        return text
    return "\n".join(w for line in text.split("\n") for w in (textwrap.wrap(line, width) or [""]))


def short(text, n=18):
    """`text` cut to at most `n` characters with an ellipsis (tick labels of long config names)."""
    text = str(text)
    return text if len(text) <= n else text[:n - 1] + "…"


def _legend_geometry(labels, width):
    """(columns, rows) of a legend of `labels` that fits `width` inches."""
    if not labels:
        return 1, 0
    colw = max(len(str(lab)) for lab in labels) * 0.62 * _LEGEND_FONT_IN + 0.45  # text + handle + gaps
    ncol = max(1, min(len(labels), int((width - 0.2) // colw)))
    return ncol, math.ceil(len(labels) / ncol)


def figure(n, ncols=None, height=PANEL_HEIGHT_IN, width=PAGE_WIDTH_IN, legend=None, sharex=False, sharey=False,
           title_lines=0):
    """A figure `width` inches wide with `n` panels in a grid of `ncols` (default
    min(n, MAX_COLUMNS)) columns, each panel `height` inches high, constrained layout, and (with
    `legend`, the labels the legend will hold) a legend row below the panels sized for them.
    Returns (fig, [axes] in reading order)."""
    ncols = max(1, min(ncols or MAX_COLUMNS, n))
    nrows = math.ceil(n / ncols)
    lcol, lrows = _legend_geometry(legend or [], width)
    leg_h = (lrows * 1.45 * _LEGEND_FONT_IN + 0.12) if lrows else 0.0
    fig = plt.figure(figsize=(width, height * nrows + leg_h + 0.2 * title_lines), layout="constrained")
    ratios = [height] * nrows + ([leg_h] if lrows else [])
    gs = fig.add_gridspec(len(ratios), ncols, height_ratios=ratios)
    axes = []
    for i in range(n):
        kw = {}
        if sharex and axes:
            kw["sharex"] = axes[0]
        if sharey and axes:
            kw["sharey"] = axes[0]
        axes.append(fig.add_subplot(gs[i // ncols, i % ncols], **kw))
    if sharex:  # tick labels only on each column's bottom panel
        for i, a in enumerate(axes):
            if i + ncols < n:
                a.tick_params(labelbottom=False)
    if sharey:
        for i, a in enumerate(axes):
            if i % ncols:
                a.tick_params(labelleft=False)
    if lrows:
        lax = fig.add_subplot(gs[nrows, :])
        lax.axis("off")
        fig._fovsim_legend = (lax, lcol)
    return fig, axes


def legend_below(fig, handles, labels, title=None):
    """The figure's legend in the row `figure(legend=...)` reserved below the panels (one entry per
    label, first handle wins); without that row, nothing is drawn."""
    slot = getattr(fig, "_fovsim_legend", None)
    if slot is None:
        return None
    seen, hs, ls = set(), [], []
    for h, lab in zip(handles, labels):
        if lab in seen or str(lab).startswith("_"):
            continue
        seen.add(lab)
        hs.append(h)
        ls.append(lab)
    if not hs:
        return None
    lax, ncol = slot
    return lax.legend(hs, ls, loc="center", ncol=min(ncol, len(hs)), frameon=False, title=title,
                      borderaxespad=0, handlelength=1.8, columnspacing=1.0, borderpad=0.1)


def figure_legend(fig, axes):
    """legend_below() with the entries of every panel of `axes` (one per label)."""
    hs, ls = [], []
    for a in axes:
        h, lab = a.get_legend_handles_labels()
        hs += h
        ls += lab
    return legend_below(fig, hs, ls)


def legend_labels(axes_entries):
    """The distinct labels, in order, of an iterable of labels (what figure(legend=...) sizes for)."""
    return list(dict.fromkeys(str(x) for x in axes_entries if not str(x).startswith("_")))


def place_labels(ax, points, fontsize=6):
    """Labels points without collisions: points = [(x, y, text)] in data coordinates. Each label
    tries eight positions around its point and takes the first that overlaps no label placed so
    far, no marker and stays inside the axes; a label with no free position is left out. The
    figure's layout is fixed first (drawn once), so positions in pixels are final. Returns the
    texts left out."""
    fig = ax.figure
    fig.canvas.draw()
    fig.set_layout_engine(None)  # freeze the constrained layout: pixel positions are final
    fig._fovsim_fixed = True
    r = fig.canvas.get_renderer()
    box = ax.get_window_extent(r)
    taken = []
    for x, y, _ in points:
        if math.isfinite(x) and math.isfinite(y):
            px, py = ax.transData.transform((x, y))
            taken.append(matplotlib.transforms.Bbox([[px - 4, py - 4], [px + 4, py + 4]]))
    dropped = []
    offsets = [(4, 3, "left", "bottom"), (-4, 3, "right", "bottom"), (4, -3, "left", "top"),
               (-4, -3, "right", "top"), (0, 6, "center", "bottom"), (0, -6, "center", "top"),
               (6, 0, "left", "center"), (-6, 0, "right", "center")]
    for x, y, text in points:
        if not (math.isfinite(x) and math.isfinite(y)):
            continue
        ok = False
        for dx, dy, ha, va in offsets:
            t = ax.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points", fontsize=fontsize,
                            ha=ha, va=va, color="0.2", annotation_clip=False)
            bb = t.get_window_extent(r)
            inside = bb.x0 >= box.x0 and bb.x1 <= box.x1 and bb.y0 >= box.y0 and bb.y1 <= box.y1
            if inside and not any(bb.overlaps(o) for o in taken):
                taken.append(bb)
                ok = True
                break
            t.remove()
        if not ok:
            dropped.append(text)
    return dropped


def _drawn_texts(fig):
    """The non-empty texts a draw of `fig` renders, with the renderer."""
    from matplotlib.text import Text

    drawn, orig = [], Text.draw

    def record(self, renderer):
        orig(self, renderer)
        if self.get_visible() and self.get_text().strip():
            drawn.append(self)

    Text.draw = record
    try:
        fig.canvas.draw()
    finally:
        Text.draw = orig
    return drawn, fig.canvas.get_renderer()


def layout_problems(fig, tol=1.0):
    """What is wrong with the layout of `fig` as drawn: texts that extend outside the canvas and
    pairs of texts whose boxes overlap (by more than `tol` pixels both ways). [] when none."""
    texts, r = _drawn_texts(fig)
    W, H = fig.bbox.width, fig.bbox.height
    out, boxes = [], []
    for t in texts:
        bb = t.get_window_extent(r)
        boxes.append(bb)
        if bb.x0 < -tol or bb.y0 < -tol or bb.x1 > W + tol or bb.y1 > H + tol:
            out.append(f"outside the {W:.0f}x{H:.0f} canvas: {t.get_text()!r} at "
                       f"[{bb.x0:.0f}, {bb.x1:.0f}]x[{bb.y0:.0f}, {bb.y1:.0f}]")
    for i in range(len(texts)):
        for j in range(i + 1, len(texts)):
            a, b = boxes[i], boxes[j]
            if min(a.x1, b.x1) - max(a.x0, b.x0) > tol and min(a.y1, b.y1) - max(a.y0, b.y0) > tol:
                out.append(f"overlap: {texts[i].get_text()!r} and {texts[j].get_text()!r}")
    return out


def figure_name(stem):
    """The file name of figure `stem` in the chosen --format (the PNG is written always)."""
    return stem + ".png"


def add_output_args(ap, configs=True):
    """--format, --dpi (and --configs), shared by every plot script."""
    ap.add_argument("--format", choices=FORMATS, default="png",
                    help="also write every figure as PDF or SVG next to its PNG (default: png only)")
    ap.add_argument("--dpi", type=float, default=110, help="resolution of raster output (default 110; "
                    f"figures are {PAGE_WIDTH_IN:g} in wide, so 300 gives {PAGE_WIDTH_IN * 300:.0f} px)")
    if configs:
        ap.add_argument("--configs", help="comma-separated configurations (labels / config ids) to draw, "
                        "in this order (default: all)")


def set_output(a):
    if not (a.dpi > 0 and a.dpi <= 2400):
        raise SystemExit(f"--dpi {a.dpi}: expected a number in (0, 2400]")
    OUTPUT["format"], OUTPUT["dpi"] = a.format, a.dpi


def pick_configs(available, spec, what="configuration"):
    """The configurations named by --configs (comma-separated), in that order; an unknown name is an
    error listing the available ones."""
    if not spec:
        return list(available)
    want = [s.strip() for s in spec.split(",") if s.strip()]
    bad = [w for w in want if w not in available]
    if bad:
        raise SystemExit(f"--configs: unknown {what} {', '.join(bad)} (available: {', '.join(available)})")
    return want


def save(fig, path):
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    paths = [path]
    if OUTPUT["format"] != "png":
        paths.append(os.path.splitext(path)[0] + "." + OUTPUT["format"])
    for p in paths:
        tmp = os.path.join(os.path.dirname(p) or ".", ".tmp.%d.%s" % (os.getpid(), os.path.basename(p)))
        # A figure with a layout engine (figure()) keeps its size: PAGE_WIDTH_IN at any dpi.
        tight = {} if fig.get_layout_engine() is not None or getattr(fig, "_fovsim_fixed", False) else \
            {"bbox_inches": "tight"}
        fig.savefig(tmp, dpi=OUTPUT["dpi"], format=os.path.splitext(p)[1][1:], **tight)
        os.replace(tmp, p)  # atomic, like every fovsim output
    plt.close(fig)


def write_text_atomic(path, text):
    tmp = os.path.join(os.path.dirname(path) or ".", ".tmp.%d.%s" % (os.getpid(), os.path.basename(path)))
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)
