#!/usr/bin/env python3
"""What --integrator auto chooses on every scene, without and with its first-shot table, and the pilot's figures.

usage: bench/pilot_choices.py BUILD TABLES [--time S] [--size W H] [--seed N] [SCENES...]
  BUILD: build/release; TABLES: a folder for the scenes' tables (made at the preprocessor's defaults where absent);
  --time (default 20), --size (default 128 128) and --seed (default: the scene's) as the render is given them, one
  thread; SCENES: scene files
  (default: the shipped scenes and those of ../shared/scenes).
Each render is stopped once the choice is printed (the pilot alone runs). Prints, per scene and table, the pilot's
table and its choice; the last lines list the choices alone, one per line, to compare two builds with diff.
"""
import glob
import os
import subprocess
import sys
import tempfile


def main():
    args = sys.argv[1:]
    if len(args) < 2:
        sys.exit(__doc__)
    build, tables = args[0], args[1]
    rest = args[2:]
    seconds, size, seed = "20", ["128", "128"], []
    scenes = []
    i = 0
    while i < len(rest):
        if rest[i] == "--time":
            seconds, i = rest[i + 1], i + 2
        elif rest[i] == "--seed":
            seed, i = ["--seed", rest[i + 1]], i + 2
        elif rest[i] == "--size":
            size, i = rest[i + 1:i + 3], i + 3
        else:
            scenes.append(rest[i])
            i += 1
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    if not scenes:
        scenes = sorted(glob.glob(os.path.join(here, "scenes", "*.json")))
        shared = os.path.join(here, "..", "shared", "scenes")
        if os.path.isdir(shared):
            scenes += [os.path.join(shared, s) for s in ("veach-bidir/scene.xml", "veach-mis/scene.xml",
                                                          "bitterli-cornell-box/scene.xml",
                                                          "mcguire-cornell-box/CornellBox-Original.obj",
                                                          "classroom/scene.xml")]
        else:
            print("pilot_choices: ../shared/scenes is absent: the public scenes are left out", file=sys.stderr)
    os.makedirs(tables, exist_ok=True)
    render = os.path.join(build, "render", "firstshot-render")
    preprocess = os.path.join(build, "preprocess", "firstshot-preprocess")
    choices = []
    with tempfile.TemporaryDirectory() as scratch:
        for scene in scenes:
            tag = os.path.basename(os.path.dirname(scene)) + "-" + os.path.splitext(os.path.basename(scene))[0]
            table = os.path.join(tables, tag + ".fsd")
            if not os.path.exists(table):
                if subprocess.run([preprocess, scene, "-o", table, "--threads", "1", "-q"],
                                  capture_output=True).returncode != 0:
                    table = None
            for extra in ([], ["--firstshot", table] if table else None):
                if extra is None:
                    continue
                name = f"{tag} {'table' if extra else 'none'}"
                print(f"=== {name}", flush=True)
                cmd = [render, scene, *extra, "--width", size[0], "--height", size[1], "--time", seconds,
                       "--threads", "1", *seed, "-o", os.path.join(scratch, "x.exr")]
                p = subprocess.Popen(cmd, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True)
                shown, chose = False, "-"
                for line in p.stderr:
                    shown = shown or "pilot at" in line
                    if shown:
                        print(line.rstrip())
                    if "--integrator auto" in line and ("chose " in line or not shown):
                        chose = line.split("chose ", 1)[1].split(" (efficiency")[0] if "chose " in line else \
                            line.split("auto: ", 1)[1].strip()
                        if not shown:
                            print(line.rstrip())
                        break
                p.kill()
                p.wait()
                choices.append(f"{name}: {chose}")
    print("\n".join(choices))


if __name__ == "__main__":
    main()
