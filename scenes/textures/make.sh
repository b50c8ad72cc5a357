#!/bin/sh
# The textures of scenes/textured-room.json and scenes/cutout-screen.json, made here (no third-party images): run from this folder with
# OpenImageIO's oiiotool (Debian package openimageio-tools). Stored 8-bit, so read as sRGB.
set -e
# Floor: rows of planks 40 texels wide in two wood tones, times a grain of uniform noise; 1 m per image.
oiiotool --pattern checker:width=256:height=40:color1=0.45,0.28,0.15:color2=0.55,0.36,0.2 256x256 3 \
  --pattern noise:type=uniform:min=0.85:max=1.0:mono=1:seed=3 256x256 3 --mul -d uint8 -o floor.png
# Walls: a light paint with a slight texture.
oiiotool --pattern noise:type=uniform:min=0.78:max=0.86:mono=1:seed=5 128x128 3 -d uint8 -o wall.png
# Rug: a red and beige check.
oiiotool --pattern checker:width=16:height=16:color1=0.6,0.12,0.1:color2=0.75,0.65,0.45 128x128 3 -d uint8 -o rug.png
# The crate's metallic-roughness texture (scenes/assets/crate.gltf; glTF layout: roughness in G, metallic in B, read
# as linear): a dielectric whose planks alternate between roughness 0.35 and 0.8.
oiiotool --pattern checker:width=128:height=40:color1=0,0.35,0:color2=0,0.8,0 128x128 3 -d uint8 -o crate_mr.png
# Perforated screen (scenes/cutout-screen.json): grey + alpha, 64 × 64, an 8 × 8 grid of round holes (alpha 0)
# of radius 3 texels in a light grey sheet; written with Python's zlib (oiiotool draws no discs).
python3 - <<'PY'
import struct, zlib
n, cell, r = 64, 8, 3.0
rows = b""
for y in range(n):
    row = b"\0"
    for x in range(n):
        dx, dy = (x % cell) - (cell - 1) / 2, (y % cell) - (cell - 1) / 2
        row += bytes([200, 0 if dx * dx + dy * dy <= r * r else 255])
    rows += row
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", n, n, 8, 4, 0, 0, 0))
png += chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")
open("perforated.png", "wb").write(png)
PY
# Emissive panel (scenes/emissive-texture.json): 16 × 16 RGB, the left half (u < ½) white, the right half
# black; written with Python's zlib.
python3 - <<'PY'
import struct, zlib
n = 16
rows = b"".join(b"\0" + b"".join(bytes([255, 255, 255] if x < n // 2 else [0, 0, 0]) for x in range(n)) for y in range(n))
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", n, n, 8, 2, 0, 0, 0))
png += chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")
open("half_white.png", "wb").write(png)
PY
