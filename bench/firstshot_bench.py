#!/usr/bin/python3
"""firstshot-bench: how fast the error falls for each rendering method (speed against error).

Measures where users look: the time each method needs to reach 5% and 2% relative RMSE (and MARE) against a
converged path-traced reference, first-shot preprocessing included, against the baseline a user would pick.
Drives the command-line tools exactly as a user runs them (firstshot-preprocess, firstshot-render) and compares
every image with the reference (firstshot-compare). For each scene:

1. methods: a name from METHODS (integrator, renderer arguments, first-shot or not, baseline or not), or any
   other name (NAME is an integrator, NAME+firstshot adds a first-shot table). The baseline is path tracing
   without first-shot: `path` (next-event estimation to every light, --light-sampler all) and `path-tree` (a
   light tree picks one light per vertex, --light-sampler tree); speed comparisons use the better of the two
   ("best baseline": the smaller time to the target). The first-shot methods are compared through the best of
   them ("best first-shot"). Every method is probed first with a 1-spp render at 8x6 px; a method the tools
   reject is skipped with a note (e.g. a flag the renderer does not have yet).
2. reference: rendered progressively and cached in OUT/<scene>/reference.exr, its record in reference.json.
   Two halves A and B (different seeds) of `start` spp together; each round then renders as many spp again
   into each half with new seeds, and a half becomes the plain mean of its old and new images (equal spp, so
   the plain mean is the spp-weighted mean); the reference is mean(A, B). Its noise is rel. RMSE(A, mean(A, B)):
   A - mean = (A - B)/2 has the distribution of the mean's error. The rounds stop when that noise is at most
   the smallest target / 3 (--ref-noise-fraction) or when the next round (as long as all before it) would take
   the reference past --ref-max-minutes. The method is --ref-method (default per scene, `path`), never
   first-shot: first-shot's own small bias must show against it. reference.json records every round (spp,
   seconds, noise), the commands and the cache key (scene file sha256, renderer binary size and mtime, method
   and its arguments, size, seeds, start spp); a matching cached reference is used as it is when converged
   and otherwise continued from its halves (e.g. after a larger --ref-max-minutes).
3. runs: every method at every time budget (firstshot-render --time B), repetitions with different seeds,
   methods interleaved (the order rotates from run to run). A first-shot method runs firstshot-preprocess once
   per repetition; its time is preprocessing wall time + render wall time, both recorded. A run is killed after
   4*budget+10 s (a method that ignores the budget, e.g. an irradiance cache filling its records first); it is
   then not run again at budgets up to that one.
4. outputs: OUT/<scene>/results.csv (one row per run, exact command lines, load average), the combined
   OUT/results.csv, OUT/error_vs_time_<scene>.png, OUT/table_<scene>.md (median curves; per method the time to
   every target in rel. RMSE and MARE, the best baseline, the best first-shot method and their ratio) and
   OUT/summary.md (one row per scene: best baseline and best first-shot time to each target, the ratio, the goal).

Errors (bench/image_metrics.h, computed by firstshot-compare over all pixels and RGB channels, x: image,
r: reference, eps = 0.01 * mean(r)):
  rel. RMSE = sqrt(mean(((x - r)/(r + eps))^2)),  MARE = mean(|x - r|/(r + eps)),  NRMSE = RMSE/mean(r).
The reference's noise adds to the measured error (about in quadrature: at noise = target/3 a true error equal to
the target is measured 5% high); the curves flatten at it.

The time to reach a target interpolates the median curve (median total time, median error) linearly in log-log
between the two budgets around the first crossing; "not reached" comes with the smallest error reached. A method
already below the target at its first budget gives an upper bound (≤), a baseline that never reaches it a lower
bound on the ratio (>): the time it would need is more than its longest run.

Goals (GOALS): best first-shot at least 10x faster than the best baseline to the smallest target on many-lights,
fixture-room and office-floor; never slower than the best baseline on cornell (ratio >= 1 at every target).

Cost of the defaults: budgets 1..128 s sum to 255 s per method and repetition, so 6 methods x 3 repetitions take
about 80 min per scene, plus each reference once (at most --ref-max-minutes). --max-budget, --reps and --methods
cut it down; --quick is a 2-minute smoke check of the plumbing (its numbers mean nothing).

Also (unless --no-accuracy): the preprocessing accuracy report, r_ij error against the analytic value
vs R and patch width in pixels (firstshot-preprocess-accuracy), and cornell's preprocessing time vs R.

Standard library only, plus matplotlib (Debian's python3-matplotlib) for the plots.
"""
import argparse
import collections
import csv
import hashlib
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

# A named method: the integrator, its extra renderer arguments, whether it renders with a first-shot table
# (then firstshot-preprocess runs first and its time counts), and whether it is one of the baselines a user
# would pick (path tracing without first-shot; the speed comparisons use the best of them).
Method = collections.namedtuple("Method", "integrator args firstshot baseline about")

# The irradiance cache's defaults (512 samples, 3 bounces) fill ~2*10^5 records on cornell at 160x120, a minute
# on 2 cores; the bench uses a cheaper cache. No --ambient: past the last cached bounce the integrator continues
# the path (an --ambient 0 would truncate the light). The CSV shows exactly what ran.
IC_ARGS = ["--ic-samples", "128", "--bounces", "2"]

METHODS = {
    "path": Method("path", ["--light-sampler", "all"], False, True,
                   "path tracing, next-event estimation to every light"),
    "path-tree": Method("path", ["--light-sampler", "tree"], False, True,
                        "path tracing, a light tree picks one light per vertex"),
    "path+firstshot": Method("path", ["--light-sampler", "all", "--patch-nee", "off"], True, False,
                             "path tracing with first-shot; shadow rays to every small light at camera-visible "
                             "surfaces, lit patches met by BSDF sampling"),
    "path+firstshot-tree": Method("path", ["--light-sampler", "tree", "--patch-nee", "off"], True, False,
                                  "path tracing with first-shot (the renderer's defaults); a light tree picks the "
                                  "small light at camera-visible surfaces"),
    "path+firstshot-patchnee": Method("path", ["--light-sampler", "all", "--patch-nee", "every"], True, False,
                                      "path tracing with first-shot; lit patches sampled as lights at every vertex"),
    "irradiance-cache": Method("irradiance-cache", ["--light-sampler", "tree"] + IC_ARGS, False, False,
                               "irradiance cache, no first-shot (not a baseline: shown for comparison)"),
    "irradiance-cache+firstshot": Method("irradiance-cache", ["--light-sampler", "all"] + IC_ARGS, True, False,
                                         "irradiance cache with first-shot"),
}
DEFAULT_METHODS = list(METHODS)

