"""The converged path-traced reference of a scene: its cache key (scene bytes, renderer binary, method, size,
seeds), the cached record (reference.json) and the progressive rendering in two halves A and B that continues
until its noise reaches the goal or the time limit (see the docstring of bench/firstshot_bench.py).
"""
import hashlib
import json
import os
import shlex
import shutil
import sys

from .analysis import next_reference_round, predicted_spp, reference_goal, reference_seeds
from .config import scene_default, spec_of
from .tools import compare, log, mean_images, run


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
    key = reference_key(scene_path, tools.ref_render, method, spec, start_half, args.ref_seed, args.width, args.height)
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
            cmd = [tools.ref_render, scene_path, "--integrator", spec.integrator] + spec.args + [
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
