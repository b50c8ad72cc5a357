#!/usr/bin/python3
"""firstshot-bench: how fast the error falls for each rendering method (speed against error).

Drives the command-line tools exactly as a user runs them (firstshot-preprocess, firstshot-render) and
compares every image with a cached path-traced reference (firstshot-compare). For each scene:

1. reference: plain path tracing at --ref-spp samples per pixel, rendered as two halves with different
   seeds and averaged. It is cached in OUT/<scene>/reference.exr with its settings in reference.json
   (scene file sha256, spp, seeds, size, renderer binary size and mtime) and re-rendered when any differs.
   Its own noise is estimated from the halves: rel. RMSE(half A, mean) estimates the mean's error, since
   A - mean = (A - B)/2 has the distribution of the mean's error. The error curves flatten there.
2. every method at every time budget (firstshot-render --time B), repetitions with different seeds,
   methods interleaved (the order rotates from run to run). A method "X+firstshot" runs
   firstshot-preprocess once per repetition and renders integrator X with --firstshot; its total time
   is preprocess wall time + render wall time, both recorded. Any method name is accepted: the harness
   probes each one with a 1-spp render first and skips (with a note) a method the renderer rejects.
   A run is killed after 4*budget+10 s (a method that ignores the budget, e.g. an irradiance cache
   filling its records first); it is then not run again at budgets up to that one.
3. OUT/<scene>/results.csv (one row per run, exact command lines, load average), the combined
   OUT/results.csv, OUT/error_vs_time_<scene>.png and OUT/table_<scene>.md (medians over repetitions,
   the time to reach the target error, the speed-up of every method over the first one).

Errors (bench/image_metrics.h, computed by firstshot-compare over all pixels and RGB channels, x: image,
r: reference, eps = 0.01 * mean(r)):
  rel. RMSE = sqrt(mean(((x - r)/(r + eps))^2)),  MARE = mean(|x - r|/(r + eps)),  NRMSE = RMSE/mean(r).

The time to reach the target error interpolates the median curve (median total time, median error)
linearly in log-log between the two budgets around the first crossing.

Also (unless --no-accuracy): the preprocessing accuracy report, r_ij error against the analytic value
vs R and patch width in pixels (firstshot-preprocess-accuracy), and cornell's preprocessing time vs R.

Standard library only, plus matplotlib (Debian's python3-matplotlib) for the plots.
"""
import argparse
import csv
import hashlib
import io
import json
import math
import os
import re
import shlex
import shutil
import statistics
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Per-scene defaults: reference spp (bounded so a reference takes a few minutes on 2 cores at 160x120)
# and the target error (rel. RMSE) for the time-to-target column, chosen above the reference's noise.
SCENE_DEFAULTS = {
    "cornell": {"ref_spp": 4096, "target": 0.10},
    "many-lights": {"ref_spp": 512, "target": 0.25},
    "sierpinski-glossy": {"ref_spp": 2048, "target": 0.10},
    "ward-sphere": {"ref_spp": 2048, "target": 0.05},
}
FALLBACK_DEFAULTS = {"ref_spp": 1024, "target": 0.10}

# Extra renderer arguments per integrator, used unless --method-args overrides them. The irradiance
# cache's defaults (512 samples, 3 bounces) fill ~2*10^5 records on cornell at 160x120, a minute on 2
# cores, far past the budgets; the bench uses a cheaper cache (5-7 s on cornell, ~20 s on many-lights,
# whose 64 lights are all shadow-tested at every hemisphere sample). The CSV shows exactly what ran.
DEFAULT_METHOD_ARGS = {
    "irradiance-cache": ["--ic-samples", "128", "--bounces", "2"],
}

FIRSTSHOT_SUFFIX = "+firstshot"

CSV_FIELDS = [
    "scene", "method", "budget_s", "rep", "seed", "status", "spp", "render_wall_s", "render_reported_s",
    "preprocess_wall_s", "preprocess_reported_s", "total_s", "rel_rmse", "mare", "nrmse", "ref_noise_rel_rmse",
    "threads", "width", "height", "load_avg_1m", "render_cmd", "preprocess_cmd", "note",
]