# Arguments of an integrator used by a method name that is not in METHODS (NAME or NAME+firstshot).
DEFAULT_METHOD_ARGS = {
    "irradiance-cache": IC_ARGS,
}

FIRSTSHOT_SUFFIX = "+firstshot"

# Per scene: the reference's starting spp (it doubles from there until converged) and its method.
# office-floor: NEE to every one of its >= 200 lights costs hundreds of shadow rays per vertex; the light tree
# is unbiased too.
SCENE_DEFAULTS = {
    "cornell": {"ref_spp": 1024, "ref_method": "path"},
    "many-lights": {"ref_spp": 256, "ref_method": "path"},
    "sierpinski-glossy": {"ref_spp": 512, "ref_method": "path"},
    "fixture-room": {"ref_spp": 256, "ref_method": "path"},
    "office-floor": {"ref_spp": 128, "ref_method": "path-tree"},
    "ward-sphere": {"ref_spp": 512, "ref_method": "path"},
}
FALLBACK_DEFAULTS = {"ref_spp": 256, "ref_method": "path"}

# The requirement: the ratio best baseline time / best first-shot time must be at least min_ratio, at the
# smallest target ("smallest") or at every target ("every"), rel. RMSE.
GOALS = {
    "cornell": {"min_ratio": 1.0, "at": "every"},
    "many-lights": {"min_ratio": 10.0, "at": "smallest"},
    "fixture-room": {"min_ratio": 10.0, "at": "smallest"},
    "office-floor": {"min_ratio": 10.0, "at": "smallest"},
}

METRICS = (("rel_rmse", "rel. RMSE"), ("mare", "MARE"))

CSV_FIELDS = [
    "scene", "method", "role", "budget_s", "rep", "seed", "status", "spp", "render_wall_s", "render_reported_s",
    "preprocess_wall_s", "preprocess_reported_s", "total_s", "rel_rmse", "mare", "nrmse", "ref_spp",
    "ref_noise_rel_rmse", "threads", "width", "height", "load_avg_1m", "render_cmd", "preprocess_cmd", "note",
]

CSV_HEADER = """# firstshot-bench results: one row per run. role: baseline | firstshot | other.
# total_s = preprocess_wall_s + render_wall_s (wall times of the whole processes; *_reported_s: the tools' own timers).
# rel_rmse = sqrt(mean(((x-r)/(r+eps))^2)), mare = mean(|x-r|/(r+eps)), nrmse = RMSE/mean(r); over all pixels and RGB
# channels, x: image, r: reference (ref_spp, see reference.json), eps = 0.01*mean(r). ref_noise_rel_rmse: the
# reference's own estimated error. load_avg_1m: the machine's 1-minute load average when the run started.
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


def target_info(curve, target, key="rel_rmse"):
    """Time to @p target on a median curve (points with 'total' and @p key), with what a bound needs.

    Returns {"time", "kind"} as time_to_reach, "t_max": the longest time measured, "best_error": the smallest
    error reached and "best_error_time": when. None when the curve has no point.
    """
    pts = [(p["total"], p[key]) for p in curve if math.isfinite(p["total"]) and math.isfinite(p[key])]
    if not pts:
        return None
    t, kind = time_to_reach([p[0] for p in pts], [p[1] for p in pts], target)
    best = min(pts, key=lambda p: p[1])
    return {"time": t, "kind": kind, "t_max": max(p[0] for p in pts), "best_error": best[1], "best_error_time": best[0]}


def best_of(infos):
    """The method that reaches the target first, among @p infos ({method: target_info or None}).

    Returns {"method", "time", "kind", "t_max"}: the smallest time among the methods that reach the target;
    kind "at_or_before" (an upper bound) when any method's time is one (it was below the target at its first
    budget, so its true time may be smaller), or when a method that did not reach the target stopped earlier
    than the best time (it might have reached it sooner with longer runs). When none reaches it: method
    None, kind "not_reached" and t_max the smallest longest-run time, a lower bound of the best time (every
    method would need more than its longest run). None when there is no method with a result.
    """
    infos = {m: i for m, i in infos.items() if i is not None}
    if not infos:
        return None
    reached = {m: i for m, i in infos.items() if i["kind"] != "not_reached"}
    if not reached:
        return {"method": None, "time": float("nan"), "kind": "not_reached",
                "t_max": min(i["t_max"] for i in infos.values())}
    m = min(reached, key=lambda k: reached[k]["time"])
    best = reached[m]
    kind = best["kind"]
    if any(i["kind"] == "at_or_before" for i in reached.values()) or \
            any(i["kind"] == "not_reached" and i["t_max"] < best["time"] for i in infos.values()):
        kind = "at_or_before"
    return {"method": m, "time": best["time"], "kind": kind, "t_max": best["t_max"]}


def ratio(base, other):
    """base time / other time at a target, as (value, relation) with relation "=", "≥", "≤", ">", "<" or None.

    base: (time, kind, longest time measured), other: (time, kind) or (time, kind, longest time measured), kinds
    as returned by time_to_reach ("at_or_before" times are upper bounds; a "not_reached" time is more than the
    longest time measured). (NaN, None) when nothing can be said.
    """
    tb, kb, tb_max = base
    to, ko = other[0], other[1]
    to_max = other[2] if len(other) > 2 else float("nan")
    if ko == "not_reached":
        if kb == "interpolated" and to_max > 0:
            return tb / to_max, "<"
        return float("nan"), None
    if kb == "not_reached":
        return tb_max / to, ">"
    if kb == "at_or_before" and ko == "at_or_before":
        return float("nan"), None
    if ko == "at_or_before":
        return tb / to, "≥"
    if kb == "at_or_before":
        return tb / to, "≤"
    return tb / to, "="


def format_ratio(value, relation):
    if relation is None or not math.isfinite(value):
        return "–"
    if relation in (">", "<"):
        return f"{relation} {value:.1f}×"
    return f"{value:.2f}×" if relation == "=" else f"{relation} {value:.2f}×"


def speedup(base, other):
    """Speed-up of @p other over @p base at the target error, as text (see ratio)."""
    return format_ratio(*ratio(base, other))


def best_ratio(best_base, best_fs):
    """ratio() of two best_of() results (either may be None)."""
    if best_base is None or best_fs is None:
        return float("nan"), None
    return ratio((best_base["time"], best_base["kind"], best_base["t_max"]),
                 (best_fs["time"], best_fs["kind"], best_fs["t_max"]))


def goal_check(value, relation, need):
    """'met', 'not met' or 'open' (bounds on both sides of @p need, or no result) for ratio >= need."""
    if relation is None or not math.isfinite(value):
        return "open"
    if relation == "=":
        return "met" if value >= need else "not met"
    if relation in (">", "≥"):
        return "met" if value >= need else "open"
    return "not met" if value < need else "open"  # "<", "≤": an upper bound


def goal_status(scene, ratios, goals=None):
    """The scene's goal (GOALS) against @p ratios ({target: (value, relation)}, rel. RMSE): (text, verdict).

    verdict: 'met' when met at every target the goal concerns, 'not met' when missed at one, else 'open';
    None (and text '–') for a scene without a goal.
    """
    goal = (GOALS if goals is None else goals).get(scene)
    if goal is None or not ratios:
        return "–", None
    at = sorted(ratios) if goal["at"] == "every" else [min(ratios)]
    checks = [goal_check(*ratios[t], goal["min_ratio"]) for t in at]
    verdict = "not met" if "not met" in checks else "met" if all(c == "met" for c in checks) else "open"
    where = "every target" if goal["at"] == "every" else fmt_target(min(ratios))
    return f"≥ {goal['min_ratio']:g}× at {where}: {verdict}", verdict


# The progressive reference

def reference_goal(targets, fraction):
    """The reference's noise goal (rel. RMSE): @p fraction of the smallest target."""
    return fraction * min(targets)


