#!/usr/bin/env python3
"""MPI speed-up on this machine (docs/mpi.md): wall time of the -mpi tools under `mpirun -np 1` and `-np 2`, one
thread per rank, against the MPI-free tool with one and with two threads, for the preprocessor and every
integrator; and the data rank 0 sends.

    /usr/bin/python3 bench/mpi_speedup.py [--build build/release] [--ranks 1,2] [--reps 1]

prints one Markdown row per case: whole-process wall times, and the time of the work itself as the tool reports
it (the preprocessor's table, the render loop; without start-up, scene and table loading). The first-shot table the renders use is made once (cornell, default settings).
Needs the build made with -DFIRSTSHOT_MPI=ON. Standard library only.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def run(cmd):
    t = time.perf_counter()
    r = subprocess.run(cmd, env=ENV, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.perf_counter() - t
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)}\n{r.stdout}")
    sent = re.search(r"rank 0 sent ([0-9.]+) MB", r.stdout)
    loop = re.search(r"spp in ([0-9.]+) s", r.stdout) or re.search(r"factors, ([0-9.]+) s", r.stdout)
    return wall, float(sent.group(1)) if sent else 0.0, float(loop.group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build/release"))
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--reps", type=int, default=1, help="repetitions; the fastest counts")
    a = ap.parse_args()
    pre, ren = os.path.join(a.build, "preprocess/firstshot-preprocess"), os.path.join(a.build, "render/firstshot-render")
    ranks = [int(n) for n in a.ranks.split(",")]
    tmp = tempfile.mkdtemp(prefix="fs_mpi_")
    cornell = os.path.join(ROOT, "scenes/cornell.json")
    fsd = os.path.join(tmp, "cornell.fsd")
    run([pre, cornell, "-o", fsd])
    render = [cornell, "--firstshot", fsd, "-o", os.path.join(tmp, "x.exr"), "--width", "256", "--height", "256"]
    cases = [
        ("preprocess office-floor (gl)", pre, [os.path.join(ROOT, "scenes/office-floor.json"), "-o", os.path.join(tmp, "o.fsd")]),
        ("preprocess cornell, R = 512", pre, [cornell, "--resolution", "512", "-o", os.path.join(tmp, "c.fsd")]),
        ("render path, 32 spp", ren, render + ["--integrator", "path", "--spp", "32"]),
        ("render irradiance-cache, 8 spp", ren, render + ["--integrator", "irradiance-cache", "--spp", "8"]),
        ("render light, 16 passes", ren, render + ["--integrator", "light", "--spp", "16"]),
        ("render bdpt, 8 spp", ren, render + ["--integrator", "bdpt", "--spp", "8"]),
        ("render bundle, 32 iterations", ren, render + ["--integrator", "bundle", "--spp", "32"]),
    ]
    head = "| case | 1 process, 1 thread | 1 process, 2 threads | " + " | ".join(
        f"mpirun -np {n}, 1 thread each" for n in ranks) + f" | speed-up np {ranks[0]} → {ranks[-1]} | of the work itself | rank 0 sent (np {ranks[-1]}) |"
    print(head)
    print("|" + "---|" * (head.count("|") - 1))
    for name, exe, args in cases:
        def best(cmd):
            return min((run(cmd) for _ in range(a.reps)), key=lambda r: r[0])
        t1 = best([exe] + args + ["--threads", "1"])[0]
        t2 = best([exe] + args + ["--threads", "2"])[0]
        mpi = [best(["mpirun", "--oversubscribe", "--bind-to", "none", "-np", str(n), exe + "-mpi"] + args + ["--threads", "1"])
               for n in ranks]
        cells = " | ".join(f"{w:.2f} s" for w, _, _ in mpi)
        print(f"| {name} | {t1:.2f} s | {t2:.2f} s | {cells} | {mpi[0][0] / mpi[-1][0]:.2f}× | "
              f"{mpi[0][2]:.2f} → {mpi[-1][2]:.2f} s, {mpi[0][2] / mpi[-1][2]:.2f}× | {mpi[-1][1]:.2f} MB |", flush=True)


if __name__ == "__main__":
    main()
