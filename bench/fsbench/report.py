"""The reports of the speed-against-error runs: the reference's description, the per-scene Markdown table
(median curves, time to every target, best baseline, best first-shot and their ratio, the goal), the summary
over scenes (OUT/summary.md) and the error-against-time plot (matplotlib, imported when plotting).
"""
import math
import shlex

from .analysis import format_ratio, goal_status, loglog_slope, median, scene_targets
from .config import METRICS
from .formatting import describe_best, describe_ttt, fmt_num, fmt_target


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