def next_reference_round(spp_per_half, noise, goal, seconds, max_seconds):
    """What the progressive reference does next, given its state after a round.

    spp_per_half: spp in each half now (0: nothing rendered yet), noise: its measured rel. RMSE, goal: the
    noise wanted, seconds: render time so far, max_seconds: the limit. Each round doubles the spp (each half
    gets as many new spp as it has, so the halves stay plain means of equal-spp images) and so takes about as
    long as all rounds before it. Returns (action, spp to add to each half): ("render", n) or ("converged", 0)
    or ("time_limit", 0) when the doubling would end past max_seconds.
    """
    if spp_per_half <= 0:
        raise ValueError("the first round's spp comes from the start spp")
    if noise is not None and math.isfinite(noise) and noise <= goal:
        return "converged", 0
    if 2 * seconds > max_seconds:
        return "time_limit", 0
    return "render", spp_per_half


def predicted_spp(total_spp, noise, goal):
    """spp at which the noise reaches @p goal if it falls as 1/sqrt(spp)."""
    return total_spp * (noise / goal) ** 2 if goal > 0 else float("inf")


def reference_seeds(base_seed, round_index):
    """Seeds of halves A and B in round @p round_index (0, 1, ...): all different."""
    return base_seed + 2 * round_index, base_seed + 2 * round_index + 1


# Methods and parsing

def split_method(name):
    """'path+firstshot' -> ('path', True); 'irradiance-cache' -> ('irradiance-cache', False)."""
    if name.endswith(FIRSTSHOT_SUFFIX):
        return name[: -len(FIRSTSHOT_SUFFIX)], True
    return name, False


def method_spec(name, overrides=None, appended=None, baselines=None):
    """The Method that @p name runs.

    A name in METHODS has its registered integrator and arguments; another name is an integrator (NAME) or an
    integrator with a first-shot table (NAME+firstshot) with DEFAULT_METHOD_ARGS of that integrator.
    overrides ({name: args}, from --method-args NAME=ARGS) replace the arguments of method NAME (for a name not
    in METHODS, also an integrator's); appended ({name: args}, from NAME+=ARGS) are added after them.
    baselines: the names that count as baselines (default: METHODS' own flags).
    """
    overrides, appended = overrides or {}, appended or {}
    if name in METHODS:
        reg = METHODS[name]
        integrator, firstshot, args, about = reg.integrator, reg.firstshot, reg.args, reg.about
    else:
        integrator, firstshot = split_method(name)
        args = overrides.get(integrator, DEFAULT_METHOD_ARGS.get(integrator, []))
        about = f"integrator {integrator}" + (" with first-shot" if firstshot else "")
    if name in overrides:
        args = overrides[name]
    args = list(args) + list(appended.get(name, []))
    if baselines is None:
        baseline = name in METHODS and METHODS[name].baseline
    else:
        baseline = name in baselines
    return Method(integrator, args, firstshot, baseline and not firstshot, about)


def method_role(spec):
    return "firstshot" if spec.firstshot else "baseline" if spec.baseline else "other"


def parse_method_args(items):
    """--method-args items: NAME=ARGS replaces, NAME+=ARGS appends. Returns (overrides, appended)."""
    overrides, appended = {}, {}
    for item in items:
        name, sep, rest = item.partition("=")
        if not sep or not name:
            sys.exit(f"firstshot-bench: --method-args wants NAME=ARGS or NAME+=ARGS, got {item!r}")
        if name.endswith("+"):
            appended.setdefault(name[:-1], []).extend(shlex.split(rest))
        else:
            overrides[name] = shlex.split(rest)
    return overrides, appended


def parse_list(text, kind=float):
    return [kind(x) for x in text.split(",") if x.strip()]


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


def reference_key(scene_path, renderer, method, spec, start_spp_per_half, seed, width, height):
    """The settings a cached reference must match (anything else: render it again from the start)."""
    return {
        "scene_sha256": sha256_file(scene_path),
        "renderer": binary_identity(renderer),
        "method": method,
        "integrator": spec.integrator,
        "args": list(spec.args),
        "start_spp_per_half": start_spp_per_half,
        "seed": seed,
        "width": width,
        "height": height,
        "max_depth": "scene settings",
    }


def fmt_num(x, digits=3):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "–"
    return f"{x:.{digits}g}"


def fmt_target(t):
    """0.05 -> '5%'."""
    return f"{100 * t:g}%"


