#!/usr/bin/env python3
"""Preprocess time and peak memory against patches x light samples (docs/preprocess-performance.md).

Builds synthetic scenes with about N patches and M point lights and runs firstshot-preprocess on each under
/usr/bin/time: a 10 x 10 grid of closed rooms (4 m x 4 m x 3 m, 1 m apart, walls facing inwards), each with a
0.8 m box standing on its floor; the M point lights are dealt round-robin to the rooms at fixed positions under the
ceiling. The mesh is uniform (patch_size = min_patch_size = P, P chosen for N), so N is what the command line sets;
each light sees its own room only, so the factors grow as N*M/100 (the table must fit in memory at 1M x 1000).

    python3 bench/preprocess_scaling.py [--build build/release] [--patches 1e4,1e5,1e6] [--lights 10,100,1000]
                                        [--resolution 128] [--backend embree] [--threads 2] [--time-limit 600]

prints one Markdown row per run (N, M, wall s, user s, peak RSS MB, non-zeros) and the least-squares slope of
log(wall) and log(user) against log(N*M). --scene-only N M writes the scene JSON to stdout. Standard library only.
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile

ROOMS = 10                   # rooms per side of the grid
ROOM = (4.0, 3.0, 4.0)       # x, y (height), z
GAP = 1.0
BOX = 0.8
ROOM_AREA = 2 * ROOM[0] * ROOM[2] + 2 * ROOM[1] * (ROOM[0] + ROOM[2]) + 6 * BOX * BOX
# light positions inside a room (fractions of x and z), at 2.0-2.6 m; lights beyond 16 per room repeat the pattern
PATTERN = [(0.25 + 0.5 * (k % 2) + 0.11 * ((k // 4) % 2), 0.25 + 0.5 * ((k // 2) % 2) + 0.07 * (k // 8)) for k in range(16)]


def quad(material, vs):
    return {"type": "quad", "material": material, "vertices": [[round(c, 6) for c in v] for v in vs]}


def scene(patches, lights, resolution):
    rooms = ROOMS * ROOMS
    p = math.sqrt(ROOM_AREA * rooms / patches)
    shapes, lamps = [], []
    W, H, D = ROOM
    for r in range(rooms):
        x0, z0 = (r % ROOMS) * (W + GAP), (r // ROOMS) * (D + GAP)
        x1, z1 = x0 + W, z0 + D
        # normals inward (counter-clockwise seen from inside)
        shapes.append(quad("white", [[x1, 0, z0], [x0, 0, z0], [x0, 0, z1], [x1, 0, z1]]))  # floor, +y
        shapes.append(quad("white", [[x1, H, z0], [x1, H, z1], [x0, H, z1], [x0, H, z0]]))  # ceiling, -y
        shapes.append(quad("white", [[x0, 0, z0], [x1, 0, z0], [x1, H, z0], [x0, H, z0]]))  # z0 wall, +z
        shapes.append(quad("white", [[x1, 0, z1], [x0, 0, z1], [x0, H, z1], [x1, H, z1]]))  # z1 wall, -z
        shapes.append(quad("red", [[x0, 0, z1], [x0, 0, z0], [x0, H, z0], [x0, H, z1]]))    # x0 wall, +x
        shapes.append(quad("green", [[x1, 0, z0], [x1, 0, z1], [x1, H, z1], [x1, H, z0]]))  # x1 wall, -x
        bx, bz = x0 + 0.3 * W, z0 + 0.55 * D
        shapes.append({"type": "box", "material": "white", "min": [round(bx, 6), 0, round(bz, 6)],
                       "max": [round(bx + BOX, 6), BOX, round(bz + BOX, 6)]})
    for l in range(lights):
        r, k = l % rooms, (l // rooms) % len(PATTERN)
        x0, z0 = (r % ROOMS) * (W + GAP), (r // ROOMS) * (D + GAP)
        fx, fz = PATTERN[k]
        lamps.append({"type": "point", "position": [round(x0 + fx * W, 6), round(2.0 + 0.04 * (l // rooms % 16), 6),
                                                     round(z0 + fz * D, 6)], "power": 50})
    return {
        "description": f"preprocess scaling: {rooms} rooms, about {patches} patches, {lights} point lights",
        "camera": {"position": [2, 1.5, 0.5], "look_at": [2, 1.5, 4], "up": [0, 1, 0], "fov_y": 60, "resolution": [64, 64]},
        "materials": {"white": {"type": "diffuse", "albedo": 0.7}, "red": {"type": "diffuse", "albedo": [0.6, 0.1, 0.1]},
                      "green": {"type": "diffuse", "albedo": [0.1, 0.6, 0.1]}},
        "shapes": shapes,
        "lights": lamps,
        "settings": {"patch_size": p, "min_patch_size": p, "item_buffer_resolution": resolution},
    }


def run(args, n, m, tmp):
    path = os.path.join(tmp, f"scaling-{n}-{m}.json")
    with open(path, "w") as f:
        json.dump(scene(n, m, args.resolution), f)
    out = os.path.join(tmp, "out.fsd")
    cmd = ["/usr/bin/time", "-f", "TIME %e %U %M", os.path.join(args.build, "preprocess", "firstshot-preprocess"), path,
           "-o", out, "--backend", args.backend, "-q", "--time", str(args.time_limit)]
    if args.threads:
        cmd += ["--threads", str(args.threads)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    t = re.search(r"TIME ([\d.]+) ([\d.]+) (\d+)", p.stderr)
    s = re.search(r"(\d+) light samples .*?, (\d+) patches, (\d+) non-zero factors, ([\d.]+) s", p.stdout)
    if p.returncode != 0 or not t or not s:
        return {"n": n, "m": m, "failed": (p.stdout + p.stderr).strip().splitlines()[-1:]}
    os.remove(out)
    return {"n": n, "m": m, "patches": int(s.group(2)), "samples": int(s.group(1)), "nnz": int(s.group(3)),
            "wall": float(t.group(1)), "user": float(t.group(2)), "rss": int(t.group(3)) / 1024.0,
            "preprocess": float(s.group(4))}


def slope(xs, ys):
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    den = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / den if den > 0 else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build/release")
    ap.add_argument("--patches", default="1e4,1e5,1e6")
    ap.add_argument("--lights", default="10,100,1000")
    ap.add_argument("--resolution", type=int, default=128)
    ap.add_argument("--backend", default="embree")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--time-limit", type=float, default=600)
    ap.add_argument("--scene-only", nargs=2, type=int, metavar=("N", "M"))
    args = ap.parse_args()
    if args.scene_only:
        json.dump(scene(args.scene_only[0], args.scene_only[1], args.resolution), sys.stdout)
        return
    ns = [int(float(x)) for x in args.patches.split(",")]
    ms = [int(float(x)) for x in args.lights.split(",")]
    rows = []
    print(f"backend {args.backend}, R = {args.resolution}, load {os.getloadavg()[0]:.2f}")
    print("| patches N | lights M | N·M | wall s | user s | peak RSS MB | non-zeros |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for n in ns:
            for m in ms:
                r = run(args, n, m, tmp)
                if "failed" in r:
                    print(f"| ~{n} | {m} | | failed: {r['failed']} | | | |", flush=True)
                    continue
                rows.append(r)
                print(f"| {r['patches']} | {r['samples']} | {r['patches'] * r['samples']:.3g} | {r['wall']:.2f} | "
                      f"{r['user']:.2f} | {r['rss']:.0f} | {r['nnz']} |", flush=True)
    if len(rows) >= 2:
        nm = [r["patches"] * r["samples"] for r in rows]
        print(f"\nlog-log slope against N·M: wall {slope(nm, [r['wall'] for r in rows]):.3f}, "
              f"user {slope(nm, [r['user'] for r in rows]):.3f} (load {os.getloadavg()[0]:.2f})")


if __name__ == "__main__":
    main()
