#!/usr/bin/env python3
"""Reduces measured spectral η(λ), k(λ) of conductors to the RGB η, k of common/materials/conductor_presets.cpp.

Usage: scripts/conductor_presets.py IOR_DIR CIE_CSV > rows.txt
  IOR_DIR  a folder of NAME.eta.spd and NAME.k.spd files (two columns, wavelength in nm and value; lines starting
           with # are comments): the measured optical constants that Mitsuba ships under data/ior/ (from the
           luxpop.com database, which compiles Palik's Handbook of Optical Constants of Solids and others)
  CIE_CSV  the CIE 1931 2° colour matching functions as published by the CIE: rows "λ,x̄,ȳ,z̄" (λ in nm)

The reduction is Mitsuba's in its RGB modes, so that a preset gives the numbers a Mitsuba scene means by that
name: each spectrum s(λ), linearly interpolated between its samples, is weighed by the matching functions over
360–830 nm, X = ∫ s x̄ dλ / ∫ ȳ dλ (and Y, Z alike: equal energy, a flat spectrum of 1 has X = Y = Z = 1), and
XYZ is turned into linear sRGB / Rec. 709 RGB by the IEC 61966-2-1 matrix. Two differences, both only where the
data are short: beyond its last (first) sample a spectrum keeps that sample's value, where Mitsuba takes 0 (which
drives e.g. AlSb's red η below 0); and a channel below 0 (a narrow spectrum that sRGB's gamut cannot hold) is
taken as 0. For Cu this gives η = (0.200438, 0.924033, 1.102212), k = (3.912948, 2.452848, 2.142188), the very
values of the Veach MIS scene's roughconductors.
"""
import csv
import os
import sys

XYZ_TO_RGB = ((3.240479, -1.537150, -0.498535), (-0.969256, 1.875991, 0.041556), (0.055648, -0.204043, 1.057311))
LO, HI, STEP = 360.0, 830.0, 0.05  # nm: the integration range and the trapezoid step


def read_spd(path):
    points = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if line and not line.startswith('#'):
                lam, value = line.split()[:2]
                points.append((float(lam), float(value)))
    points.sort()
    return points


def interpolate(points, lam):
    """Linear between samples; the end samples held beyond the data."""
    if lam <= points[0][0]:
        return points[0][1]
    if lam >= points[-1][0]:
        return points[-1][1]
    lo, hi = 0, len(points) - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if points[mid][0] <= lam:
            lo = mid
        else:
            hi = mid
    (l0, v0), (l1, v1) = points[lo], points[hi]
    return v0 + (lam - l0) / (l1 - l0) * (v1 - v0)


def read_cie(path):
    rows = []
    with open(path) as f:
        for r in csv.reader(f):
            if r and r[0].strip()[0].isdigit():
                rows.append(tuple(float(x) for x in r[:4]))
    return rows


def to_rgb(points, cie):
    cmf = [(lam, (x, y, z)) for lam, x, y, z in cie]
    n = int(round((HI - LO) / STEP))
    sums, norm = [0.0, 0.0, 0.0], 0.0
    for j in range(n + 1):
        lam = LO + j * STEP
        w = 0.5 if j in (0, n) else 1.0
        bar = [interpolate([(l, v[c]) for l, v in cmf_window(cmf, lam)], lam) for c in range(3)]
        s = interpolate(points, lam)
        for c in range(3):
            sums[c] += w * s * bar[c]
        norm += w * bar[1]
    xyz = [v / norm for v in sums]
    return tuple(max(0.0, sum(m * v for m, v in zip(row, xyz))) for row in XYZ_TO_RGB)


def cmf_window(cmf, lam):
    """The two tabulated matching-function rows around lam (the table is sorted, usually at 1 nm)."""
    i = max(0, min(len(cmf) - 2, int((lam - cmf[0][0]) / (cmf[1][0] - cmf[0][0]))))
    return cmf[i:i + 2]


def literal(v):
    """A C++ float literal of 6 significant digits; below 1e-6 (no effect on a reflectance), 0."""
    text = '%.6g' % (v if v >= 1e-6 else 0.0)
    return (text if '.' in text or 'e' in text else text + '.0') + 'f'


def main():
    ior_dir, cie_path = sys.argv[1], sys.argv[2]
    cie = read_cie(cie_path)
    names = sorted({f[:-len('.eta.spd')] for f in os.listdir(ior_dir) if f.endswith('.eta.spd')})
    for name in names:
        eta = to_rgb(read_spd(os.path.join(ior_dir, name + '.eta.spd')), cie)
        k = to_rgb(read_spd(os.path.join(ior_dir, name + '.k.spd')), cie)
        print('    {"%s", {%s}, {%s}},' % (name, ', '.join(map(literal, eta)), ', '.join(map(literal, k))))


if __name__ == '__main__':
    main()