CSV_HEADER = """# firstshot-bench results: one row per run.
# total_s = preprocess_wall_s + render_wall_s (wall times of the whole processes; *_reported_s: the tools' own timers).
# rel_rmse = sqrt(mean(((x-r)/(r+eps))^2)), mare = mean(|x-r|/(r+eps)), nrmse = RMSE/mean(r); over all pixels and RGB
# channels, x: image, r: reference (path tracing, ref_spp), eps = 0.01*mean(r). ref_noise_rel_rmse: the reference's own
# estimated error. load_avg_1m: the machine's 1-minute load average when the run started (shared machine).
"""


# ----------------------------------------------------------------------------------------------------
# Maths (tested by bench/test_firstshot_bench.py)

def median(values):
    """Median of the finite values, or NaN if there are none."""
    v = [x for x in values if x is not None and math.isfinite(x)]
    return statistics.median(v) if v else float("nan")


def time_to_reach(times, errors, target):
    """Time at which a curve first reaches @p target error.

    times/errors: the median curve, one point per budget. Points are sorted by time; the crossing is
    interpolated linearly in (log t, log e) between the last point above the target and the first at or
    below it. Returns (time, kind): kind "interpolated"; "at_or_before" when the first point is already at
    or below the target (time is that point's); "not_reached" (time NaN) when no point reaches it.
    """
    pts = sorted((t, e) for t, e in zip(times, errors) if t > 0 and e > 0 and math.isfinite(t) and math.isfinite(e))
    if not pts or not (target > 0):
        return float("nan"), "not_reached"
    if pts[0][1] <= target:
        return pts[0][0], "at_or_before"
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        if e1 <= target:
            if e1 == e0:
                return t1, "interpolated"
            s = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + s * (math.log(t1) - math.log(t0))), "interpolated"
    return float("nan"), "not_reached"


def loglog_slope(times, errors):
    """Least-squares slope of log(error) against log(time) (-0.5 for unbiased Monte Carlo)."""
    pts = [(math.log(t), math.log(e)) for t, e in zip(times, errors) if t > 0 and e > 0 and math.isfinite(t * e)]
    if len(pts) < 2:
        return float("nan")
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx if sxx > 0 else float("nan")


def split_method(name):
    """'path+firstshot' -> ('path', True); 'irradiance-cache' -> ('irradiance-cache', False)."""
    if name.endswith(FIRSTSHOT_SUFFIX):
        return name[: -len(FIRSTSHOT_SUFFIX)], True
    return name, False


def rotated(items, k):
    """items rotated left by k (interleaving: each run starts with a different method)."""
    if not items:
        return []
    k %= len(items)
    return items[k:] + items[:k]


def parse_render_summary(text):
    """(spp, seconds) from firstshot-render's summary line 'WxH at N spp in S s: ...', or (None, None)."""
    m = re.search(r"\bat (\d+) spp in ([0-9.]+) s", text)
    return (int(m.group(1)), float(m.group(2))) if m else (None, None)


def parse_preprocess_summary(text):
    """Seconds from firstshot-preprocess's summary line '..., N non-zero factors, S s, ...', or None."""
    m = re.search(r"non-zero factors, ([0-9.]+) s\b", text)
    return float(m.group(1)) if m else None


def sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def binary_identity(path):
    st = os.stat(path)
    return {"path": os.path.abspath(path), "size": st.st_size, "mtime": int(st.st_mtime)}


def reference_key(scene_path, renderer, spp, seeds, width, height):
    """The settings a cached reference must match (anything else: render it again)."""
    return {
        "scene_sha256": sha256_file(scene_path),
        "renderer": binary_identity(renderer),
        "integrator": "path",
        "spp": spp,
        "seeds": list(seeds),
        "width": width,
        "height": height,
        "max_depth": "scene settings",
    }


