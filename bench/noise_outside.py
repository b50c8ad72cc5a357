#!/usr/bin/env python3
"""Relative noise of a method's two seed images, over the whole picture and outside a pixel window.

usage: bench/noise_outside.py DIR METHODS X0,X1,Y0,Y1
  DIR: a scene's folder of bench/auto_vs_best.sh (METHOD-1.exr, METHOD-2.exr); METHODS: comma-separated names
  (path, all, cache, light, bdpt, auto, pathT, cacheT, autoT); X0,X1,Y0,Y1: the window left out, pixels, inclusive (say, where
  the camera sees a lamp through glass: those pixels every method path traces alike).
noise = RMS over pixels and channels of (a - b)/sqrt(2), relative to the mean of the pixels counted, as
auto_vs_best.sh's. Reads the images with oiiotool --dumpdata (no Python packages needed).
"""
import math
import subprocess
import sys


def read(path):
    out = subprocess.run(["oiiotool", "--dumpdata", path], capture_output=True, text=True, check=True).stdout
    pixels, width = [], 0
    for line in out.splitlines():
        if "Pixel (" in line:
            x = int(line.split("(")[1].split(",")[0])
            width = max(width, x + 1)
            pixels.append([float(v) for v in line.split(":")[1].split()[:3]])
    return pixels, width


def noise(a, b, keep):
    mean = sum(sum(a[i]) + sum(b[i]) for i in keep) / (6 * len(keep))
    sq = sum(sum((x - y) ** 2 / 2 for x, y in zip(a[i], b[i])) for i in keep)
    return math.sqrt(sq / (3 * len(keep))) / mean, mean


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    folder, methods, window = sys.argv[1], sys.argv[2].split(","), [int(v) for v in sys.argv[3].split(",")]
    x0, x1, y0, y1 = window
    print("| method | noise, whole picture | mean | noise outside the window | mean |")
    print("|---|---|---|---|---|")
    for m in methods:
        (a, w), (b, _) = read(f"{folder}/{m}-1.exr"), read(f"{folder}/{m}-2.exr")
        every = range(len(a))
        outside = [i for i in every if not (x0 <= i % w <= x1 and y0 <= i // w <= y1)]
        na, ma = noise(a, b, every)
        no, mo = noise(a, b, outside)
        print(f"| {m} | {na:.4f} | {ma:.4f} | {no:.4f} | {mo:.4f} |")


if __name__ == "__main__":
    main()
