#!/usr/bin/python3
"""Pixels whose G-buffer differs between Embree ISA paths (tests/golden/README.md).

Runs BUILD/isa_gbuffer under every Embree path `fovsim info --json` lists, then compares each
path with the last (widest) one, bit for bit over depth, object id, normal, albedo, uv and
position, at 1440 x 1600 on three atrium complexities x three views. A differing pixel is
classified as an object/miss change or as the same object hit on another triangle (a crease,
a shared edge of a planar face, or a fold of the same mesh), with the largest depth and albedo
differences and the smallest normal dot product among them.
Usage: bench/isa_gbuffer_diff.py [BUILD_DIR]   (needs numpy: python3-numpy)
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

B = sys.argv[1] if len(sys.argv) > 1 else "build"
W, H = 1440, 1600
info = json.loads(subprocess.run([f"{B}/fovsim", "info", "--json"], check=True,
                                 capture_output=True, text=True).stdout)
isas = info["embree_isas"]
tmp = tempfile.mkdtemp()
for isa in isas:
    subprocess.run([f"{B}/isa_gbuffer", f"{tmp}/{isa}"], check=True,
                   env=dict(os.environ, FOVSIM_EMBREE_ISA=isa))


def load(path):
    b = open(path, "rb").read()
    n = int(np.frombuffer(b[:8], np.uint64)[0])
    o, out = 8, []
    for comps, dt in ((1, np.float32), (1, np.int32), (3, np.float32), (3, np.float32),
                      (2, np.float32), (3, np.float32)):
        size = n * comps * 4
        out.append(np.frombuffer(b[o:o + size], dt).reshape(H, W, comps))
        o += size
    return out


ref = isas[-1]
print(f"CPU paths: {', '.join(isas)}; each compared with {ref}, {W} x {H} = {W * H} pixels per view")
for cx in (1, 3, 6):
    for view in range(3):
        a = load(f"{tmp}/{ref}_{cx}_{view}.bin")
        for isa in isas[:-1]:
            b = load(f"{tmp}/{isa}_{cx}_{view}.bin")
            diff = np.zeros((H, W), bool)
            for x, y in zip(a, b):
                diff |= (x.view(np.uint32) != y.view(np.uint32)).any(-1)
            obj = ((a[1][..., 0] != b[1][..., 0]) |
                   (np.isinf(a[0][..., 0]) != np.isinf(b[0][..., 0]))) & diff
            same = diff & ~obj
            detail = ""
            if same.any():
                da, db = a[0][..., 0][same], b[0][..., 0][same]
                detail = (f"; max rel. depth diff {(np.abs(da - db) / np.abs(da)).max():.1e}, "
                          f"min normal dot {(a[2][same] * b[2][same]).sum(-1).min():.3f}, "
                          f"max albedo diff {np.abs(a[3][same] - b[3][same]).max():.2g}")
            print(f"complexity {cx} view {view} {isa:7s}: {int(diff.sum())} px differ "
                  f"({diff.sum() / (W * H) * 1e6:.1f} ppm): object/miss change {int(obj.sum())}, "
                  f"same object {int(same.sum())}{detail}")
