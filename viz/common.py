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


def config_color(i):
    """Colour of the i-th configuration (order of first appearance), shared by every plot."""
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


def clamp_box(cx, cy, half, w, h):
    """Square crop of half-size `half` centred near (cx, cy), moved (not cut) to lie inside a
    w×h image; returns integer (x0, y0, x1, y1) with x1 - x0 == y1 - y0 == min(2*half, w, h)."""
    size = int(min(2 * half, w, h))
    x0 = int(round(cx - size / 2))
    y0 = int(round(cy - size / 2))
    x0 = max(0, min(x0, w - size))
    y0 = max(0, min(y0, h - size))
    return x0, y0, x0 + size, y0 + size


def strip_geometry(w, h, gx, gy):
    """Inset boxes (x0, y0, x1, y1), clamped inside the w×h image: one centred on the gaze, one
    in the periphery (the candidate point farthest from the gaze: left/right middle)."""
    half = max(8, min(w, h) // 6)
    fov = clamp_box(gx, gy, half, w, h)
    cands = [(w * 0.12, h * 0.5), (w * 0.88, h * 0.5), (w * 0.5, h * 0.12), (w * 0.5, h * 0.88)]
    px, py = max(cands, key=lambda c: (c[0] - gx) ** 2 + (c[1] - gy) ** 2)
    per = clamp_box(px, py, half, w, h)
    return fov, per


def draw_strip(cols, gx, gy, title):
    """Side-by-side strip: cols = [(name, image, error image or None)], the first usually the
    reference. Row 1: images with the gaze (red +), a green box at the gaze and an orange box in
    the periphery (both inside the image); rows 2-3: those boxes zoomed; row 4 (when any error
    image): the error maps with a colour bar (|luma error|, turbo 0–0.25). Returns the figure."""
    from matplotlib import cm, colors

    h, w = cols[0][1].shape[:2]
    (fx0, fy0, fx1, fy1), (px0, py0, px1, py1) = strip_geometry(w, h, gx, gy)
    has_err = any(c[2] is not None for c in cols)
    nrow = 4 if has_err else 3
    fig, axes = plt.subplots(nrow, len(cols), figsize=(3.2 * len(cols), 3.0 * nrow), squeeze=False)
    for k, (name, im, err) in enumerate(cols):
        a = axes[0][k]
        a.imshow(im)
        a.add_patch(plt.Rectangle((fx0, fy0), fx1 - fx0, fy1 - fy0, fill=False, ec="lime", lw=1.2))
        a.add_patch(plt.Rectangle((px0, py0), px1 - px0, py1 - py0, fill=False, ec="orange", lw=1.2))
        a.plot([gx], [gy], marker="+", color="red", ms=10, mew=1.5)
        a.set_title(name, fontsize=8)
        axes[1][k].imshow(im[fy0:fy1, fx0:fx1], interpolation="nearest")
        axes[1][k].set_title("at the gaze (green)", fontsize=7)
        axes[2][k].imshow(im[py0:py1, px0:px1], interpolation="nearest")
        axes[2][k].set_title("periphery (orange)", fontsize=7)
        if has_err:
            if err is not None:
                axes[3][k].imshow(err)
                axes[3][k].set_title("|luma error|", fontsize=7)
            axes[3][k].axis("off")
        for a in (axes[0][k], axes[1][k], axes[2][k]):
            a.set_xticks([])
            a.set_yticks([])
    if has_err:  # colour bar in the reference's (empty) error slot, so columns stay aligned
        sm = cm.ScalarMappable(norm=colors.Normalize(0, 0.25), cmap="turbo")
        cax = axes[3][0].inset_axes([0.45, 0.05, 0.1, 0.9])
        fig.colorbar(sm, cax=cax, label="|luma error| (display-encoded)")
    fig.suptitle(title, fontsize=10)
    return fig


def save(fig, path):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    tmp = os.path.join(os.path.dirname(path) or ".", ".tmp.%d.%s" % (os.getpid(), os.path.basename(path)))
    fig.savefig(tmp, dpi=110, bbox_inches="tight")
    plt.close(fig)
    os.replace(tmp, path)  # atomic, like every fovsim output


def write_text_atomic(path, text):
    tmp = os.path.join(os.path.dirname(path) or ".", ".tmp.%d.%s" % (os.getpid(), os.path.basename(path)))
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)
