"""The preprocessing accuracy report: r_ij error against the analytic value vs item-buffer resolution R and patch
width in pixels (firstshot-preprocess-accuracy), cornell's preprocessing time vs R, and their plot (matplotlib,
imported when plotting).
"""
import csv
import math
import os
import shlex
import sys

from .analysis import median
from .config import REPO, rotated
from .tools import log, parse_preprocess_summary, read_rows, run


def accuracy_report(tools, args):
    log("== preprocessing accuracy: r_ij against the analytic value vs R and patch width")
    acc_csv = os.path.join(args.out, "preprocess_accuracy.csv")
    cmd = [tools.accuracy, "-o", acc_csv, "--threads", str(args.threads), "--resolutions",
           ",".join(map(str, args.accuracy_resolutions))]
    if args.quick:
        cmd += ["--backends", "gl", "--patch-sizes", "0.1,0.025"]
    rc, wall, text = run(cmd)
    if rc != 0:
        sys.exit(f"firstshot-bench: {shlex.join(cmd)} failed:\n{text}")
    log(f"  {acc_csv} in {wall:.1f} s")
    log("== preprocessing time vs R (cornell)")
    scene = os.path.join(REPO, "scenes", "cornell.json")
    fsd = os.path.join(args.out, "preprocess_time.fsd")
    rows = []
    backends = ["gl"] if args.quick else ["gl", "embree"]
    for rep in range(args.reps):
        for i, R in enumerate(args.accuracy_resolutions):
            for backend in rotated(backends, rep + i):
                if backend == "embree" and R > 512:
                    continue  # 20 s a run on 2 cores: the trend is clear by 512
                c = [tools.preprocess, scene, "-o", fsd, "--resolution", str(R), "--backend", backend,
                     "--threads", str(args.threads), "--quiet"]
                load = os.getloadavg()[0]
                rc, wall, text = run(c)
                rows.append({"backend": backend, "resolution": R, "rep": rep, "wall_s": round(wall, 4),
                             "reported_s": parse_preprocess_summary(text) if rc == 0 else "",
                             "status": "ok" if rc == 0 else f"exit {rc}", "threads": args.threads,
                             "load_avg_1m": round(load, 2), "cmd": shlex.join(c)})
                log(f"  rep {rep} R {R:5d} {backend:6s}: {wall:.2f} s")
    time_csv = os.path.join(args.out, "preprocess_time.csv")
    with open(time_csv, "w", newline="") as f:
        f.write("# cornell preprocessing time vs R: wall time of the whole firstshot-preprocess process, and its own timer\n")
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    plot_accuracy(acc_csv, time_csv, os.path.join(args.out, "preprocess_accuracy.png"))


def plot_accuracy(acc_csv, time_csv, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    acc = read_rows(acc_csv)
    times = read_rows(time_csv)
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6), dpi=100)
    floor = 1e-9  # only keeps exact zeros on the log axis; the analytic estimator's ~3e-8 is float rounding
    # (a) RMS error vs patch width in pixels, pooled over R and patch sizes, per back end and estimator.
    for (backend, est) in sorted({(r["backend"], r["estimator"]) for r in acc}):
        bins = {}
        for r in acc:
            if r["backend"] == backend and r["estimator"] == est:
                lo = float(r["width_px_lo"])
                n, s = bins.get(lo, (0, 0.0))
                bins[lo] = (n + int(r["patches"]), s + int(r["patches"]) * float(r["rms_rel_error"]) ** 2)
        xs = sorted(bins)
        axes[0].loglog([x * math.sqrt(2) for x in xs], [max(floor, math.sqrt(bins[x][1] / bins[x][0])) for x in xs],
                       "o-", markersize=3, label=f"{est} ({backend})")
    axes[0].set_xlabel("patch width on the cube face (pixels)")
    axes[0].set_ylabel("RMS relative error of r_ij")
    axes[0].set_title("error vs patch width (all R; gl and embree coincide)", fontsize=9)
    # (b) RMS error vs R for the largest, a middle and the smallest patch size (gl back end), per estimator.
    gl = [r for r in acc if r["backend"] == "gl"]
    sizes = sorted({float(r["patch_size_m"]) for r in gl}, reverse=True)
    sizes = sorted({sizes[0], sizes[len(sizes) // 2], sizes[-1]}, reverse=True)
    for est, style in (("pixels", "o-"), ("analytic", "s--")):
        for ci, ps in enumerate(sizes):
            by_r = {}
            for r in gl:
                if r["estimator"] == est and float(r["patch_size_m"]) == ps:
                    n, s = by_r.get(int(r["resolution"]), (0, 0.0))
                    by_r[int(r["resolution"])] = (n + int(r["patches"]), s + int(r["patches"]) * float(r["rms_rel_error"]) ** 2)
            if by_r:
                xs = sorted(by_r)
                axes[1].loglog(xs, [max(floor, math.sqrt(by_r[x][1] / by_r[x][0])) for x in xs], style, markersize=3,
                               color=f"C{ci}", label=f"{est}, {ps:g} m patches")
    axes[1].set_xlabel("item-buffer resolution R")
    axes[1].set_ylabel("RMS relative error of r_ij")
    axes[1].set_title("error vs R (gl; patch size)", fontsize=9)
    # (c) cornell preprocessing time vs R.
    for backend in sorted({r["backend"] for r in times}):
        by_r = {}
        for r in times:
            if r["backend"] == backend and r["status"] == "ok":
                by_r.setdefault(int(r["resolution"]), []).append(float(r["wall_s"]))
        xs = sorted(by_r)
        axes[2].loglog(xs, [median(by_r[x]) for x in xs], "o-", markersize=3, label=backend)
    axes[2].set_xlabel("item-buffer resolution R")
    axes[2].set_ylabel("cornell preprocessing wall time (s)")
    axes[2].set_title("preprocessing time (median)", fontsize=9)
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
