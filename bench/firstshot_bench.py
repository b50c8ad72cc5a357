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
import os
import shlex
import shutil
import sys
import time

# The code lives in the package bench/fsbench/ (one module per concern); this script is its entry point and
# re-exports every public name, so `import firstshot_bench as fb` sees the whole harness.
from fsbench.config import (  # noqa: F401 (re-exported)
    CSV_FIELDS, CSV_HEADER, DEFAULT_METHODS, DEFAULT_METHOD_ARGS, FALLBACK_DEFAULTS, FIRSTSHOT_SUFFIX, GOALS,
    IC_ARGS, METHODS, METRICS, Method, REPO, SCENE_DEFAULTS, method_role, method_spec, parse_list,
    parse_method_args, rotated, scene_default, spec_of, split_method,
)
from fsbench.formatting import (  # noqa: F401 (re-exported)
    describe_best, describe_ttt, fmt_num, fmt_seconds, fmt_target,
)
from fsbench.analysis import (  # noqa: F401 (re-exported)
    best_of, best_ratio, format_ratio, goal_check, goal_status, loglog_slope, median, next_reference_round,
    predicted_spp, ratio, reference_goal, reference_seeds, scene_targets, speedup, summarize, target_info,
    time_to_reach, time_to_target,
)
from fsbench.tools import (  # noqa: F401 (re-exported)
    Tools, compare, last_line, log, mean_images, parse_preprocess_summary, parse_render_summary, read_rows,
    run, write_rows,
)
from fsbench.reference import (  # noqa: F401 (re-exported)
    binary_identity, ensure_reference, load_reference, reference_key, sha256_file, write_reference_json,
)
from fsbench.runner import (  # noqa: F401 (re-exported)
    bench_scene, check_reference_method, preprocess_cmd, probe_methods, reload_scene, render_cmd,
)
from fsbench.report import (  # noqa: F401 (re-exported)
    minor_label, plot_scene, reference_spp, reference_text, summary_rows, why_missing, write_summary,
    write_table,
)
from fsbench.accuracy import (  # noqa: F401 (re-exported)
    accuracy_report, plot_accuracy,
)


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
    ap.add_argument("--ref-render", default=None,
                    help="firstshot-render binary for the reference (default: the build's). A copy of the renderer kept "
                         "apart (cp -p) lets a cached reference survive rebuilds that do not change the reference method; "
                         "the cache key then names that copy")
    ap.add_argument("--ref-seed", type=int, default=1000, help="seed of the reference's first half A (then +1, +2, ...)")
    ap.add_argument("--seed", type=int, default=1, help="seed of repetition 0 (repetition k: +k)")
    ap.add_argument("--sampler", default=None, choices=["sobol", "independent"],
                    help="firstshot-render --sampler of the timed runs (default: the renderer's own, sobol)")
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
    if args.ref_render:
        tools.ref_render = os.path.abspath(args.ref_render)
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
