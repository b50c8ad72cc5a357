#!/usr/bin/env python3
"""Writes crate.gltf: a 1 m wooden crate centred at the origin, glTF 2.0 with a metallic-roughness material, a
base-colour texture (../textures/floor.png) and a metallic-roughness texture (../textures/crate_mr.png), both made by
scenes/textures/make.sh. Our own asset (no third-party data): a textured glTF as a modelling tool exports it, with
normals and texture coordinates, the buffer embedded as a data URI. Run from this folder: python3 make_crate.py"""
import base64
import json
import struct

# Per face: the outward normal and four corners counter-clockwise seen from outside, uv (0,0) at the first.
FACES = [
    ((0, 0, 1), [(-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]),
    ((0, 0, -1), [(1, -1, -1), (-1, -1, -1), (-1, 1, -1), (1, 1, -1)]),
    ((1, 0, 0), [(1, -1, 1), (1, -1, -1), (1, 1, -1), (1, 1, 1)]),
    ((-1, 0, 0), [(-1, -1, -1), (-1, -1, 1), (-1, 1, 1), (-1, 1, -1)]),
    ((0, 1, 0), [(-1, 1, 1), (1, 1, 1), (1, 1, -1), (-1, 1, -1)]),
    ((0, -1, 0), [(-1, -1, -1), (1, -1, -1), (1, -1, 1), (-1, -1, 1)]),
]
UV = [(0, 1), (1, 1), (1, 0), (0, 0)]  # glTF: v down from the image's top edge

pos, nrm, uv, idx = [], [], [], []
for n, corners in FACES:
    base = len(pos)
    for c, t in zip(corners, UV):
        pos.append(tuple(0.5 * x for x in c))
        nrm.append(n)
        uv.append(t)
    idx += [base, base + 1, base + 2, base, base + 2, base + 3]

blob = b"".join(struct.pack("<3f", *p) for p in pos) + b"".join(struct.pack("<3f", *n) for n in nrm) + \
    b"".join(struct.pack("<2f", *t) for t in uv) + b"".join(struct.pack("<H", i) for i in idx)
n = len(pos)
views = [(0, 12 * n, 34962), (12 * n, 12 * n, 34962), (24 * n, 8 * n, 34962), (32 * n, 2 * len(idx), 34963)]
gltf = {
    "asset": {"version": "2.0", "generator": "firstshot scenes/assets/make_crate.py"},
    "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "crate"}],
    "meshes": [{"name": "crate", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                                  "indices": 3, "material": 0}]}],
    "materials": [{"name": "oiled wood", "pbrMetallicRoughness": {
        "baseColorTexture": {"index": 0}, "metallicFactor": 1.0, "roughnessFactor": 1.0,
        "metallicRoughnessTexture": {"index": 1}}}],
    "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}],
    "images": [{"uri": "../textures/floor.png"}, {"uri": "../textures/crate_mr.png"}],
    "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3", "min": [-0.5] * 3, "max": [0.5] * 3},
        {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5126, "count": n, "type": "VEC2"},
        {"bufferView": 3, "componentType": 5123, "count": len(idx), "type": "SCALAR"}],
    "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": l, "target": t} for o, l, t in views],
    "buffers": [{"byteLength": len(blob),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
}
with open("crate.gltf", "w") as f:
    json.dump(gltf, f, indent=1)
    f.write("\n")
