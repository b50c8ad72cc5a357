"""Running the command-line tools (Tools: the paths of firstshot-preprocess, firstshot-render, firstshot-compare and
firstshot-preprocess-accuracy under the build folder), timing them, reading their summary lines, comparing and
averaging images with firstshot-compare, logging, and the results CSV (write_rows, read_rows).
"""
import csv
import json
import os
import re
import subprocess
import sys
import time

from .config import CSV_FIELDS, CSV_HEADER


def parse_render_summary(text):
    """(spp, seconds) from firstshot-render's summary line 'WxH at N spp in S s: ...', or (None, None)."""
    m = re.search(r"\bat (\d+) spp in ([0-9.]+) s", text)
    return (int(m.group(1)), float(m.group(2))) if m else (None, None)


def parse_preprocess_summary(text):
    """Seconds from firstshot-preprocess's summary line '..., N non-zero factors, S s, ...', or None."""
    m = re.search(r"non-zero factors, ([0-9.]+) s\b", text)
    return float(m.group(1)) if m else None


class Tools:
    def __init__(self, build):
        self.preprocess = os.path.join(build, "preprocess", "firstshot-preprocess")
        self.render = os.path.join(build, "render", "firstshot-render")
        self.ref_render = self.render  # the reference's renderer (--ref-render)
        self.compare = os.path.join(build, "bench", "firstshot-compare")
        self.accuracy = os.path.join(build, "bench", "firstshot-preprocess-accuracy")

    def check(self, need_accuracy):
        needed = [self.preprocess, self.render, self.ref_render, self.compare] + ([self.accuracy] if need_accuracy else [])
        missing = [p for p in needed if not os.access(p, os.X_OK)]
        if missing:
            sys.exit("firstshot-bench: missing " + ", ".join(missing) + " (build first: make build, or cmake --build BUILD)")


def run(cmd, timeout=None):
    """Runs @p cmd; returns (returncode, wall seconds, stdout+stderr). returncode None on timeout."""
    t0 = time.perf_counter()
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout)
        return p.returncode, time.perf_counter() - t0, p.stdout
    except subprocess.TimeoutExpired as e:
        out = e.output.decode() if isinstance(e.output, bytes) else (e.output or "")
        return None, time.perf_counter() - t0, out


def compare(tools, image, reference):
    rc, _, out = run([tools.compare, image, reference])
    if rc != 0:
        raise RuntimeError(f"firstshot-compare failed on {image}: {out.strip()}")
    return json.loads(out)


def mean_images(tools, a, b, out):
    rc, _, text = run([tools.compare, "--mean", a, b, "-o", out])
    if rc != 0:
        sys.exit(f"firstshot-bench: firstshot-compare --mean {a} {b} failed: {text.strip()}")


def last_line(text, rc):
    """The last line of a tool's output that says something (CLI11 ends its errors with 'Run with --help ...')."""
    lines = [ln.strip() for ln in text.strip().splitlines() if ln.strip() and not ln.startswith("Run with --help")]
    return lines[-1] if lines else f"exit code {rc}"


def log(msg):
    print(msg, flush=True)


def write_rows(path, rows):
    with open(path, "w", newline="") as f:
        f.write(CSV_HEADER)
        w = csv.DictWriter(f, fieldnames=CSV_FIELDS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in CSV_FIELDS})


def read_rows(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))