def fmt_num(x, digits=3):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "–"
    return f"{x:.{digits}g}"


# ----------------------------------------------------------------------------------------------------
# Running the tools

class Tools:
    def __init__(self, build):
        self.preprocess = os.path.join(build, "preprocess", "firstshot-preprocess")
        self.render = os.path.join(build, "render", "firstshot-render")
        self.compare = os.path.join(build, "bench", "firstshot-compare")
        self.accuracy = os.path.join(build, "bench", "firstshot-preprocess-accuracy")

    def check(self, need_accuracy):
        needed = [self.preprocess, self.render, self.compare] + ([self.accuracy] if need_accuracy else [])
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


def log(msg):
    print(msg, flush=True)


# ----------------------------------------------------------------------------------------------------
# Reference

def ensure_reference(tools, scene_name, scene_path, sdir, args):
    spp = args.ref_spp or SCENE_DEFAULTS.get(scene_name, FALLBACK_DEFAULTS)["ref_spp"]
    half = max(1, spp // 2)
    seeds = (args.ref_seed, args.ref_seed + 1)
    key = reference_key(scene_path, tools.render, 2 * half, seeds, args.width, args.height)
    ref_exr = os.path.join(sdir, "reference.exr")
    ref_json = os.path.join(sdir, "reference.json")
    if os.path.exists(ref_exr) and os.path.exists(ref_json):
        with open(ref_json) as f:
            cached = json.load(f)
        if cached.get("key") == key:
            log(f"  reference: cached ({2 * half} spp, noise rel. RMSE {cached['noise_rel_rmse']:.4f})")
            return cached
        log("  reference: settings changed, rendering again")
    halves, cmds, seconds = [], [], []
    for i, seed in enumerate(seeds):
        out = os.path.join(sdir, f"reference_half_{'ab'[i]}.exr")
        cmd = [tools.render, scene_path, "--integrator", "path", "--spp", str(half), "--seed", str(seed),
               "--threads", str(args.threads), "--width", str(args.width), "--height", str(args.height), "-o", out]
        log(f"  reference half {'AB'[i]}: {half} spp, seed {seed} ...")
        rc, wall, text = run(cmd)
        if rc != 0:
            sys.exit(f"firstshot-bench: the reference render failed:\n{shlex.join(cmd)}\n{text}")
        halves.append(out), cmds.append(shlex.join(cmd)), seconds.append(wall)
    rc, _, text = run([tools.compare, "--mean", halves[0], halves[1], "-o", ref_exr])
    if rc != 0:
        sys.exit(f"firstshot-bench: averaging the reference halves failed: {text}")
    noise = compare(tools, halves[0], ref_exr)
    info = {"key": key, "commands": cmds, "seconds": seconds, "noise_rel_rmse": noise["rel_rmse"],
            "noise_mare": noise["mare"], "noise_nrmse": noise["nrmse"], "threads": args.threads,
            "note": "noise_*: error of half A against the mean, an estimate of the reference's own error"}
    with open(ref_json, "w") as f:
        json.dump(info, f, indent=2)
    log(f"  reference: {2 * half} spp in {sum(seconds):.0f} s, noise rel. RMSE {noise['rel_rmse']:.4f}")
    return info


# ----------------------------------------------------------------------------------------------------
# Methods

def method_args(method, args):
    integrator, _ = split_method(method)
    if method in args.method_args:
        return args.method_args[method]
    if integrator in args.method_args:
        return args.method_args[integrator]
    return DEFAULT_METHOD_ARGS.get(integrator, [])


def render_cmd(tools, scene_path, method, fsd, budget, seed, out, args):
    integrator, _ = split_method(method)
    cmd = [tools.render, scene_path, "--integrator", integrator]
    if fsd:
        cmd += ["--firstshot", fsd]
    cmd += method_args(method, args)
    cmd += ["--time", f"{budget:g}", "--seed", str(seed), "--threads", str(args.threads),
            "--width", str(args.width), "--height", str(args.height), "-o", out]
    return cmd


def preprocess_cmd(tools, scene_path, fsd, args):
    return [tools.preprocess, scene_path, "-o", fsd, "--threads", str(args.threads), "--quiet"] + args.preprocess_args


def probe_methods(tools, scene_path, sdir, methods, args):
    """Drops the methods the tools reject (one tiny render each); returns (usable, notes)."""
    usable, notes = [], []
    fsd = os.path.join(sdir, "probe.fsd")
    have_fsd = None
    for m in methods:
        integrator, firstshot = split_method(m)
        if firstshot and have_fsd is None:
            rc, _, text = run(preprocess_cmd(tools, scene_path, fsd, args))
            have_fsd = rc == 0
            if not have_fsd:
                notes.append(f"firstshot-preprocess failed on this scene: {text.strip().splitlines()[-1:]}")
        if firstshot and not have_fsd:
            notes.append(f"{m}: skipped (no first-shot table)")
            continue
        cmd = [tools.render, scene_path, "--integrator", integrator] + (["--firstshot", fsd] if firstshot else [])
        cmd += method_args(m, args) + ["--spp", "1", "--width", "8", "--height", "6", "--threads", "1",
                                       "-o", os.path.join(sdir, "probe.exr")]
        rc, _, text = run(cmd, timeout=300)
        if rc == 0:
            usable.append(m)
        else:
            last = text.strip().splitlines()[-1] if text.strip() else f"exit code {rc}"
            notes.append(f"{m}: skipped, the renderer rejected it ({last})")
            log(f"  {m}: skipped ({last})")
    return usable, notes


def bench_scene(tools, scene_name, scene_path, args):
    sdir = os.path.join(args.out, scene_name)
    rdir = os.path.join(sdir, "runs")
    os.makedirs(rdir, exist_ok=True)
    log(f"== {scene_name} ({scene_path}), {args.width}x{args.height}, {args.threads} threads")
    ref = ensure_reference(tools, scene_name, scene_path, sdir, args)
    ref_exr = os.path.join(sdir, "reference.exr")
    methods, notes = probe_methods(tools, scene_path, sdir, args.methods, args)
    rows = []
    dropped = set()
    timed_out = {}  # method -> largest budget at which a run was killed
    run_index = 0
    for rep in range(args.reps):
        seed = args.seed + rep
        # Preprocess once per repetition for every first-shot method (same table for all its budgets).
        pre = {}
        for m in methods:
            if split_method(m)[1] and m not in dropped:
                fsd = os.path.join(rdir, f"rep{rep}.fsd")
                cmd = preprocess_cmd(tools, scene_path, fsd, args)
                rc, wall, text = run(cmd)
                if rc != 0:
                    notes.append(f"{m}: preprocessing failed in repetition {rep}: {text.strip()}")
                    dropped.add(m)
                    continue
                pre[m] = (fsd, wall, parse_preprocess_summary(text), shlex.join(cmd))
        for bi, budget in enumerate(args.budgets):
            for m in rotated(methods, run_index):
                if m in dropped:
                    continue
                if budget <= timed_out.get(m, -1.0):
                    rows.append({"scene": scene_name, "method": m, "budget_s": budget, "rep": rep, "seed": seed,
                                 "status": "skipped", "note": f"timed out at budget {timed_out[m]:g} s before"})
                    continue
                fsd, pwall, preported, pcmd = pre.get(m, (None, 0.0, None, ""))
                out = os.path.join(rdir, f"{m}_{budget:g}_{rep}.exr")
                cmd = render_cmd(tools, scene_path, m, fsd, budget, seed, out, args)
                load = os.getloadavg()[0]
                rc, wall, text = run(cmd, timeout=args.timeout_factor * budget + args.timeout_extra)
                row = {"scene": scene_name, "method": m, "budget_s": budget, "rep": rep, "seed": seed,
                       "render_wall_s": round(wall, 4), "preprocess_wall_s": round(pwall, 4),
                       "preprocess_reported_s": preported, "total_s": round(wall + pwall, 4),
                       "ref_noise_rel_rmse": ref["noise_rel_rmse"], "threads": args.threads, "width": args.width,
                       "height": args.height, "load_avg_1m": round(load, 2), "render_cmd": shlex.join(cmd),
                       "preprocess_cmd": pcmd, "note": ""}
                if rc is None:
                    row["status"] = "timeout"
                    row["note"] = f"killed after {wall:.0f} s"
                    timed_out[m] = max(budget, timed_out.get(m, -1.0))
                    notes.append(f"{m}: killed after {wall:.0f} s at budget {budget:g} s (repetition {rep}); "
                                 f"not run again at budgets up to {budget:g} s")
                elif rc != 0:
                    row["status"] = f"exit {rc}"
                    row["note"] = (text.strip().splitlines() or [""])[-1]
                else:
                    spp, reported = parse_render_summary(text)
                    e = compare(tools, out, ref_exr)
                    row.update(status="ok", spp=spp, render_reported_s=reported, rel_rmse=e["rel_rmse"],
                               mare=e["mare"], nrmse=e["nrmse"])
                    if e.get("non_finite"):
                        row["note"] = f"{e['non_finite']} non-finite values"
                    if not args.keep_images:
                        os.remove(out)
                rows.append(row)
                run_index += 1
                log(f"  rep {rep} budget {budget:g} s {m:>24}: total {row['total_s']:.2f} s, "
                    f"rel. RMSE {fmt_num(row.get('rel_rmse'))}, spp {row.get('spp')} [{row['status']}]")
            run_index += 1  # next budget starts with another method
    write_rows(os.path.join(sdir, "results.csv"), rows)
    return {"scene": scene_name, "rows": rows, "methods": methods, "notes": notes, "ref": ref,
            "target": args.target_error or SCENE_DEFAULTS.get(scene_name, FALLBACK_DEFAULTS)["target"]}


def reload_scene(scene_name, args):
    """The result of an earlier run, from OUT/<scene>/results.csv and reference.json (for --replot)."""
    sdir = os.path.join(args.out, scene_name)
    rows = read_rows(os.path.join(sdir, "results.csv"))
    with open(os.path.join(sdir, "reference.json")) as f:
        ref = json.load(f)
    seen = list(dict.fromkeys(r["method"] for r in rows))
    methods = [m for m in args.methods if m in seen] + [m for m in seen if m not in args.methods]
    notes = [f"{r['method']}: {r['status']} at budget {r['budget_s']} s, repetition {r['rep']} ({r['note']})"
             for r in rows if r["status"] not in ("ok", "skipped")]
    return {"scene": scene_name, "rows": rows, "methods": methods, "notes": notes, "ref": ref,
            "target": args.target_error or SCENE_DEFAULTS.get(scene_name, FALLBACK_DEFAULTS)["target"]}


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


# ----------------------------------------------------------------------------------------------------
# Summaries, tables, plots

def summarize(result):
    """Per method: the median curve over repetitions, one point per budget."""
    curves = {}
    for m in result["methods"]:
        pts = []
        budgets = sorted({float(r["budget_s"]) for r in result["rows"] if r["method"] == m})
        for b in budgets:
            rs = [r for r in result["rows"] if r["method"] == m and float(r["budget_s"]) == b and r["status"] == "ok"]
            if not rs:
                continue
            f = lambda k: median([float(r[k]) for r in rs if r.get(k) not in (None, "")])
            pts.append({"budget": b, "n": len(rs), "total": f("total_s"), "render": f("render_wall_s"),
                        "preprocess": f("preprocess_wall_s"), "spp": f("spp"), "rel_rmse": f("rel_rmse"),
                        "mare": f("mare"), "nrmse": f("nrmse")})
        if pts:
            curves[m] = pts
    return curves


def time_to_target(curve, target, key="rel_rmse"):
    return time_to_reach([p["total"] for p in curve], [p[key] for p in curve], target)


def describe_ttt(t, kind):
    if kind == "not_reached":
        return "not reached"
    if kind == "at_or_before":
        return f"≤ {t:.2f} s"
    return f"{t:.2f} s"


def write_table(result, curves, path):
    target = result["target"]
    noise = result["ref"]["noise_rel_rmse"]
    key = result["ref"]["key"]
    ok = [r for r in result["rows"] if r["status"] == "ok"]
    threads = ok[0]["threads"] if ok else "?"
    reps = len({str(r["rep"]) for r in result["rows"]})
    lines = [f"### {result['scene']}: error against time",
             "",
             f"{key['width']}×{key['height']} px, {threads} threads, medians of {reps} repetitions "
             f"(different seeds), methods interleaved. Reference: path tracing, {key['spp']} spp "
             f"(its own noise: rel. RMSE ≈ {noise:.4f}). Time = whole-process wall time; first-shot methods include "
             f"the preprocessing (its median shown separately). Median load average during the runs: "
             f"{median([float(r['load_avg_1m']) for r in result['rows'] if r.get('load_avg_1m') not in (None, '')]):.1f}.",
             "",
             "| method | budget (s) | total time (s) | of which preprocess (s) | spp | rel. RMSE | MARE |",
             "|---|---|---|---|---|---|---|"]
    for m, pts in curves.items():
        for p in pts:
            lines.append(f"| {m} | {p['budget']:g} | {p['total']:.2f} | {p['preprocess']:.2f} | {fmt_num(p['spp'], 4)} "
                         f"| {p['rel_rmse']:.4f} | {p['mare']:.4f} |")
    lines += ["", f"Time to reach rel. RMSE {target:g} (log-log interpolation of the median curve), and the "
                  f"log-log slope of error against time:", "",
              "| method | time to target | speed-up over " + (next(iter(curves)) if curves else "-") + " | slope |",
              "|---|---|---|---|"]
    base = None
    for m, pts in curves.items():
        t, kind = time_to_target(pts, target)
        if base is None:
            base = (t, kind, pts_max_time(pts))
        slope = loglog_slope([p["total"] for p in pts], [p["rel_rmse"] for p in pts])
        lines.append(f"| {m} | {describe_ttt(t, kind)} | {speedup(base, (t, kind))} | {fmt_num(slope, 2)} |")
    if target < 2 * noise:
        lines += ["", f"Warning: the target {target:g} is less than twice the reference's noise ({noise:.4f})."]
    for n in result["notes"]:
        lines.append(f"\nNote: {n}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return "\n".join(lines)


def minor_label(value, _pos):
    """Labels the minor log ticks 2 and 5 of each decade (matplotlib labels only the decades)."""
    mantissa = value / 10 ** math.floor(math.log10(value) + 1e-9)
    return f"{value:g}" if round(mantissa) in (2, 5) and abs(mantissa - round(mantissa)) < 1e-6 else ""


def why_missing(result, m):
    statuses = {r["status"] for r in result["rows"] if r["method"] == m}
    if "timeout" in statuses:
        return "timed out"
    if m not in result["methods"]:
        return "rejected"
    return "failed"


def pts_max_time(pts):
    return max(p["total"] for p in pts)


def speedup(base, other):
    """Speed-up of @p other over @p base at the target error, as text.

    base: (time, kind, longest time measured) of the baseline, other: (time, kind), kinds as returned by
    time_to_reach. A time of kind "at_or_before" is an upper bound, so the ratio becomes a bound too.
    """
    tb, kb, tb_max = base
    to, ko = other
    if ko == "not_reached":
        return "–"
    if kb == "not_reached":
        return f"> {tb_max / to:.1f}×"
    if kb == "at_or_before" and ko == "at_or_before":
        return "–"
    if ko == "at_or_before":
        return f"≥ {tb / to:.2f}×"
    if kb == "at_or_before":
        return f"≤ {tb / to:.2f}×"
    return f"{tb / to:.2f}×"


def plot_scene(result, curves, path, all_methods):
    """Error against time, one line per method; a method's colour is fixed by its place in all_methods."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker  # noqa: F401 (used through matplotlib.ticker)
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), dpi=100)
    noise = {"rel_rmse": result["ref"]["noise_rel_rmse"], "mare": result["ref"]["noise_mare"]}
    colour = {m: f"C{i % 10}" for i, m in enumerate(all_methods)}
    for ax, key, label in ((axes[0], "rel_rmse", "relative RMSE"), (axes[1], "mare", "mean abs. relative error")):
        for m in all_methods:
            if m in curves:
                pts = sorted(curves[m], key=lambda p: p["total"])
                ax.loglog([p["total"] for p in pts], [p[key] for p in pts], "o-", label=m, markersize=4, color=colour[m])
            elif key == "rel_rmse":
                ax.plot([], [], "o-", color=colour[m], alpha=0.4, label=f"{m} (no result: {why_missing(result, m)})")
        ax.axhline(noise[key], color="grey", linestyle=":", linewidth=1, label="reference noise")
        if key == "rel_rmse":
            ax.axhline(result["target"], color="black", linestyle="--", linewidth=0.8, label="target")
        ax.set_xlabel("wall time incl. preprocessing (s)")
        ax.set_ylabel(label)
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
            axis.set_minor_formatter(matplotlib.ticker.FuncFormatter(minor_label))
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=6)
    fig.suptitle(f"{result['scene']}: error against time", fontsize=10)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


# ----------------------------------------------------------------------------------------------------
# Preprocessing accuracy and time

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


# ----------------------------------------------------------------------------------------------------

def parse_method_args(items):
    out = {}
    for item in items:
        name, sep, rest = item.partition("=")
        if not sep:
            sys.exit(f"firstshot-bench: --method-args wants NAME=ARGS, got {item!r}")
        out[name] = shlex.split(rest)
    return out


def resolve_scene(s):
    if os.path.exists(s):
        return os.path.splitext(os.path.basename(s))[0], os.path.abspath(s)
    p = os.path.join(REPO, "scenes", s + ".json")
    if not os.path.exists(p):
        sys.exit(f"firstshot-bench: no scene {s!r} (neither a file nor scenes/{s}.json)")
    return s, p


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="Example: bench/firstshot_bench.py cornell many-lights --build build/release")
    ap.add_argument("scenes", nargs="*", default=["cornell", "many-lights"], help="scene names (scenes/NAME.json) or files")
    ap.add_argument("--build", default=os.path.join(REPO, "build", "release"), help="CMake build folder with the tools")
    ap.add_argument("--out", default=None, help="output folder (default out/bench, out/bench/quick with --quick)")
    ap.add_argument("--methods", default="path,path+firstshot,irradiance-cache,irradiance-cache+firstshot",
                    help="comma-separated; NAME is an integrator, NAME+firstshot adds a preprocessed first-shot table")
    ap.add_argument("--budgets", default=None, help="render time budgets in seconds (default 0.5,1,2,4,8)")
    ap.add_argument("--reps", type=int, default=None, help="repetitions (different seeds), medians (default 3)")
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1, help="threads of every tool (default: cores)")
    ap.add_argument("--width", type=int, default=None, help="image width (default 160)")
    ap.add_argument("--height", type=int, default=None, help="image height (default 120)")
    ap.add_argument("--ref-spp", type=int, default=None, help="reference spp (default per scene)")
    ap.add_argument("--ref-seed", type=int, default=1000, help="seed of reference half A (B: +1)")
    ap.add_argument("--seed", type=int, default=1, help="seed of repetition 0 (repetition k: +k)")
    ap.add_argument("--target-error", type=float, default=None, help="target rel. RMSE (default per scene)")
    ap.add_argument("--method-args", action="append", default=[], metavar="NAME=ARGS",
                    help="extra renderer arguments of a method or integrator, e.g. 'irradiance-cache=--accuracy 0.2'")
    ap.add_argument("--preprocess-args", default="", help="extra firstshot-preprocess arguments, e.g. '--resolution 128'")
    ap.add_argument("--timeout-factor", type=float, default=4.0,
                    help="a run is killed after F*budget+extra seconds (then not run again at budgets up to that one)")
    ap.add_argument("--timeout-extra", type=float, default=10.0)
    ap.add_argument("--no-accuracy", action="store_true", help="skip the preprocessing accuracy report")
    ap.add_argument("--accuracy-only", action="store_true", help="only the preprocessing accuracy report")
    ap.add_argument("--figures", default=None, help="copy the PNGs into this folder (e.g. docs/figures)")
    ap.add_argument("--replot", action="store_true",
                    help="no runs: tables and plots again from OUT/<scene>/results.csv (e.g. with another --target-error)")
    ap.add_argument("--keep-images", action="store_true", help="keep every run's EXR under OUT/SCENE/runs/")
    ap.add_argument("--quick", action="store_true", help="smoke check: 80x60, budgets 0.25,0.5, 1 repetition, "
                                                          "reference 128 spp, small accuracy sweep (~1-2 min)")
    args = ap.parse_args(argv)
    q = args.quick
    args.out = os.path.abspath(args.out or os.path.join(REPO, "out", "bench", "quick" if q else ""))
    args.budgets = [float(b) for b in (args.budgets or ("0.25,0.5" if q else "0.5,1,2,4,8")).split(",")]
    args.reps = args.reps or (1 if q else 3)
    args.width = args.width or (80 if q else 160)
    args.height = args.height or (60 if q else 120)
    args.ref_spp = args.ref_spp or (128 if q else None)
    args.methods = [m.strip() for m in args.methods.split(",") if m.strip()]
    args.method_args = parse_method_args(args.method_args)
    args.preprocess_args = shlex.split(args.preprocess_args)
    args.accuracy_resolutions = [64, 256] if q else [64, 128, 256, 512, 1024]
    tools = Tools(os.path.abspath(args.build))
    tools.check(not args.no_accuracy)
    os.makedirs(args.out, exist_ok=True)
    t0 = time.perf_counter()
    pngs = []
    if not args.accuracy_only:
        for s in args.scenes:
            name, path = resolve_scene(s)
            result = reload_scene(name, args) if args.replot else bench_scene(tools, name, path, args)
            curves = summarize(result)
            table = write_table(result, curves, os.path.join(args.out, f"table_{name}.md"))
            png = os.path.join(args.out, f"error_vs_time_{name}.png")
            plot_scene(result, curves, png, args.methods)
            pngs.append(png)
            log(table)
        # The combined CSV: every scene that has results in this folder.
        rows = []
        for d in sorted(os.listdir(args.out)):
            p = os.path.join(args.out, d, "results.csv")
            if os.path.isfile(p):
                rows += read_rows(p)
        write_rows(os.path.join(args.out, "results.csv"), rows)
    if not args.no_accuracy and args.replot:
        plot_accuracy(os.path.join(args.out, "preprocess_accuracy.csv"), os.path.join(args.out, "preprocess_time.csv"),
                      os.path.join(args.out, "preprocess_accuracy.png"))
        pngs.append(os.path.join(args.out, "preprocess_accuracy.png"))
    elif not args.no_accuracy:
        accuracy_report(tools, args)
        pngs.append(os.path.join(args.out, "preprocess_accuracy.png"))
    if args.figures:
        os.makedirs(args.figures, exist_ok=True)
        for p in pngs:
            shutil.copy(p, args.figures)
        log(f"copied {len(pngs)} figures to {args.figures}")
    log(f"firstshot-bench: done in {time.perf_counter() - t0:.0f} s; results under {args.out}")


if __name__ == "__main__":
    main()
