"""Text of numbers, targets, times and times to a target (fmt_num, fmt_target, fmt_seconds, describe_ttt,
describe_best), as the tables and the log print them. Standard library only, no other harness module.
"""
import math


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
