#!/usr/bin/env python3
"""Writes the two large generated scenes of docs/measurements.md ("Scenes nobody here wrote, at the defaults").

- million-room.json: a 12 x 3 x 8 m room, three spheres of 327,680 triangles each (983,046 faces in all), 9 point
  lights and a spot under the ceiling.
- building.json: a 5-storey 62 x 62 m building of 4 m storeys: floor slabs, outer walls, 8 stairs of 60 steps,
  24 columns, 40 tables, 12 spheres of 20,480 triangles, 20 small lights (15 points, 5 spots); 24.7 M patches at a
  patch size of 0.05 m (the old default), 265,450 at the automatic one.

Neither sets a patch size: they measure the defaults. Standard library only; the output is the same on every run.

    python3 bench/large_scenes.py OUT_DIR      # writes OUT_DIR/million-room.json and OUT_DIR/building.json
"""
import json
import random
import sys


def million_room():
    points = [[x, 2.7, z] for z in (1.5, 6.5) for x in (1.5, 4.5, 7.5, 10.5)]
    lights = [{"type": "point", "position": p, "power": 60} for p in points]
    lights.append({"type": "spot", "position": [6, 2.8, 4], "direction": [0, -1, 0], "power": 100,
                   "inner_angle": 20, "outer_angle": 35})
    lights.append({"type": "point", "position": [11, 1.5, 7], "power": 30})
    return {
        "materials": {"white": {"type": "diffuse", "albedo": 0.6}, "grey": {"type": "diffuse", "albedo": 0.3}},
        "shapes": [
            {"type": "box", "material": "white", "min": [0, 0, 0], "max": [12, 3, 8], "flip_normals": True},
            {"type": "sphere", "material": "grey", "center": [3, 0.8, 3], "radius": 0.8, "subdivisions": 7},
            {"type": "sphere", "material": "grey", "center": [7, 0.8, 5], "radius": 0.8, "subdivisions": 7},
            {"type": "sphere", "material": "grey", "center": [10, 0.6, 2], "radius": 0.6, "subdivisions": 7}],
        "lights": lights,
        "camera": {"position": [0.5, 1.7, 7.5], "look_at": [8, 0.8, 2], "fov_y": 60, "resolution": [160, 100]}}


def building():
    rng = random.Random(7)
    width, storey, storeys = 62.0, 4.0, 5
    shapes, lights = [], []
    for f in range(storeys + 1):
        y = f * storey
        shapes.append({"type": "box", "material": "concrete", "min": [0, y - 0.3 if f else -0.3, 0], "max": [width, y, width]})
    shapes.append({"type": "box", "material": "white", "min": [-0.01, -0.3, -0.01],
                   "max": [width + 0.01, storeys * storey, width + 0.01], "flip_normals": True})
    rise = storeys * storey / 60
    for s in range(8):
        x0, z0 = 5 + (s % 4) * 14, (10 if s < 4 else 45)
        for k in range(60):
            shapes.append({"type": "box", "material": "wood", "min": [x0, k * rise, z0 + k * 0.3],
                           "max": [x0 + 1.5, k * rise + 0.15, z0 + k * 0.3 + 0.3]})
    for c in range(24):
        x, z = 7.5 + (c % 6) * 9, 7.5 + (c // 6) * 15
        shapes.append({"type": "box", "material": "concrete", "min": [x, 0, z], "max": [x + 0.5, storeys * storey, z + 0.5]})
    for t in range(40):
        f, x, z = t % storeys, rng.uniform(3, 55), rng.uniform(3, 55)
        shapes.append({"type": "box", "material": "wood", "min": [x, f * storey, z], "max": [x + 1.6, f * storey + 0.75, z + 0.8]})
    for s in range(12):
        f = s % storeys
        shapes.append({"type": "sphere", "material": "grey", "radius": 0.6, "subdivisions": 5,
                       "center": [rng.uniform(5, 55), f * storey + 0.6, rng.uniform(5, 55)]})
    for i in range(20):
        f = i % storeys
        if i % 4 == 0:
            lights.append({"type": "spot", "position": [rng.uniform(5, 55), f * storey + storey - 0.35, rng.uniform(5, 55)],
                           "direction": [0, -1, 0], "power": 100, "inner_angle": 20, "outer_angle": 40})
        else:
            lights.append({"type": "point", "position": [rng.uniform(5, 55), f * storey + storey - 0.4, rng.uniform(5, 55)],
                           "power": 60})
    return {
        "materials": {"white": {"type": "diffuse", "albedo": 0.7}, "concrete": {"type": "diffuse", "albedo": 0.4},
                      "wood": {"type": "diffuse", "albedo": [0.5, 0.35, 0.2]}, "grey": {"type": "diffuse", "albedo": 0.3}},
        "shapes": shapes, "lights": lights,
        "camera": {"position": [2, 1.7, 2], "look_at": [30, 1.5, 30], "fov_y": 60, "resolution": [160, 100]}}


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    for name, scene in (("million-room", million_room()), ("building", building())):
        with open(f"{sys.argv[1]}/{name}.json", "w") as f:
            json.dump(scene, f)