def fmt_seconds(t):
    return f"{t:.3g} s" if t < 100 else f"{t:.0f} s"


def describe_ttt(info):
    """A target_info as table text."""
    if info is None:
        return "no result"
    if info["kind"] == "not_reached":
        return f"not reached (best {info['best_error']:.3g} at {fmt_seconds(info['best_error_time'])})"
    if info["kind"] == "at_or_before":
        return f"≤ {fmt_seconds(info['time'])}"
    return fmt_seconds(info["time"])


def describe_best(best):
    """A best_of result as table text."""
    if best is None:
        return "no result"
    if best["kind"] == "not_reached":
        return f"not reached (> {fmt_seconds(best['t_max'])})"
    prefix = "≤ " if best["kind"] == "at_or_before" else ""
    return f"{prefix}{fmt_seconds(best['time'])} ({best['method']})"


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


def spec_of(name, args):
    return method_spec(name, args.method_overrides, args.method_appended, args.baselines)


def scene_default(scene_name, key):
    return SCENE_DEFAULTS.get(scene_name, FALLBACK_DEFAULTS).get(key, FALLBACK_DEFAULTS[key])


# ----------------------------------------------------------------------------------------------------
# Reference

def load_reference(sdir, key):
    """The cached reference record if its key matches and its files exist, else None."""
    ref_json = os.path.join(sdir, "reference.json")
    if not os.path.exists(ref_json):
        return None
    try:
        with open(ref_json) as f:
            cached = json.load(f)
    except (OSError, ValueError):
        return None
    if cached.get("key") != key or "files" not in cached:
        return None
    if not all(os.path.exists(os.path.join(sdir, p)) for p in cached["files"].values()):
        return None
    return cached


