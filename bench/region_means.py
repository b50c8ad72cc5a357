#!/usr/bin/env python3
"""Region-by-region comparison of a render with a tone-mapped reference picture (docs/measurements.md, "Conductors
as Mitsuba means them").

Usage: bench/region_means.py RENDER.exr REFERENCE.png [--rows 3] [--cols 3] [--curve filmic|srgb]

Both images are cut into the same rows × cols grid of equal fractions (they may differ in resolution). The reference
is an 8-bit picture whose codes v/255 are curve(L) of the radiance L:
  filmic  Tungsten's "filmic" tone map (the Hejl–Burgess-Dawson curve, display gamma included):
          y = x(6.2x + 0.5)/(x(6.2x + 1.7) + 0.06), x = max(0, L − 0.004)
  srgb    the sRGB transfer function of L clipped to [0, 1]
Two comparisons per region: "display", the mean of curve(render) against the mean of the codes (like for like, as
the reference was made); "radiance", the mean of the render against the mean of the codes turned back into radiance
(code 0 as 0), both clipped to [0, 1]: the filmic curve leaves too few codes above radiance 1 (codes 214–255 hold 1 to
infinity) to read radiance back there, and the sRGB one nothing at all.
Each is printed with the ratio render/reference and that ratio over the whole picture's (how the regions compare
when the exposures differ by a constant factor). The render is read by oiiotool (OpenImageIO's tool, on the PATH);
the reference is decoded here (8-bit RGB or RGBA PNG, not interlaced).
"""
import argparse
import math
import re
import struct
import subprocess
import zlib


def filmic(L):
    x = max(0.0, L - 0.004)
    return x * (6.2 * x + 0.5) / (x * (6.2 * x + 1.7) + 0.06)


def filmic_inverse(y):
    """The radiance L ≥ 0.004 with filmic(L) = y, for 0 < y < 1: the positive root of 6.2(y−1)x² + (1.7y − 0.5)x +
    0.06y = 0."""
    a, b, c = 6.2 * (y - 1.0), 1.7 * y - 0.5, 0.06 * y
    return (-b - math.sqrt(b * b - 4.0 * a * c)) / (2.0 * a) + 0.004


def srgb(L):
    L = min(max(L, 0.0), 1.0)
    return 12.92 * L if L <= 0.0031308 else 1.055 * L ** (1 / 2.4) - 0.055


def srgb_inverse(y):
    return y / 12.92 if y <= 0.04045 else ((y + 0.055) / 1.055) ** 2.4


CURVES = {'filmic': filmic_inverse, 'srgb': srgb_inverse}


def read_png(path):
    """(width, height, rows of 8-bit RGB triples) of an 8-bit RGB/RGBA non-interlaced PNG."""
    data = open(path, 'rb').read()
    if data[:8] != b'\x89PNG\r\n\x1a\n':
        raise SystemExit(path + ': not a PNG')
    pos, idat, width = 8, b'', 0
    while pos < len(data):
        n, kind = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b'IHDR':
            width, height, depth, colour, _, _, interlace = struct.unpack('>IIBBBBB', body)
            if depth != 8 or colour not in (2, 6) or interlace:
                raise SystemExit(path + ': only 8-bit RGB/RGBA, not interlaced')
            bpp = 3 if colour == 2 else 4
        elif kind == b'IDAT':
            idat += body
        pos += 12 + n
    raw, stride, prev, rows = zlib.decompress(idat), width * bpp, bytearray(width * bpp), []
    for r in range(height):
        f, line = raw[r * (stride + 1)], bytearray(raw[r * (stride + 1) + 1:(r + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line[k] for k in range(stride) if k % bpp < 3))
        prev = line
    return width, height, rows


def cells(width, height, rows, cols):
    for r in range(rows):
        for c in range(cols):
            x0, y0 = width * c // cols, height * r // rows
            yield x0, y0, width * (c + 1) // cols - x0, height * (r + 1) // rows - y0


def reference_means(path, rows, cols, curve):
    inverse = CURVES[curve]
    lut = [0.0] + [min(1.0, inverse(v / 255.0)) for v in range(1, 255)] + [1.0]
    width, height, pixels = read_png(path)
    out = []
    for x0, y0, w, h in list(cells(width, height, rows, cols)) + [(0, 0, width, height)]:
        codes = [v for line in pixels[y0:y0 + h] for v in line[3 * x0:3 * (x0 + w)]]
        out.append((sum(codes) / (255.0 * len(codes)), sum(lut[v] for v in codes) / len(codes)))
    return out


def oiio_mean(args):
    out = subprocess.run(['oiiotool'] + args + ['--printstats'], capture_output=True, text=True, check=True).stdout
    avg = re.search(r'Stats Avg:\s*(\S+)\s+(\S+)\s+(\S+)', out)
    return sum(float(v) for v in avg.groups()) / 3.0


def render_means(path, rows, cols, curve):
    out = subprocess.run(['oiiotool', '--info', path], capture_output=True, text=True, check=True).stdout
    width, height = map(int, re.search(r'(\d+)\s*x\s*(\d+)', out).groups())
    if curve == 'filmic':  # y = x(6.2x + 0.5)/(x(6.2x + 1.7) + 0.06) with oiiotool's image arithmetic
        display = [path, '--ch', 'R,G,B', '--subc', '0.004', '--clamp:min=0', '--label', 'x',
                   'x', '--mulc', '6.2', '--addc', '0.5', 'x', '--mul', '--label', 'num',
                   'x', '--mulc', '6.2', '--addc', '1.7', 'x', '--mul', '--addc', '0.06', '--label', 'den',
                   'num', 'den', '--div']
    else:
        display = [path, '--ch', 'R,G,B', '--clamp:min=0:max=1', '--colorconvert', 'linear', 'sRGB']
    res = []
    for x0, y0, w, h in list(cells(width, height, rows, cols)) + [(0, 0, width, height)]:
        cut = ['--cut', '%dx%d+%d+%d' % (w, h, x0, y0)]
        res.append((oiio_mean(display + cut),
                    oiio_mean([path, '--ch', 'R,G,B', '--clamp:min=0:max=1'] + cut)))
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('render')
    ap.add_argument('reference')
    ap.add_argument('--rows', type=int, default=3)
    ap.add_argument('--cols', type=int, default=3)
    ap.add_argument('--curve', choices=sorted(CURVES), default='filmic')
    a = ap.parse_args()
    ref = reference_means(a.reference, a.rows, a.cols, a.curve)
    ours = render_means(a.render, a.rows, a.cols, a.curve)
    print('reference curve: %s' % a.curve)
    print('region      display: render  reference  ratio  /whole   radiance: render  reference  ratio  /whole')
    n = len(ref) - 1
    whole = [ours[n][k] / ref[n][k] for k in (0, 1)]
    for i in range(n + 1):
        name = 'whole' if i == n else '(%d, %d)' % (i // a.cols, i % a.cols)
        d, L = (ours[i][k] / ref[i][k] for k in (0, 1))
        print('%-10s  %15.5f  %9.5f  %6.4f  %6.4f  %16.5f  %9.5f  %6.4f  %6.4f' %
              (name, ours[i][0], ref[i][0], d, d / whole[0], ours[i][1], ref[i][1], L, L / whole[1]))


if __name__ == '__main__':
    main()
