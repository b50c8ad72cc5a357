#!/usr/bin/env python3
"""How well --integrator auto's pilot projects each candidate's error: its projected render error against the error
the candidate's own render reaches, forced, at the same time and size.

usage: bench/pilot_calibration.py BUILD OUT SCENE [--time S] [--size W H] [--table T] [--core C]
  BUILD: build/release; OUT: a folder for the images; SCENE: a scene file; --time (default 20) and --size (default
  128 128) as each render is given them, one thread, pinned to core C (default 0); --table: the scene's first-shot
  table (made at the preprocessor's defaults into OUT where not given).
The defaults' pilot runs once (seed 1) and prints each candidate's projected error ("render err"); each measured
candidate is then rendered forced with its options (the cache at the rays per record the pilot gave it) for seeds 1
and 2, and its noise measured outside the lamps' pixels (bench/noise_lamps.py). Prints a Markdown table: candidate,
projected, measured, measured / projected. The ratio is what matters between candidates: all share the host's ray
rate against the pilot's nominal one (kTimeRaysRate), a candidate whose ratio stands apart is misjudged by the pilot.
"""
import os
import re
import subprocess
import sys
import time


def main():
    args = sys.argv[1:]
    if len(args) < 3:
        sys.exit(__doc__)
    build, out, scene = args[:3]
    seconds, size, table, core = "20", ["128", "128"], None, "0"
    i = 3
    while i < len(args):
        if args[i] == "--time":
            seconds, i = args[i + 1], i + 2
        elif args[i] == "--size":
            size, i = args[i + 1:i + 3], i + 3
        elif args[i] == "--table":
            table, i = args[i + 1], i + 2
        elif args[i] == "--core":
            core, i = args[i + 1], i + 2
        else:
            sys.exit(f"pilot_calibration: unknown argument {args[i]}\n{__doc__}")
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    render = os.path.join(build, "render", "firstshot-render")
    os.makedirs(out, exist_ok=True)
    pin = ["taskset", "-c", core]
    if table is None:
        table = os.path.join(out, "table.fsd")
        if not os.path.exists(table):
            subprocess.run(pin + [os.path.join(build, "preprocess", "firstshot-preprocess"), scene, "-o", table,
                                  "--threads", "1", "-q"], check=True)
    common = ["--threads", "1", "--width", size[0], "--height", size[1], "--time", seconds]
    lamps = os.path.join(out, "lamps.exr")
    subprocess.run(pin + [render, scene, "--integrator", "path", "--max-depth", "0", "--spp", "256", "--threads", "1",
                          "--width", size[0], "--height", size[1], "--quiet", "-o", lamps], check=True)
    # The defaults' pilot alone: stopped once the choice is printed.
    p = subprocess.Popen(pin + [render, scene, "--firstshot", table, *common, "--seed", "1", "-o",
                                os.path.join(out, "auto.exr")], stderr=subprocess.PIPE, stdout=subprocess.DEVNULL,
                         text=True)
    rows, records, shown = [], {}, False
    for line in p.stderr:
        shown = shown or "pilot at" in line
        if shown:
            print(line.rstrip(), file=sys.stderr)
        m = re.match(r"  (\S.*?)\s+(\d+)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)\s+(\S+)\s+([\d.]+)", line)
        if shown and m:
            rows.append((m.group(1), float(m.group(7))))
        m = re.match(r"  (\S.*?): filled at .*? at (\d+) hemisphere rays per record", line)
        if m:
            records[m.group(1)] = m.group(2)
        if "auto chose" in line:
            break
    p.kill()
    p.wait()
    print("| candidate | projected | measured | measured / projected |")
    print("|---|---|---|---|")
    for label, projected in rows:
        parts = label.split(", no table")
        words = parts[0].split()
        opts = ["--integrator", words[0], *words[1:]]
        if len(parts) == 1:
            opts += ["--firstshot", table]
        if label in records:
            opts += ["--ic-samples", records[label]]
        tag = re.sub(r"[^a-z0-9]+", "-", label.lower()).strip("-")
        images = []
        for s in ("1", "2"):
            image = os.path.join(out, f"{tag}-{s}.exr")
            subprocess.run(pin + [render, scene, *common, "--seed", s, "--quiet", "-o", image, *opts], check=True)
            images.append(image)
        noise = subprocess.run([sys.executable, os.path.join(here, "bench", "noise_lamps.py"), lamps, *images],
                               capture_output=True, text=True, check=True).stdout.split()[0]
        ratio = float(noise) / projected if projected > 0 else float("nan")
        print(f"| {label} | {projected:.4f} | {float(noise):.4f} | {ratio:.2f} |", flush=True)


if __name__ == "__main__":
    t = time.time()
    main()
    print(f"pilot_calibration: {time.time() - t:.0f} s", file=sys.stderr)