def ensure_reference(tools, scene_name, scene_path, sdir, args):
    """The converged (or time-limited) reference of the scene, rendered or continued as needed (see the docstring)."""
    method = args.ref_method or scene_default(scene_name, "ref_method")
    spec = spec_of(method, args)
    if spec.firstshot:
        sys.exit(f"firstshot-bench: the reference method {method!r} uses first-shot; its bias would not show")
    start = args.ref_spp or scene_default(scene_name, "ref_spp")
    start_half = max(1, start // 2)
    goal = reference_goal(args.targets, args.ref_noise_fraction)
    max_seconds = 60.0 * args.ref_max_minutes
    key = reference_key(scene_path, tools.render, method, spec, start_half, args.ref_seed, args.width, args.height)
    ref_exr = os.path.join(sdir, "reference.exr")
    rdir = os.path.join(sdir, "reference")
    os.makedirs(rdir, exist_ok=True)
    info = load_reference(sdir, key)
    if info is None:
        if os.path.exists(os.path.join(sdir, "reference.json")):
            log("  reference: settings changed (or files missing), rendering again")
        info = {"key": key, "spp": 0, "spp_per_half": 0, "seconds": 0.0, "rounds": [], "commands": [],
                "noise_rel_rmse": float("nan"), "noise_mare": float("nan"), "noise_nrmse": float("nan")}
    else:
        log(f"  reference: cached, {info['spp']} spp in {info['seconds']:.0f} s, noise rel. RMSE "
            f"{info['noise_rel_rmse']:.4f} (goal {goal:.4f})")
    while True:
        if info["spp_per_half"] == 0:
            action, add = "render", start_half
        else:
            action, add = next_reference_round(info["spp_per_half"], info["noise_rel_rmse"], goal, info["seconds"],
                                               max_seconds)
        if action != "render":
            break
        r = len(info["rounds"])
        new = {}
        for half, seed in zip("ab", reference_seeds(args.ref_seed, r)):
            out = os.path.join(rdir, f"round{r}_{half}.exr")
            cmd = [tools.render, scene_path, "--integrator", spec.integrator] + spec.args + [
                "--spp", str(add), "--seed", str(seed), "--threads", str(args.threads),
                "--width", str(args.width), "--height", str(args.height), "-o", out, "--quiet"]
            rc, wall, text = run(cmd)
            if rc != 0:
                sys.exit(f"firstshot-bench: the reference render failed:\n{shlex.join(cmd)}\n{text}")
            new[half] = out
            info["seconds"] += wall
            info["commands"].append(shlex.join(cmd))
        total_half = info["spp_per_half"] + add
        files = {"a": f"reference/a_{total_half}.exr", "b": f"reference/b_{total_half}.exr",
                 "mean": f"reference/mean_{total_half}.exr"}
        old = info.get("files")
        for half in "ab":
            dst = os.path.join(sdir, files[half])
            if old is None:
                os.replace(new[half], dst)
            else:  # equal spp: the plain mean is the spp-weighted mean
                mean_images(tools, os.path.join(sdir, old[half]), new[half], dst)
                os.remove(new[half])
        mean_images(tools, os.path.join(sdir, files["a"]), os.path.join(sdir, files["b"]), os.path.join(sdir, files["mean"]))
        noise = compare(tools, os.path.join(sdir, files["a"]), os.path.join(sdir, files["mean"]))
        info.update(spp=2 * total_half, spp_per_half=total_half, files=files, noise_rel_rmse=noise["rel_rmse"],
                    noise_mare=noise["mare"], noise_nrmse=noise["nrmse"])
        info["rounds"].append({"spp": 2 * total_half, "seconds": round(info["seconds"], 2),
                               "noise_rel_rmse": noise["rel_rmse"], "noise_mare": noise["mare"]})
        write_reference_json(sdir, info, goal, max_seconds, args, "rendering")
        if old is not None:
            for p in old.values():
                if p not in files.values() and os.path.exists(os.path.join(sdir, p)):
                    os.remove(os.path.join(sdir, p))
        log(f"  reference round {r}: {2 * total_half} spp, {info['seconds']:.0f} s, noise rel. RMSE "
            f"{noise['rel_rmse']:.4f} (goal {goal:.4f}; at 1/sqrt(spp): "
            f"{predicted_spp(2 * total_half, noise['rel_rmse'], goal):.0f} spp)")
    shutil.copyfile(os.path.join(sdir, info["files"]["mean"]), ref_exr)
    info = write_reference_json(sdir, info, goal, max_seconds, args, action)
    if action == "time_limit":
        log(f"  reference: stopped by --ref-max-minutes {args.ref_max_minutes:g} at {info['spp']} spp, noise rel. RMSE "
            f"{info['noise_rel_rmse']:.4f} > goal {goal:.4f}")
    else:
        log(f"  reference: {info['spp']} spp, {info['seconds']:.0f} s, noise rel. RMSE {info['noise_rel_rmse']:.4f} "
            f"≤ goal {goal:.4f}")
    return info


def write_reference_json(sdir, info, goal, max_seconds, args, status):
    info.update(status=status, noise_goal_rel_rmse=goal, goal_rule=f"{args.ref_noise_fraction:g} x smallest target",
                max_seconds=max_seconds, threads=args.threads, seconds=round(info["seconds"], 2),
                note="noise_*: error of half A against mean(A, B), an estimate of the reference's own error; "
                     "seconds: render wall time of all rounds; status: rendering | converged | time_limit")
    tmp = os.path.join(sdir, "reference.json.tmp")
    with open(tmp, "w") as f:
        json.dump(info, f, indent=2)
    os.replace(tmp, os.path.join(sdir, "reference.json"))
    return info


# ----------------------------------------------------------------------------------------------------
# Methods

def render_cmd(tools, scene_path, spec, fsd, budget, seed, out, args):
    cmd = [tools.render, scene_path, "--integrator", spec.integrator]
    if fsd:
        cmd += ["--firstshot", fsd]
    cmd += spec.args
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
        spec = spec_of(m, args)
        if spec.firstshot and have_fsd is None:
            rc, _, text = run(preprocess_cmd(tools, scene_path, fsd, args))
            have_fsd = rc == 0
            if not have_fsd:
                notes.append(f"firstshot-preprocess failed on this scene: {last_line(text, rc)}")
        if spec.firstshot and not have_fsd:
            notes.append(f"{m}: skipped (no first-shot table)")
            continue
        cmd = [tools.render, scene_path, "--integrator", spec.integrator] + (["--firstshot", fsd] if spec.firstshot else [])
        cmd += spec.args + ["--spp", "1", "--width", "8", "--height", "6", "--threads", "1", "--quiet",
                            "-o", os.path.join(sdir, "probe.exr")]
        rc, _, text = run(cmd, timeout=300)
        if rc == 0:
            usable.append(m)
        else:
            reason = last_line(text, rc) if rc is not None else "timed out"
            notes.append(f"{m}: skipped, the renderer rejected it ({reason}; {shlex.join(cmd[1:])})")
            log(f"  {m}: skipped ({reason})")
    return usable, notes


def check_reference_method(tools, scene_name, scene_path, sdir, args, probed, probe_notes):
    """Exits with a clear message when the renderer rejects the reference method (before any long run).

    probed, probe_notes: probe_methods() of the bench's methods (the reference method is probed again only
    when it is not among them)."""
    method = args.ref_method or scene_default(scene_name, "ref_method")
    if spec_of(method, args).firstshot:
        sys.exit(f"firstshot-bench: the reference method {method!r} uses first-shot; its bias would not show")
    if method in args.methods:
        usable, notes = [m for m in probed if m == method], [n for n in probe_notes if n.startswith(method + ":")]
    else:
        usable, notes = probe_methods(tools, scene_path, sdir, [method], args)
    if not usable:
        sys.exit(f"firstshot-bench: the reference method of {scene_name} is unusable: {(notes or ['?'])[-1]}\n"
                 f"choose another with --ref-method, or change its arguments with --method-args {method}=ARGS")


def bench_scene(tools, scene_name, scene_path, args):
    sdir = os.path.join(args.out, scene_name)
    rdir = os.path.join(sdir, "runs")
    os.makedirs(rdir, exist_ok=True)
    log(f"== {scene_name} ({scene_path}), {args.width}x{args.height}, {args.threads} threads")
    methods, notes = probe_methods(tools, scene_path, sdir, args.methods, args)
    check_reference_method(tools, scene_name, scene_path, sdir, args, methods, notes)
    ref = ensure_reference(tools, scene_name, scene_path, sdir, args)
    ref_exr = os.path.join(sdir, "reference.exr")
    specs = {m: spec_of(m, args) for m in methods}
    rows = []
    dropped = set()
    timed_out = {}  # method -> largest budget at which a run was killed
    run_index = 0
    for rep in range(args.reps):
        seed = args.seed + rep
        # Preprocess once per repetition for every first-shot method (same table for all its budgets).
        pre = {}
        for m in methods:
            if specs[m].firstshot and m not in dropped:
                fsd = os.path.join(rdir, f"rep{rep}.fsd")
                cmd = preprocess_cmd(tools, scene_path, fsd, args)
                rc, wall, text = run(cmd)
                if rc != 0:
                    notes.append(f"{m}: preprocessing failed in repetition {rep}: {text.strip()}")
                    dropped.add(m)
                    continue
                pre[m] = (fsd, wall, parse_preprocess_summary(text), shlex.join(cmd))
        for budget in args.budgets:
            for m in rotated(methods, run_index):
                if m in dropped:
                    continue
                base_row = {"scene": scene_name, "method": m, "role": method_role(specs[m]), "budget_s": budget,
                            "rep": rep, "seed": seed}
                if budget <= timed_out.get(m, -1.0):
                    rows.append(dict(base_row, status="skipped", note=f"timed out at budget {timed_out[m]:g} s before"))
                    continue
                fsd, pwall, preported, pcmd = pre.get(m, (None, 0.0, None, ""))
                out = os.path.join(rdir, f"{m}_{budget:g}_{rep}.exr")
                cmd = render_cmd(tools, scene_path, specs[m], fsd, budget, seed, out, args)
                load = os.getloadavg()[0]
                rc, wall, text = run(cmd, timeout=args.timeout_factor * budget + args.timeout_extra)
                row = dict(base_row, render_wall_s=round(wall, 4), preprocess_wall_s=round(pwall, 4),
                           preprocess_reported_s=preported, total_s=round(wall + pwall, 4), ref_spp=ref["spp"],
                           ref_noise_rel_rmse=ref["noise_rel_rmse"], threads=args.threads, width=args.width,
                           height=args.height, load_avg_1m=round(load, 2), render_cmd=shlex.join(cmd),
                           preprocess_cmd=pcmd, note="")
                if rc is None:
                    row["status"] = "timeout"
                    row["note"] = f"killed after {wall:.0f} s"
                    timed_out[m] = max(budget, timed_out.get(m, -1.0))
                    notes.append(f"{m}: killed after {wall:.0f} s at budget {budget:g} s (repetition {rep}); "
                                 f"not run again at budgets up to {budget:g} s")
                elif rc != 0:
                    row["status"] = f"exit {rc}"
                    row["note"] = last_line(text, rc)
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
                log(f"  rep {rep} budget {budget:g} s {m:>26}: total {row['total_s']:.2f} s, "
                    f"rel. RMSE {fmt_num(row.get('rel_rmse'))}, spp {row.get('spp')} [{row['status']}]")
            run_index += 1  # next budget starts with another method
    write_rows(os.path.join(sdir, "results.csv"), rows)
    return {"scene": scene_name, "rows": rows, "methods": methods, "roles": {m: method_role(specs[m]) for m in methods},
            "about": {m: specs[m].about for m in methods}, "notes": notes, "ref": ref, "targets": args.targets}


def reload_scene(scene_name, args):
    """The result of an earlier run, from OUT/<scene>/results.csv and reference.json (for --replot)."""
    sdir = os.path.join(args.out, scene_name)
    rows = read_rows(os.path.join(sdir, "results.csv"))
    with open(os.path.join(sdir, "reference.json")) as f:
        ref = json.load(f)
    seen = list(dict.fromkeys(r["method"] for r in rows))
    methods = [m for m in args.methods if m in seen] + [m for m in seen if m not in args.methods]
    roles = {}
    for r in rows:  # the roles recorded when it ran (--baselines may differ now)
        roles.setdefault(r["method"], r.get("role") or method_role(spec_of(r["method"], args)))
    notes = [f"{r['method']}: {r['status']} at budget {r['budget_s']} s, repetition {r['rep']} ({r['note']})"
             for r in rows if r["status"] not in ("ok", "skipped")]
    return {"scene": scene_name, "rows": rows, "methods": methods, "roles": roles,
            "about": {m: spec_of(m, args).about for m in methods}, "notes": notes, "ref": ref, "targets": args.targets}


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


def scene_targets(curves, roles, targets):
    """Everything the tables need, per metric and target.

    Returns {(key, target): {"methods": {method: target_info}, "baseline": best_of(baselines),
    "firstshot": best_of(first-shot methods), "ratio": (value, relation)}} for key in rel_rmse and mare.
    """
    out = {}
    for key, _ in METRICS:
        for t in targets:
            infos = {m: target_info(c, t, key) for m, c in curves.items()}
            bb = best_of({m: i for m, i in infos.items() if roles.get(m) == "baseline"})
            bf = best_of({m: i for m, i in infos.items() if roles.get(m) == "firstshot"})
            out[(key, t)] = {"methods": infos, "baseline": bb, "firstshot": bf, "ratio": best_ratio(bb, bf)}
    return out


def reference_spp(ref):
    return ref.get("spp", ref["key"].get("spp"))  # (records of the earlier harness: spp in the key)


def reference_text(ref):
    key = ref["key"]
    status = {"converged": "converged", "time_limit": "stopped by the time limit, NOT converged"}.get(
        ref.get("status"), ref.get("status") or "fixed spp")
    seconds = ref.get("seconds", 0.0)
    seconds = sum(seconds) if isinstance(seconds, list) else seconds
    command = shlex.join([key.get("integrator", "?")] + key.get("args", []))
    return (f"Reference: {key.get('method', key.get('integrator'))} ({command}), {reference_spp(ref)} spp in "
            f"{seconds:.0f} s, its own noise rel. RMSE {ref['noise_rel_rmse']:.4f} / MARE {ref['noise_mare']:.4f} "
            f"(goal ≤ {ref.get('noise_goal_rel_rmse', float('nan')):.4f}; {status})")


def write_table(result, curves, path):
    targets = result["targets"]
    cols = sorted(targets, reverse=True)  # 5% before 2%: time grows left to right
    roles = result["roles"]
    ref = result["ref"]
    noise = ref["noise_rel_rmse"]
    key = ref["key"]
    ok = [r for r in result["rows"] if r["status"] == "ok"]
    threads = ok[0]["threads"] if ok else "?"
    reps = len({str(r["rep"]) for r in result["rows"]})
    loads = [float(r["load_avg_1m"]) for r in result["rows"] if r.get("load_avg_1m") not in (None, "")]
    st = scene_targets(curves, roles, targets)
    lines = [f"### {result['scene']}: error against time",
             "",
             f"{key['width']}×{key['height']} px, {threads} threads, medians of {reps} repetitions "
             f"(different seeds), methods interleaved. {reference_text(ref)}. Time = whole-process wall time; "
             f"first-shot methods include the preprocessing (its median shown separately). Median load average "
             f"during the runs: {median(loads):.1f}.",
             "",
             "| method | role | budget (s) | total time (s) | of which preprocess (s) | spp | rel. RMSE | MARE |",
             "|---|---|---|---|---|---|---|---|"]
    for m, pts in curves.items():
        for p in pts:
            lines.append(f"| {m} | {roles.get(m, '?')} | {p['budget']:g} | {p['total']:.2f} | {p['preprocess']:.2f} "
                         f"| {fmt_num(p['spp'], 4)} | {p['rel_rmse']:.4f} | {p['mare']:.4f} |")
    head = [f"{label} {fmt_target(t)}" for key_, label in METRICS for t in cols]
    lines += ["", "Time to reach each target (log-log interpolation of the median curve; ≤: already below it at the "
                  "first budget; not reached: the smallest error reached), the log-log slope of rel. RMSE against "
                  "time, and the best baseline, the best first-shot method and the ratio of their times:", "",
              "| method | role | " + " | ".join(head) + " | slope |",
              "|---|---|" + "---|" * len(head) + "---|"]
    for m, pts in curves.items():
        cells = [describe_ttt(st[(k, t)]["methods"][m]) for k, _ in METRICS for t in cols]
        slope = loglog_slope([p["total"] for p in pts], [p["rel_rmse"] for p in pts])
        lines.append(f"| {m} | {roles.get(m, '?')} | " + " | ".join(cells) + f" | {fmt_num(slope, 2)} |")
    lines.append("| **best baseline** | | " + " | ".join(describe_best(st[(k, t)]["baseline"]) for k, _ in METRICS for t in cols) + " | |")
    lines.append("| **best first-shot** | | " + " | ".join(describe_best(st[(k, t)]["firstshot"]) for k, _ in METRICS for t in cols) + " | |")
    lines.append("| **ratio baseline / first-shot** | | " + " | ".join(format_ratio(*st[(k, t)]["ratio"]) for k, _ in METRICS for t in cols) + " | |")
    goal_text, _ = goal_status(result["scene"], {t: st[("rel_rmse", t)]["ratio"] for t in targets})
    if goal_text != "–":
        lines += ["", f"Goal (rel. RMSE): {goal_text}."]
    lines += ["", "Methods: " + "; ".join(f"{m}: {result['about'].get(m, '')}" for m in result["methods"]) + "."]
    if min(targets) < 3 * noise:
        lines += ["", f"Warning: the reference's noise ({noise:.4f}) is more than a third of the smallest target "
                      f"({min(targets):g}); the time to it is overestimated."]
    for n in result["notes"]:
        lines.append(f"\nNote: {n}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return "\n".join(lines)


def summary_rows(scene_results, targets, key="rel_rmse"):
    """One row per scene: [(scene, {target: scene_targets entry}, goal text, reference)], for summary tables."""
    out = []
    for result, curves in scene_results:
        st = scene_targets(curves, result["roles"], targets)
        per = {t: st[(key, t)] for t in targets}
        goal_text, _ = goal_status(result["scene"], {t: per[t]["ratio"] for t in targets}) if key == "rel_rmse" else ("", None)
        out.append((result["scene"], per, goal_text, result["ref"]))
    return out


def write_summary(scene_results, targets, path, args):
    """OUT/summary.md: one row per scene, best baseline / best first-shot time to each target and the ratio."""
    cols = sorted(targets)  # the smallest target (the headline) first
    lines = ["## Speed against error: summary", "",
             f"{args.width}×{args.height} px, {args.threads} threads, medians of {args.reps} repetitions; time = wall "
             f"time to the target including first-shot preprocessing. Best baseline: the faster of "
             f"{', '.join(sorted(args.baselines)) if args.baselines else 'the baseline methods'} (no first-shot); best "
             f"first-shot: the fastest first-shot method; ratio = best baseline time / best first-shot time (>: the "
             f"baseline did not reach the target within its longest run; ≤/≥: a time was already below the target at "
             f"its first budget)."]
    for key, label in METRICS:
        lines += ["", f"**{label}**", ""]
        head = []
        for t in cols:
            head += [f"best baseline → {fmt_target(t)}", f"best first-shot → {fmt_target(t)}", f"ratio at {fmt_target(t)}"]
        goal_col = key == "rel_rmse"
        lines += ["| scene | " + " | ".join(head) + (" | goal | reference noise |" if goal_col else " |"),
                  "|---|" + "---|" * (len(head) + (2 if goal_col else 0))]
        for scene, per, goal_text, ref in summary_rows(scene_results, targets, key):
            cells = []
            for t in cols:
                cells += [describe_best(per[t]["baseline"]), describe_best(per[t]["firstshot"]),
                          format_ratio(*per[t]["ratio"])]
            extra = ""
            if goal_col:
                ref_note = f"{ref['noise_rel_rmse']:.4f} ({reference_spp(ref)} spp" + \
                           (", not converged)" if ref.get("status") == "time_limit" else ")")
                extra = f" | {goal_text} | {ref_note}"
            lines.append(f"| {scene} | " + " | ".join(cells) + extra + " |")
    text = "\n".join(lines) + "\n"
    with open(path, "w") as f:
        f.write(text)
    return text


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


def plot_scene(result, curves, path, all_methods):
    """Error against time, one line per method; a method's colour is fixed by its place in all_methods."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker  # noqa: F401 (used through matplotlib.ticker)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), dpi=100)
    noise = {"rel_rmse": result["ref"]["noise_rel_rmse"], "mare": result["ref"]["noise_mare"]}
    order = list(all_methods) + [m for m in result["methods"] if m not in all_methods]
    colour = {m: f"C{i % 10}" for i, m in enumerate(order)}
    style = {"baseline": "s--", "firstshot": "o-", "other": "^:"}
    for ax, (key, label) in zip(axes, METRICS):
        for m in order:
            role = result["roles"].get(m, "other")
            if m in curves:
                pts = sorted(curves[m], key=lambda p: p["total"])
                ax.loglog([p["total"] for p in pts], [p[key] for p in pts], style.get(role, "o-"), label=f"{m} ({role})",
                          markersize=4, color=colour[m])
            elif key == "rel_rmse" and m in all_methods:
                ax.plot([], [], "o-", color=colour[m], alpha=0.4, label=f"{m} (no result: {why_missing(result, m)})")
        ax.axhline(noise[key], color="grey", linestyle=":", linewidth=1, label="reference noise")
        for i, t in enumerate(sorted(result["targets"], reverse=True)):
            ax.axhline(t, color="black", linestyle="--", linewidth=0.6 + 0.3 * i,
                       label="targets" if i == 0 else None)
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


def resolve_scene(s):
    """(name, path) of a scene argument: a file, or NAME for scenes/NAME.json; None when neither exists."""
    if os.path.exists(s):
        return os.path.splitext(os.path.basename(s))[0], os.path.abspath(s)
    p = os.path.join(REPO, "scenes", s + ".json")
    return (s, p) if os.path.exists(p) else None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="Methods (METHODS):\n" + "\n".join(
                                     f"  {m}: {spec.about}; {spec.integrator} {shlex.join(spec.args)}"
                                     + (" [baseline]" if spec.baseline else "") for m, spec in METHODS.items())
                                 + "\n\nExample: bench/firstshot_bench.py cornell many-lights --build build/release")
    ap.add_argument("scenes", nargs="*", default=["cornell", "many-lights", "sierpinski-glossy", "fixture-room",
                                                  "office-floor"],
                    help="scene names (scenes/NAME.json) or files")
    ap.add_argument("--build", default=os.path.join(REPO, "build", "release"), help="CMake build folder with the tools")
    ap.add_argument("--out", default=None, help="output folder (default out/bench, out/bench/quick with --quick)")
    ap.add_argument("--methods", default=",".join(DEFAULT_METHODS),
                    help="comma-separated method names: a name from METHODS (below), or NAME (an integrator) or "
                         "NAME+firstshot (with a preprocessed first-shot table); rejected ones are skipped with a note")
    ap.add_argument("--baselines", default=None,
                    help="comma-separated methods that count as the baseline (default: "
                         + ",".join(m for m, s in METHODS.items() if s.baseline) + ")")
    ap.add_argument("--method-args", action="append", default=[], metavar="NAME=ARGS",
                    help="renderer arguments of a method, replacing its own ('path-tree=--light-sampler tree "
                         "--max-depth 8'), or NAME+=ARGS to add to them ('irradiance-cache+firstshot+=--accuracy 0.2')")
    ap.add_argument("--targets", default="0.05,0.02", help="target errors, rel. RMSE and MARE (default 0.05,0.02)")
    ap.add_argument("--budgets", default=None, help="render time budgets in seconds (default 1,2,4,...,128)")
    ap.add_argument("--max-budget", type=float, default=None, help="drop the budgets above this many seconds")
    ap.add_argument("--reps", type=int, default=None, help="repetitions (different seeds), medians (default 3)")
    ap.add_argument("--threads", type=int, default=2, help="threads of every tool (default 2)")
    ap.add_argument("--width", type=int, default=None, help="image width (default 160)")
    ap.add_argument("--height", type=int, default=None, help="image height (default 120)")
    ap.add_argument("--ref-method", default=None,
                    help="the reference's method, never first-shot (default per scene: path, office-floor path-tree)")
    ap.add_argument("--ref-spp", type=int, default=None,
                    help="the reference's starting spp, doubled until converged (default per scene)")
    ap.add_argument("--ref-noise-fraction", type=float, default=1 / 3,
                    help="the reference is converged when its noise (rel. RMSE) is at most this times the smallest "
                         "target (default 1/3)")
    ap.add_argument("--ref-max-minutes", type=float, default=None,
                    help="stop doubling the reference before it would take longer than this (default 60)")
    ap.add_argument("--ref-seed", type=int, default=1000, help="seed of the reference's first half A (then +1, +2, ...)")
    ap.add_argument("--seed", type=int, default=1, help="seed of repetition 0 (repetition k: +k)")
    ap.add_argument("--preprocess-args", default="", help="extra firstshot-preprocess arguments, e.g. '--resolution 128'")
    ap.add_argument("--timeout-factor", type=float, default=4.0,
                    help="a run is killed after F*budget+extra seconds (then not run again at budgets up to that one)")
    ap.add_argument("--timeout-extra", type=float, default=10.0)
    ap.add_argument("--no-accuracy", action="store_true", help="skip the preprocessing accuracy report")
    ap.add_argument("--accuracy-only", action="store_true", help="only the preprocessing accuracy report")
    ap.add_argument("--figures", default=None, help="copy the PNGs into this folder (e.g. docs/figures)")
    ap.add_argument("--replot", action="store_true",
                    help="no runs: tables, summary and plots again from OUT/<scene>/results.csv (e.g. other --targets)")
    ap.add_argument("--keep-images", action="store_true", help="keep every run's EXR under OUT/SCENE/runs/")
    ap.add_argument("--quick", action="store_true", help="smoke check of the plumbing: 80x60, budgets 0.25,0.5,1, "
                                                          "1 repetition, reference from 64 spp for at most 15 s, small "
                                                          "accuracy sweep (~2 min for two scenes)")
    args = ap.parse_args(argv)
    q = args.quick
    args.out = os.path.abspath(args.out or os.path.join(REPO, "out", "bench", "quick" if q else ""))
    args.targets = sorted(set(parse_list(args.targets)), reverse=True)
    if not args.targets or min(args.targets) <= 0:
        sys.exit("firstshot-bench: --targets wants positive errors, e.g. 0.05,0.02")
    args.budgets = parse_list(args.budgets or ("0.25,0.5,1" if q else "1,2,4,8,16,32,64,128"))
    if args.max_budget is not None:
        args.budgets = [b for b in args.budgets if b <= args.max_budget]
    if not args.budgets:
        sys.exit("firstshot-bench: no time budget left (--budgets, --max-budget)")
    args.reps = args.reps or (1 if q else 3)
    args.width = args.width or (80 if q else 160)
    args.height = args.height or (60 if q else 120)
    args.ref_spp = args.ref_spp or (64 if q else None)
    args.ref_max_minutes = args.ref_max_minutes if args.ref_max_minutes is not None else (0.25 if q else 60.0)
    args.methods = list(dict.fromkeys(m.strip() for m in args.methods.split(",") if m.strip()))
    args.baselines = ([m.strip() for m in args.baselines.split(",") if m.strip()] if args.baselines is not None
                      else [m for m, s in METHODS.items() if s.baseline])
    args.method_overrides, args.method_appended = parse_method_args(args.method_args)
    args.preprocess_args = shlex.split(args.preprocess_args)
    args.accuracy_resolutions = [64, 256] if q else [64, 128, 256, 512, 1024]
    scenes = []
    if not args.accuracy_only:
        for s in args.scenes:  # every scene before any long run
            resolved = resolve_scene(s)
            if resolved is None:
                sys.exit(f"firstshot-bench: no scene {s!r} (neither a file nor scenes/{s}.json)")
            scenes.append(resolved)
    tools = Tools(os.path.abspath(args.build))
    if not args.replot:
        tools.check(not args.no_accuracy)
    os.makedirs(args.out, exist_ok=True)
    t0 = time.perf_counter()
    pngs = []
    if not args.accuracy_only:
        log(f"firstshot-bench: targets {', '.join(fmt_target(t) for t in args.targets)}; budgets "
            f"{','.join(f'{b:g}' for b in args.budgets)} s; {args.reps} repetitions; {args.threads} threads; "
            f"{args.width}x{args.height}; methods {', '.join(args.methods)}; baselines {', '.join(args.baselines)}")
        scene_results = []
        for name, path in scenes:
            result = reload_scene(name, args) if args.replot else bench_scene(tools, name, path, args)
            curves = summarize(result)
            table = write_table(result, curves, os.path.join(args.out, f"table_{name}.md"))
            png = os.path.join(args.out, f"error_vs_time_{name}.png")
            plot_scene(result, curves, png, args.methods)
            pngs.append(png)
            scene_results.append((result, curves))
            log(table)
        summary = write_summary(scene_results, args.targets, os.path.join(args.out, "summary.md"), args)
        log(summary)
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
