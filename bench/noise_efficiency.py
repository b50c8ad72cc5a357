#!/usr/bin/python3
"""noise-efficiency: how much noise each rendering method leaves per second of CPU, without a reference.

For every scene and method, two renders at the same spp with different seeds (firstshot-render, one
thread), their CPU time (user + system of the whole process, first-shot preprocessing not included:
the table is made once here) and the error of their difference (firstshot-compare): the difference
of two independent images has twice the variance of one, so an image's own noise is rel. RMSE(a, b)/√2
(likewise MARE). Efficiency = 1/(noise² · seconds): a method twice as efficient reaches the same noise
in half the time. Bias is not seen here (the difference of two images of one method cancels it): the
bias tests and the speed-against-error harness (firstshot_bench.py) cover that.

Usage: bench/noise_efficiency.py [--build DIR] [--spp N] [--width W --height H] [--methods A,B] SCENE...
(scenes/NAME.json; --methods keeps the methods whose label contains one of the comma-separated words).
Prints a Markdown table, one row per scene and method. Standard library only.
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

METHODS = [
    ("path (NEE to every light)", False, ["--light-sampler", "all"]),
    ("path, light tree", False, ["--light-sampler", "tree"]),
    ("path, light tree without visibility", False, ["--light-sampler", "tree", "--light-visibility", "off"]),
    ("first-shot (defaults: light tree, no patch NEE)", True, []),
    ("first-shot, patch NEE at every vertex", True, ["--patch-nee", "every"]),
    ("first-shot, patch NEE at the first vertex", True, ["--patch-nee", "first"]),
    ("first-shot, all small lights at camera hits", True, ["--light-sampler", "all", "--patch-nee", "off"]),
    # The irradiance cache at 4 spp (its records, not the camera samples, carry the indirect light);
    # a pair of runs with different seeds has different records, so record noise is in the measure.
    ("irradiance cache", False, ["--integrator", "irradiance-cache", "--one-pass", "--spp", "4"]),
    ("light tracing (one particle per pixel per pass)", False, ["--integrator", "light"]),
    ("bidirectional path tracing (one sample per pixel per pass)", False, ["--integrator", "bdpt"]),
    ("bidirectional path tracing + first-shot, light subpaths from the lit patches", True,
     ["--integrator", "bdpt", "--shoot-firstshot", "patches"]),
    ("irradiance cache + first-shot, no patch NEE in gathers", True,
     ["--integrator", "irradiance-cache", "--one-pass", "--spp", "4", "--ic-patch-nee", "0"]),
    ("irradiance cache + first-shot, patch NEE in gathers (0.5)", True,
     ["--integrator", "irradiance-cache", "--one-pass", "--spp", "4", "--ic-patch-nee", "0.5"]),
]


def cpu_seconds(cmd):
    """Runs cmd; returns the CPU seconds (user + system) it took. Exits on failure."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"noise-efficiency: {' '.join(cmd)} failed:\n{r.stderr}")
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(REPO, "build", "release"))
    ap.add_argument("--spp", type=int, default=32)
    ap.add_argument("--width", type=int, default=80)
    ap.add_argument("--height", type=int, default=60)
    ap.add_argument("--methods", default="", help="comma-separated label substrings (default: every method)")
    ap.add_argument("scenes", nargs="+")
    args = ap.parse_args()
    render = os.path.join(args.build, "render", "firstshot-render")
    preprocess = os.path.join(args.build, "preprocess", "firstshot-preprocess")
    compare = os.path.join(args.build, "bench", "firstshot-compare")
    print(f"| scene | method | CPU s per image | rel. RMSE | MARE | efficiency (1/(relRMSE²·s)) | vs best baseline |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.scenes:
            scene = name if os.path.exists(name) else os.path.join(REPO, "scenes", name + ".json")
            fsd = os.path.join(tmp, "t.fsd")
            cpu_seconds([preprocess, scene, "-o", fsd, "--quiet"])
            rows = []
            wanted = [w for w in args.methods.split(",") if w]
            for label, firstshot, extra in METHODS:
                if wanted and not any(w in label for w in wanted):
                    continue
                images, seconds = [], 0.0
                for seed in (1, 2):
                    out = os.path.join(tmp, f"{seed}.exr")
                    spp = [] if "--spp" in extra else ["--spp", str(args.spp)]
                    cmd = [render, scene, "--seed", str(seed), "--threads", "1", "--width", str(args.width), "--height",
                           str(args.height), "--quiet", "-o", out] + spp + extra
                    if firstshot:
                        cmd += ["--firstshot", fsd]
                    seconds += cpu_seconds(cmd)
                    images.append(out)
                r = subprocess.run([compare, images[0], images[1]], capture_output=True, text=True)
                m = json.loads(r.stdout.strip().splitlines()[-1])
                rel, mare = m["rel_rmse"] / 2 ** 0.5, m["mare"] / 2 ** 0.5
                rows.append((label, firstshot, seconds / 2, rel, mare, 1.0 / (rel * rel * seconds / 2)))
            baselines = [e for label, fs, _, _, _, e in rows if not fs and "irradiance" not in label]
            best = max(baselines) if baselines else None
            for label, _, sec, rel, mare, eff in rows:
                ratio = f"{eff / best:.2f}×" if best else "–"
                print(f"| {name} | {label} | {sec:.2f} | {rel:.3f} | {mare:.3f} | {eff:.2f} | {ratio} |", flush=True)


if __name__ == "__main__":
    main()
