"""Benchmarking one scene: the renderer and preprocessor command lines, probing which methods the tools accept,
checking the reference method, then every method at every time budget and repetition (interleaved, with
timeouts), each image compared with the reference; and reloading an earlier run's results for --replot.
"""
import json
import os
import shlex
import sys

from .config import method_role, rotated, scene_default, spec_of
from .formatting import fmt_num
from .reference import ensure_reference
from .tools import compare, last_line, log, parse_preprocess_summary, parse_render_summary, read_rows, run, write_rows


def render_cmd(tools, scene_path, spec, fsd, budget, seed, out, args):
    cmd = [tools.render, scene_path, "--integrator", spec.integrator]
    if fsd:
        cmd += ["--firstshot", fsd]
    cmd += spec.args
    if getattr(args, "sampler", None):
        cmd += ["--sampler", args.sampler]
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
