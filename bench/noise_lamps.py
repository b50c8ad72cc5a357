#!/usr/bin/env python3
"""Relative noise of one image from two seeds' images, without the pixels where the camera sees a lamp.

usage: bench/noise_lamps.py LAMPS A B
  LAMPS: the scene rendered with --max-depth 0 (only what the camera sees emitting; at 256 spp a lamp covering
  1/256 of a pixel shows); A, B: the two seeds' images. Prints "NOISE WHOLE SHARE": the noise over the pixels where
  LAMPS is 0, over every pixel, and the share of the whole picture's squared noise in the lamps' pixels.
noise = RMS over pixels and channels of (a - b)/sqrt(2), relative to the mean of the pixels counted
(firstshot-compare's nrmse / sqrt(2) when every pixel counts).

Why: a pixel the camera sees a lamp in takes its value from how much of the pixel the lamp covers, the same way in
every method (the camera ray meets the emitter), so its two seeds differ by where their samples fell, not by the
light's noise. One such pixel can be the whole figure: in Veach's MIS scene at 128 x 128 the smallest sphere lamp
covers part of one pixel, which reads about 1235 against an image mean of 1.05 and held 99.1% of the path tracer's
squared noise at 20 s (docs/measurements.md, "Lamps in the picture").
"""
import math
import sys

from noise_outside import read


def noise(a, b, keep):
    if not keep:
        return float("nan"), 0.0
    mean = sum(sum(a[i]) + sum(b[i]) for i in keep) / (6 * len(keep))
    sq = sum(sum((x - y) ** 2 / 2 for x, y in zip(a[i], b[i])) for i in keep)
    return math.sqrt(sq / (3 * len(keep))) / mean, sq


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    (lamps, _), (a, _), (b, _) = read(sys.argv[1]), read(sys.argv[2]), read(sys.argv[3])
    if not (len(lamps) == len(a) == len(b)):
        sys.exit("noise_lamps: the three images differ in size")
    every = range(len(a))
    outside = [i for i in every if max(lamps[i]) <= 0.0]
    n_out, _ = noise(a, b, outside)
    n_all, sq_all = noise(a, b, every)
    _, sq_lamps = noise(a, b, [i for i in every if max(lamps[i]) > 0.0])
    print(f"{n_out:.4f} {n_all:.4f} {sq_lamps / sq_all if sq_all > 0 else 0.0:.3f}")


if __name__ == "__main__":
    main()
