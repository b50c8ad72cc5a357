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
import subprocess
import sys

from noise_outside import noise, read


def load(path):
    try:
        return read(path)[0]
    except (subprocess.CalledProcessError, FileNotFoundError) as e:
        print(f"noise_lamps: {path}: cannot be read ({e})", file=sys.stderr)
        sys.exit(2)


def squares(a, b, keep):
    """The two images' summed squared difference / 2 over the pixels @p keep."""
    return sum(sum((x - y) ** 2 / 2 for x, y in zip(a[i], b[i])) for i in keep)


def main():
    if len(sys.argv) != 4:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    lamps, a, b = (load(p) for p in sys.argv[1:4])
    if not (len(lamps) == len(a) == len(b)):
        print(f"noise_lamps: {sys.argv[1]}, {sys.argv[2]} and {sys.argv[3]} differ in size "
              f"({len(lamps)}, {len(a)} and {len(b)} pixels)", file=sys.stderr)
        sys.exit(2)
    every = range(len(a))
    outside = [i for i in every if max(lamps[i]) <= 0.0]
    n_out = noise(a, b, outside)[0] if outside else float("nan")
    n_all = noise(a, b, every)[0]
    sq_all = squares(a, b, every)
    share = squares(a, b, [i for i in every if max(lamps[i]) > 0.0]) / sq_all if sq_all > 0 else 0.0
    print(f"{n_out:.4f} {n_all:.4f} {share:.3f}")


if __name__ == "__main__":
    main()
