#!/usr/bin/python3
"""Sensor throughput: sensors per second at a stated standard error (docs/measurements.md, "Sensor throughput").

Runs firstshot-render's sensor mode as a user does, once per method (path / irradiance-cache, each without and
with a first-shot table), at --samples N, and reads the JSON output and the timings the tool prints on stderr.
Per method it reports the estimate's seconds (the sensor loop), the integrator's own preprocessing for the
sensors (the irradiance cache's fill from the sensors' rays) and the first-shot preprocessing (firstshot-preprocess
wall time, run once per scene and stated separately), the grid's E_avg and the largest relative standard error
max_i(stderr_i)/E_avg. Standard errors fall as 1/sqrt(samples), so the time for every sensor to reach the target
(default: stderr <= 2% of E_avg) is the estimate's seconds x (max stderr / target)^2 (each sample costs about the
same); sensors/s at the target = sensors / that time (+ the fill, which does not grow with the samples).
stderr is sigma/sqrt(n) from the samples: for the irradiance cache it is the noise at fixed records only (the
records' own error is shared by neighbouring sensors; tests/test_sensors_cache.cpp bounds its bias).

  bench/sensor_throughput.py [--build build/release] [--scene scenes/many-lights.json]
      [--grid-quad floor,0.75,0.25] [--samples 64] [--target 0.02] [--threads N] [--methods path,ic,...]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

METHODS = {  # name: (integrator, first-shot)
    "path": ("path", False),
    "path+firstshot": ("path", True),
    "ic": ("irradiance-cache", False),
    "ic+firstshot": ("irradiance-cache", True),
}


def run(cmd):
    start = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True)
    seconds = time.monotonic() - start
    if p.returncode != 0:
        sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stderr}")
    return p, seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build/release")
    ap.add_argument("--scene", default="scenes/many-lights.json")
    ap.add_argument("--grid-quad", default="floor,0.75,0.25")
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--target", type=float, default=0.02, help="stderr / E_avg to reach")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--methods", default=",".join(METHODS))
    a = ap.parse_args()
    render = os.path.join(a.build, "render", "firstshot-render")
    preprocess = os.path.join(a.build, "preprocess", "firstshot-preprocess")
    threads = ["--threads", str(a.threads)] if a.threads > 0 else []
    with tempfile.TemporaryDirectory() as tmp:
        fsd, fsdSeconds = os.path.join(tmp, "scene.fsd"), None
        print(f"{a.scene}, --grid-quad {a.grid_quad}, {a.samples} samples, target stderr <= {100 * a.target:g}% of E_avg")
        print("| method | sensors | E_avg (lx) | rms stderr/E_avg | max stderr/E_avg | estimate (s) | fill (s) "
              "| first-shot (s) | to target (s) | sensors/s at target |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for name in a.methods.split(","):
            integrator, firstShot = METHODS[name]
            if firstShot and fsdSeconds is None:
                _, fsdSeconds = run([preprocess, a.scene, "-o", fsd, "-q"] + threads)
            out = os.path.join(tmp, name + ".json")
            cmd = [render, a.scene, "--grid-quad", a.grid_quad, "--integrator", integrator, "--samples", str(a.samples),
                   "-o", out] + threads + (["--firstshot", fsd] if firstShot else [])
            p, _ = run(cmd)
            m = re.search(r"(\d+) sensors at (\d+) samples in ([0-9.]+) s", p.stderr)
            fill = re.search(r"preprocess for the sensors: ([0-9.]+) s", p.stderr)
            estimate, fillSeconds = float(m.group(3)), float(fill.group(1)) if fill else 0.0
            s = json.load(open(out))["sets"][0]
            worst = max(row[10] for row in s["rows"]) / s["E_avg"]
            rms = (sum(row[10] ** 2 for row in s["rows"]) / len(s["rows"])) ** 0.5 / s["E_avg"]
            toTarget = max(estimate, 1e-3) * (worst / a.target) ** 2
            sensors = len(s["rows"])
            print(f"| {name} | {sensors} | {s['E_avg']:.2f} | {100 * rms:.2f}% | {100 * worst:.2f}% | {estimate:.3f} "
                  f"| {fillSeconds:.2f} "
                  f"| {fsdSeconds if firstShot else 0:.2f} | {toTarget + fillSeconds:.1f} "
                  f"| {sensors / (toTarget + fillSeconds):.1f} |", flush=True)


if __name__ == "__main__":
    main()
