#!/usr/bin/env python3
"""Writes a heavy-mesh test scene: one flat-shaded square grid of CELLS x CELLS quads (2 triangles
each; the default 1000 gives 2 M triangles and 1 M vertices) under a directional light, seen by a
45-degree camera, as OUT.gltf with its geometry in OUT.bin.

    python3 scripts/make-grid-gltf.py /tmp/grid/grid.gltf --cells 1000
    build/bin/relief render /tmp/grid/grid.gltf --size 1920x1080 --stats

docs/performance.md ("Heavy meshes") measures both backends on it.
"""
import argparse
import json
import os
import struct
import sys


def grid_buffers(cells, size):
    n = cells + 1
    pos, nrm, uv = bytearray(), bytearray(), bytearray()
    for j in range(n):
        z = (j / cells - 0.5) * size
        for i in range(n):
            x = (i / cells - 0.5) * size
            pos += struct.pack("<3f", x, 0.0, z)
            nrm += struct.pack("<3f", 0.0, 1.0, 0.0)
            uv += struct.pack("<2f", i / cells, j / cells)
    idx = bytearray()
    for j in range(cells):
        for i in range(cells):
            a = j * n + i
            b, c, d = a + 1, a + n, a + n + 1
            # Counter-clockwise seen from +y (glTF front faces).
            idx += struct.pack("<6I", a, c, b, b, c, d)
    return pos, nrm, uv, idx


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", help="the .gltf to write (its .bin goes beside it)")
    ap.add_argument("--cells", type=int, default=1000, help="quads per side (default 1000)")
    ap.add_argument("--size", type=float, default=2.0, help="side in metres (default 2)")
    a = ap.parse_args()
    if a.cells < 1 or a.cells > 4000:
        sys.exit("make-grid-gltf: --cells must be 1..4000")
    pos, nrm, uv, idx = grid_buffers(a.cells, a.size)
    n = a.cells + 1
    bin_name = os.path.splitext(os.path.basename(a.out))[0] + ".bin"
    chunks = [pos, nrm, uv, idx]
    views, offset = [], 0
    for k, c in enumerate(chunks):
        v = {"buffer": 0, "byteOffset": offset, "byteLength": len(c)}
        v["target"] = 34963 if k == 3 else 34962
        views.append(v)
        offset += len(c)
    h = a.size / 2
    accessors = [
        {"bufferView": 0, "componentType": 5126, "count": n * n, "type": "VEC3",
         "min": [-h, 0.0, -h], "max": [h, 0.0, h]},
        {"bufferView": 1, "componentType": 5126, "count": n * n, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5126, "count": n * n, "type": "VEC2"},
        {"bufferView": 3, "componentType": 5125, "count": a.cells * a.cells * 6, "type": "SCALAR"},
    ]
    doc = {
        "asset": {"version": "2.0", "generator": "relief scripts/make-grid-gltf.py"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "sun", "type": "directional", "intensity": 2.0}]}},
        "buffers": [{"uri": bin_name, "byteLength": offset}],
        "bufferViews": views,
        "accessors": accessors,
        "materials": [{"name": "flat", "pbrMetallicRoughness": {
            "baseColorFactor": [0.8, 0.7, 0.5, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.6}}],
        "meshes": [{"name": "grid", "primitives": [{"attributes": {
            "POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]}],
        "cameras": [{"name": "view", "type": "perspective", "perspective": {
            "yfov": 0.8, "znear": 0.05, "zfar": 50.0}}],
        "nodes": [
            {"mesh": 0},
            # 45 degrees down onto the grid's centre from 4.2 m.
            {"name": "view", "camera": 0, "translation": [0.0, 3.0, 3.0],
             "rotation": [-0.3826834, 0.0, 0.0, 0.9238795]},
            {"name": "sun", "rotation": [-0.4165493, 0.3570423, 0.0, 0.8360667],
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
        ],
        "scenes": [{"name": "grid", "nodes": [0, 1, 2]}],
        "scene": 0,
    }
    with open(os.path.join(os.path.dirname(os.path.abspath(a.out)), bin_name), "wb") as f:
        for c in chunks:
            f.write(c)
    with open(a.out, "w") as f:
        json.dump(doc, f, indent=1)


if __name__ == "__main__":
    main()
