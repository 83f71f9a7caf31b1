#!/usr/bin/python3
"""Regenerates the SSIM/PSNR fixtures used by tests/metrics/metrics_ssim_test.cpp.

Run once with Debian's python3 (numpy, scipy, scikit-image, imageio):
    /usr/bin/python3 tests/data/metrics/make_ssim_fixtures.py
Writes <name>_a.png, <name>_b.png (8-bit) and expected.json next to this script.
Expected values: skimage.metrics.structural_similarity(gaussian_weights=True, sigma=1.5,
use_sample_covariance=False, data_range=1) on Rec.709 luma computed in float32 exactly as
fovsim::luma (0.2126 r + 0.7152 g + 0.0722 b), and PSNR/MSE over all channels.
"""
import json
import os

import imageio
import numpy as np
import scipy.ndimage as ndi
import skimage
from skimage.metrics import mean_squared_error, peak_signal_noise_ratio, structural_similarity

HERE = os.path.dirname(os.path.abspath(__file__))


def base_image(rng, w, h, c):
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    chans = []
    for k in range(c):
        f = 0.5 + 0.3 * np.sin(x / (3.0 + k) + y / 5.0) * np.cos(y / (4.0 + 2 * k))
        f += 0.15 * ndi.gaussian_filter(rng.standard_normal((h, w)), 1.0)
        f[(x // 8 + y // 8) % 2 == 0] += 0.1  # checker edges
        chans.append(f)
    return np.clip(np.stack(chans, axis=-1), 0, 1)


def q8(img):
    return np.round(np.clip(img, 0, 1) * 255).astype(np.uint8)


def luma(u8):
    f = u8.astype(np.float32) / np.float32(255)
    if f.ndim == 2 or f.shape[-1] == 1:
        return f.reshape(f.shape[0], f.shape[1])
    r, g, b = f[..., 0], f[..., 1], f[..., 2]
    return (np.float32(0.2126) * r + np.float32(0.7152) * g) + np.float32(0.0722) * b


def main():
    rng = np.random.default_rng(20240607)
    cases = {}
    a = base_image(rng, 64, 48, 3)
    cases["noise"] = (a, a + rng.normal(0, 0.05, a.shape))
    cases["blur"] = (a, ndi.gaussian_filter(a, (1.2, 1.2, 0)))
    cases["shift"] = (a, np.roll(a, 1, axis=1))
    cases["contrast"] = (a, 0.8 * a + 0.1)
    t = base_image(rng, 37, 150, 3)  # odd width, taller than one 64-row block
    cases["tall"] = (t, t + rng.normal(0, 0.1, t.shape) * (np.arange(150)[:, None, None] / 150.0))
    g = base_image(rng, 40, 31, 1)[..., 0]
    cases["gray"] = (g, ndi.gaussian_filter(g, 0.8) + rng.normal(0, 0.02, g.shape))

    expected = {"skimage_version": skimage.__version__, "cases": {}}
    for name, (x, y) in cases.items():
        xa, yb = q8(x), q8(y)
        imageio.imwrite(os.path.join(HERE, f"{name}_a.png"), xa)
        imageio.imwrite(os.path.join(HERE, f"{name}_b.png"), yb)
        la, lb = luma(xa).astype(np.float64), luma(yb).astype(np.float64)
        s = structural_similarity(la, lb, gaussian_weights=True, sigma=1.5,
                                  use_sample_covariance=False, data_range=1)
        fa, fb = xa.astype(np.float64) / 255, yb.astype(np.float64) / 255
        expected["cases"][name] = {
            "width": int(xa.shape[1]), "height": int(xa.shape[0]),
            "channels": 1 if xa.ndim == 2 else int(xa.shape[2]),
            "ssim": float(s),
            "mse": float(mean_squared_error(fa, fb)),
            "psnr": float(peak_signal_noise_ratio(fa, fb, data_range=1)),
        }
    with open(os.path.join(HERE, "expected.json"), "w") as f:
        json.dump(expected, f, indent=2, sort_keys=True)
        f.write("\n")


if __name__ == "__main__":
    main()
