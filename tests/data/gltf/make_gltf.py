#!/usr/bin/env python3
"""Writes the small glTF test scenes of tests/render/import_material_test.cpp (run from this
folder with /usr/bin/python3; the outputs are committed). Standard library only.

cutout.gltf    two quads facing +z, 1 m apart: the back one opaque red (z = -1), the front one
               green (z = 0) with alphaMode MASK, cutoff 0.5 and a 4x1 RGBA base-colour texture
               whose left half has alpha 0 and right half alpha 1. Expected from a camera on +z
               looking at -z: the left half of the front quad shows the red quad behind it, the
               right half is green; shadow rays pass the cut-out part too.
normalmap.gltf one quad (z = 0) with a 2x1 normal texture: left texel tilted towards +x
               (tangent-space (0.6, 0, 0.8)), right texel flat (0, 0, 1); metallicFactor 0,
               roughnessFactor 0.5, emissiveFactor (0.2, 0.1, 0). Expected: under a light from
               +x the left half is brighter than the right half.
"""
import base64, json, struct, zlib


def png_rgba(w, h, pixels):
    raw = b"".join(b"\x00" + bytes(sum((list(p) for p in pixels[y * w:(y + 1) * w]), []))
                   for y in range(h))
    def chunk(t, d):
        c = t + d
        return struct.pack(">I", len(d)) + c + struct.pack(">I", zlib.crc32(c) & 0xffffffff)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def quad(z, size=1.0):
    s = size
    pos = [(-s, -s, z), (s, -s, z), (s, s, z), (-s, s, z)]
    nrm = [(0, 0, 1)] * 4
    uv = [(0, 1), (1, 1), (1, 0), (0, 0)]  # glTF: v = 0 at the top of the image
    idx = [0, 1, 2, 0, 2, 3]
    return pos, nrm, uv, idx


def gltf(quads, materials, images, path):
    blob = b""
    views, accessors, meshes, nodes = [], [], [], []
    def add(data, fmt, count, typ, comp, target, minmax=None):
        nonlocal blob
        while len(blob) % 4:
            blob += b"\x00"
        off = len(blob)
        blob += data
        views.append({"buffer": 0, "byteOffset": off, "byteLength": len(data), "target": target})
        a = {"bufferView": len(views) - 1, "componentType": comp, "count": count, "type": typ}
        if minmax:
            a["min"], a["max"] = minmax
        accessors.append(a)
        return len(accessors) - 1
    for qi, (q, mat) in enumerate(quads):
        pos, nrm, uv, idx = q
        p = add(b"".join(struct.pack("<3f", *v) for v in pos), None, 4, "VEC3", 5126, 34962,
                ([min(v[i] for v in pos) for i in range(3)], [max(v[i] for v in pos) for i in range(3)]))
        n = add(b"".join(struct.pack("<3f", *v) for v in nrm), None, 4, "VEC3", 5126, 34962)
        t = add(b"".join(struct.pack("<2f", *v) for v in uv), None, 4, "VEC2", 5126, 34962)
        i = add(b"".join(struct.pack("<H", v) for v in idx), None, 6, "SCALAR", 5123, 34963)
        meshes.append({"primitives": [{"attributes": {"POSITION": p, "NORMAL": n, "TEXCOORD_0": t},
                                       "indices": i, "material": mat}]})
        nodes.append({"mesh": qi, "name": "quad%d" % qi})
    doc = {
        "asset": {"version": "2.0", "generator": "tests/data/gltf/make_gltf.py"},
        "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}], "nodes": nodes,
        "meshes": meshes, "materials": materials, "accessors": accessors, "bufferViews": views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
    }
    if images:
        doc["images"] = [{"uri": u} for u in images]
        doc["textures"] = [{"source": k, "sampler": 0} for k in range(len(images))]
        doc["samplers"] = [{"magFilter": 9728, "minFilter": 9728}]
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)


# 4x1 RGBA: green, alpha 0 | 0 | 255 | 255
open("cutout_basecolor.png", "wb").write(
    png_rgba(4, 1, [(0, 255, 0, 0), (0, 255, 0, 0), (0, 255, 0, 255), (0, 255, 0, 255)]))
gltf([(quad(-1.0, 2.0), 0), (quad(0.0), 1)],
     [{"name": "back_red", "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1],
                                                     "metallicFactor": 0}},
      {"name": "front_cutout", "alphaMode": "MASK", "alphaCutoff": 0.5,
       "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}}],
     ["cutout_basecolor.png"], "cutout.gltf")

# 2x1 normal map: (0.6, 0, 0.8) | (0, 0, 1), encoded n * 0.5 + 0.5
enc = lambda n: tuple(int(round((c * 0.5 + 0.5) * 255)) for c in n) + (255,)
open("normalmap_normal.png", "wb").write(png_rgba(2, 1, [enc((0.6, 0, 0.8)), enc((0, 0, 1))]))
gltf([(quad(0.0), 0)],
     [{"name": "bumpy", "normalTexture": {"index": 0}, "emissiveFactor": [0.2, 0.1, 0.0],
       "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0,
                                "roughnessFactor": 0.5}}],
     ["normalmap_normal.png"], "normalmap.gltf")
