"""The harness's maths, all pure (tested by bench/test_firstshot_bench.py): medians, the time a median curve needs
to reach a target (log-log interpolation, with the bounds it gives), log-log slopes, the best of several methods,
ratios of times with their relation and their text, the goal checks, the progressive reference's rounds and
seeds, and the median curves of a scene's runs with everything the tables need per metric and target.
"""
import math
import statistics

from .config import GOALS, METRICS
from .formatting import fmt_target


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
