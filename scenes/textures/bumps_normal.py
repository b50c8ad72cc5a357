#!/usr/bin/env python3
"""The normal map of scenes/normal-map.json, made here (no third-party images): run from this folder.

A tangent-space normal map (glTF's convention: +x along u, +y up the image, z out of the surface; texel = (n + 1)/2,
8-bit, linear) of a height field of rounded tiles, h(u, v) = A·sin²(πku)·sin²(πkv) over k × k tiles per image, its
normal n = normalize(−∂h/∂x, −∂h/∂y, 1) with x = u, y = −v (image up). Standard library only (zlib, struct).
"""
import math
import struct
import zlib

SIZE, TILES, AMPLITUDE = 128, 4, 0.06  # texels, tiles across, height in units of the image's width


def normal(x, y):
    """The unit normal at texel centre (x, y), y down from the top row."""
    u, v = (x + 0.5) / SIZE, (y + 0.5) / SIZE
    k = math.pi * TILES
    su, cu, sv, cv = math.sin(k * u), math.cos(k * u), math.sin(k * v), math.cos(k * v)
    dhdu = AMPLITUDE * 2 * su * cu * k * sv * sv
    dhdv = AMPLITUDE * 2 * sv * cv * k * su * su
    n = (-dhdu, dhdv, 1.0)  # ∂h/∂y = −∂h/∂v
    length = math.sqrt(sum(c * c for c in n))
    return [c / length for c in n]


def png(path, rows):
    raw = b"".join(b"\0" + bytes(row) for row in rows)
    chunk = lambda kind, data: struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", SIZE, SIZE, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


rows = []
for y in range(SIZE):
    row = []
    for x in range(SIZE):
        row += [max(0, min(255, round((c + 1) / 2 * 255))) for c in normal(x, y)]
    rows.append(row)
png("bumps_normal.png", rows)
