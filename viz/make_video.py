#!/usr/bin/python3
"""A short video of a fovsim run: the saved frames with the gaze marked, the reference and
the methods side by side, one video frame per images/frame_<n>/ folder.

    /usr/bin/python3 viz/make_video.py results/<name> [--out DIR] [--fps N] [--format mp4|gif]

Needs Debian's ffmpeg (`apt-get install ffmpeg`); without it, or with fewer than two saved
frames, it prints why and writes nothing (exit 0: a video is optional). Which frames are saved
is `outputs.image_frames` of the run config (e.g. `outputs.image_frames=[0,3,6,...]`). Writes
DIR/run.mp4 (H.264, yuv420p) or DIR/run.gif (default DIR: results/<name>/plots). `fovsim run`
makes it through viz/plot_run.py. Colours per method: viz/common.py (the same as every plot).
"""
import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from common import log, plt, to_float  # noqa: E402

MAX_METHODS = 8  # methods shown side by side (besides the reference); the title says when capped


class NoVideo(Exception):
    """Why no video is made (ffmpeg missing, too few frames): a message, not an error."""


def frame_dirs(run_dir):
    root = os.path.join(run_dir, "images")
    if not os.path.isdir(root):
        return []
    out = []
    for d in os.listdir(root):
        if d.startswith("frame_") and os.path.exists(os.path.join(root, d, "reference.png")):
            try:
                out.append((int(d[len("frame_"):]), os.path.join(root, d)))
            except ValueError:
                continue
    return sorted(out)


def _run_info(run_dir):
    """(labels in order with their method, {frame: (gaze_x, gaze_y)}, display width or None)."""
    _, frames = common.read_csv(os.path.join(run_dir, "frames.csv"))
    labels, gaze = {}, {}
    for r in frames or []:
        lab = r.get("label") or r.get("config_id") or ""
        labels.setdefault(lab, r.get("method") or lab)
        f = to_float(r.get("frame"))
        if math.isfinite(f) and int(f) not in gaze:
            gaze[int(f)] = (to_float(r.get("gaze_x")), to_float(r.get("gaze_y")))
    disp = common.find_display(common.read_json(os.path.join(run_dir, "manifest.json"))) or {}
    w = disp.get("width") if isinstance(disp.get("width"), (int, float)) else None
    return labels, gaze, w


def compose(frame, fdir, labels, gaze, disp_w, path, capped_note):
    """One video frame: reference and each method's image in a row, gaze marked (red + and a
    circle), the method's name in its colour (common.method_color)."""
    cols = [("reference", "reference", os.path.join(fdir, "reference.png"))]
    for lab, meth in labels.items():
        p = os.path.join(fdir, lab + ".png")
        if os.path.exists(p) and len(cols) <= MAX_METHODS:
            cols.append((lab, meth, p))
    ims = [plt.imread(c[2]) for c in cols]
    h, w = ims[0].shape[:2]
    n = len(cols)
    ncol = min(n, 3) if n <= 6 or n == 9 else 4  # few empty slots
    nrow = int(math.ceil(n / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.2 * ncol, (3.2 * h / w + 0.3) * nrow + 0.4), squeeze=False,
                             layout="constrained")  # same size every frame (H.264)
    gx, gy = gaze.get(frame, (math.nan, math.nan))
    sc = w / float(disp_w) if disp_w else 1.0
    for k, ax in enumerate(axes.flat):
        ax.set_xticks([])
        ax.set_yticks([])
        if k >= n:
            ax.axis("off")
            continue
        lab, meth, _ = cols[k]
        ax.imshow(ims[k])
        if math.isfinite(gx) and math.isfinite(gy):
            ax.plot([gx * sc], [gy * sc], marker="+", color="red", ms=12, mew=2)
            ax.add_patch(plt.Circle((gx * sc, gy * sc), 0.06 * w, fill=False, ec="red", lw=1))
        ax.set_title(lab, fontsize=9, color=common.method_color(meth) if meth != "reference" else "k")
    fig.suptitle(f"frame {frame}: gaze + (red){capped_note}", fontsize=10)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def make_video(run_dir, out, fps=4.0, fmt="mp4", report=log):
    """Writes out/run.<fmt>; returns its file name. Raises NoVideo with the reason."""
    ffmpeg = shutil.which("ffmpeg")
    if not ffmpeg:
        raise NoVideo("ffmpeg not found (apt-get install ffmpeg)")
    dirs = frame_dirs(run_dir)
    if len(dirs) < 2:
        raise NoVideo(f"{len(dirs)} saved frame(s) under images/ (set outputs.image_frames to two or more frames)")
    labels, gaze, disp_w = _run_info(run_dir)
    shown = [lab for lab in labels if any(os.path.exists(os.path.join(d, lab + ".png")) for _, d in dirs)]
    capped = f" ({MAX_METHODS} of {len(shown)} configurations shown)" if len(shown) > MAX_METHODS else ""
    name = f"run.{fmt}"
    os.makedirs(out, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        for i, (frame, fdir) in enumerate(dirs):
            compose(frame, fdir, labels, gaze, disp_w, os.path.join(tmp, f"v{i:05d}.png"), capped)
        dst = os.path.join(out, name)
        tmp_out = os.path.join(tmp, name)
        src = ["-framerate", f"{fps:g}", "-i", os.path.join(tmp, "v%05d.png")]
        if fmt == "gif":
            args = src + ["-vf", "split[a][b];[a]palettegen[p];[b][p]paletteuse"]
        else:  # H.264 wants even sizes
            args = src + ["-vf", "scale=trunc(iw/2)*2:trunc(ih/2)*2", "-c:v", "libx264", "-pix_fmt", "yuv420p"]
        p = subprocess.run([ffmpeg, "-y", "-loglevel", "error"] + args + [tmp_out], capture_output=True, text=True)
        if p.returncode != 0 or not os.path.exists(tmp_out):
            raise NoVideo(f"ffmpeg failed (exit {p.returncode}): {p.stderr.strip()[:300]}")
        shutil.move(tmp_out, dst + ".tmp")
        os.replace(dst + ".tmp", dst)  # atomic, like every fovsim output
    report(f"wrote {os.path.join(out, name)} ({len(dirs)} frames at {fps:g} fps)")
    return name


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("results_dir")
    ap.add_argument("--out", help="output directory (default: RESULTS_DIR/plots)")
    ap.add_argument("--fps", type=float, default=4.0, help="video frames per second (default 4)")
    ap.add_argument("--format", choices=["mp4", "gif"], default="mp4")
    a = ap.parse_args(argv)
    if not os.path.isdir(a.results_dir):
        print(f"make_video: error: {a.results_dir}: no such directory", file=sys.stderr)
        return 2
    try:
        make_video(a.results_dir, a.out or os.path.join(a.results_dir, "plots"), a.fps, a.format)
    except NoVideo as e:
        log(f"video skipped: {e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
