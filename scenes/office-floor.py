#!/usr/bin/env python3
"""Generates scenes/office-floor.json: one floor of an office building lit by hundreds of small lights.

The floor is 40 m x 20 m with a 3 m ceiling (x from 0 to 40, z from 0 to 20, y up). Two corridors 2 m wide run its
whole length (z 6-8 and z 12-14), joined by a cross corridor (x 19-21). Along the south and north facades are offices
(ten 4 m x 6 m ones to the south, six 5 m x 6 m ones and a 10 m x 6 m meeting room to the north); the block between
the corridors holds two meeting rooms, a kitchen and two small rooms: 22 rooms in all. Walls are 0.12 m thick boxes
with door openings (1 m x 2.1 m, a lintel above); the facade walls are single quads. Rooms hold desks (boxes: top and
two side panels), chairs, cabinets and tables.

Lights (all small, so first-shot replaces every one of them): ceiling spots (downlights 5 cm under the ceiling) over
desks and tables, at the office doors and every 2 m along the corridors, and point lights for desk lamps, lamps and
pendants. From any one point most of them are hidden behind walls, which is what makes next-event estimation to every
light expensive here. The camera stands in the south corridor and looks south-west: through the doors of two offices
onto their lit desks, with the corridor running off to the west past further doors.

As generated: 454 shapes, 217 lights (144 spots, 73 points); patches from settings.patch_size 0.5 m, refined to
0.03125 m where shadows cross them (156,819 after refinement).

Standard library only, no randomness: the output is the same byte for byte on every run. Regenerate with

    python3 scenes/office-floor.py > scenes/office-floor.json

or give the output file as the only argument: python3 scenes/office-floor.py scenes/office-floor.json
"""
import json
import sys

WIDTH, DEPTH, HEIGHT = 40.0, 20.0, 3.0  # x, z, y (metres)
WALL = 0.12                             # interior wall thickness
DOOR_WIDTH, DOOR_HEIGHT = 1.0, 2.1
CEILING_LIGHT_Y = HEIGHT - 0.05

shapes = []
lights = []


def num(v):
    """Rounds to 0.1 mm and writes whole numbers without a fraction, for a stable and compact file."""
    v = round(v, 4)
    return int(v) if v == int(v) else v


def vec(v):
    return [num(c) for c in v]


def box(name, material, lo, hi):
    shapes.append({"type": "box", "name": name, "material": material, "min": vec(lo), "max": vec(hi)})


def quad(name, material, vertices):
    shapes.append({"type": "quad", "name": name, "material": material, "vertices": [vec(v) for v in vertices]})


def spot(name, x, z, power, inner=30, outer=50, y=CEILING_LIGHT_Y):
    lights.append({"type": "spot", "name": name, "position": vec([x, y, z]), "direction": [0, -1, 0],
                   "power": vec(power), "inner_angle": inner, "outer_angle": outer})


def point(name, x, y, z, power):
    lights.append({"type": "point", "name": name, "position": vec([x, y, z]), "power": vec(power)})


def wall_x(name, z, x0, x1, doors=()):
    """A wall along x at z (centre of its thickness) from x0 to x1, with doors centred at the given x."""
    wall(name, 0, z, x0, x1, doors)


def wall_z(name, x, z0, z1, doors=()):
    """A wall along z at x from z0 to z1, with doors centred at the given z."""
    wall(name, 2, x, z0, z1, doors)


def wall(name, axis, at, a0, a1, doors):
    # axis is the coordinate the wall runs along (0 = x, 2 = z); 'at' is the other horizontal coordinate.
    # A door is its centre (DOOR_WIDTH x DOOR_HEIGHT) or (centre, width, height).
    def make(label, s0, s1, y0, y1):
        lo, hi = [0.0, y0, 0.0], [0.0, y1, 0.0]
        other = 2 - axis
        lo[axis], hi[axis] = s0, s1
        lo[other], hi[other] = at - WALL / 2, at + WALL / 2
        box(f"{name} {label}", "wall", lo, hi)

    openings = sorted(d if isinstance(d, tuple) else (d, DOOR_WIDTH, DOOR_HEIGHT) for d in doors)
    start = a0
    for k, (centre, width, height) in enumerate(openings):
        d0, d1 = centre - width / 2, centre + width / 2
        if d0 > start:
            make(f"segment {k}", start, d0, 0.0, HEIGHT)
        make(f"lintel {k}", d0, d1, height, HEIGHT)
        start = d1
    if a1 > start:
        make(f"segment {len(openings)}", start, a1, 0.0, HEIGHT)


def desk(name, x0, z0, chair_south=False):
    """A 1.6 m (x) by 0.8 m (z) desk with its low corner at (x0, z0), a monitor, a chair on its north side
    (+z; south side with chair_south) and a desk lamp (a point light over its back corner)."""
    w, d = 1.6, 0.8
    box(f"{name} top", "desk", [x0, 0.72, z0], [x0 + w, 0.75, z0 + d])
    box(f"{name} panel 0", "desk_frame", [x0 + 0.02, 0, z0 + 0.05], [x0 + 0.05, 0.72, z0 + d - 0.05])
    box(f"{name} panel 1", "desk_frame", [x0 + w - 0.05, 0, z0 + 0.05], [x0 + w - 0.02, 0.72, z0 + d - 0.05])
    if chair_south:
        box(f"{name} chair", "chair", [x0 + 0.55, 0, z0 - 0.6], [x0 + 1.05, 0.45, z0 - 0.1])
        box(f"{name} monitor", "dark", [x0 + 0.5, 0.75, z0 + d - 0.18], [x0 + 1.1, 1.15, z0 + d - 0.15])
        point(f"{name} lamp", x0 + 0.2, 1.15, z0 + d - 0.2, [3.0, 2.7, 2.2])
    else:
        box(f"{name} chair", "chair", [x0 + 0.55, 0, z0 + d + 0.1], [x0 + 1.05, 0.45, z0 + d + 0.6])
        box(f"{name} monitor", "dark", [x0 + 0.5, 0.75, z0 + 0.15], [x0 + 1.1, 1.15, z0 + 0.18])
        point(f"{name} lamp", x0 + 0.2, 1.15, z0 + 0.2, [3.0, 2.7, 2.2])


# --- Shell: floor, ceiling, facades (single quads, normals inward). ---
quad("floor", "floor", [[WIDTH, 0, 0], [0, 0, 0], [0, 0, DEPTH], [WIDTH, 0, DEPTH]])
quad("ceiling", "ceiling", [[WIDTH, HEIGHT, 0], [WIDTH, HEIGHT, DEPTH], [0, HEIGHT, DEPTH], [0, HEIGHT, 0]])
quad("facade south", "wall", [[0, 0, 0], [WIDTH, 0, 0], [WIDTH, HEIGHT, 0], [0, HEIGHT, 0]])
quad("facade north", "wall", [[WIDTH, 0, DEPTH], [0, 0, DEPTH], [0, HEIGHT, DEPTH], [WIDTH, HEIGHT, DEPTH]])
quad("facade west", "wall", [[0, 0, DEPTH], [0, 0, 0], [0, HEIGHT, 0], [0, HEIGHT, DEPTH]])
quad("facade east", "wall", [[WIDTH, 0, 0], [WIDTH, 0, DEPTH], [WIDTH, HEIGHT, DEPTH], [WIDTH, HEIGHT, 0]])

SOUTH_CORRIDOR = (6.0, 8.0)
NORTH_CORRIDOR = (12.0, 14.0)
CROSS_CORRIDOR = (19.0, 21.0)

# --- South offices: ten rooms 4 m wide between the facade (z = 0) and the south corridor. ---
south_doors = []
for i in range(10):
    x0 = 4.0 * i
    door = x0 + (3.2 if i % 2 == 0 else 0.8)
    south_doors.append(door)
    room = f"south office {i}"
    if i > 0:
        wall_z(f"{room} west wall", x0, 0.0, SOUTH_CORRIDOR[0] - WALL / 2)
    # Four desks: two by the facade, two in the middle of the room.
    for r, z0 in enumerate((0.6, 3.0)):
        for c, dx in enumerate((0.25, 2.15)):
            desk(f"{room} desk {r}.{c}", x0 + dx, z0)
            spot(f"{room} downlight {r}.{c}", x0 + dx + 0.8, z0 + 0.4, [18, 17, 15])
    spot(f"{room} door light", door, 5.2, [12, 11, 10], inner=35, outer=60)
    cab_x = x0 + 0.15 if i % 2 == 0 else x0 + 3.45
    box(f"{room} cabinet", "cabinet", [cab_x, 0, 4.4], [cab_x + 0.4, 1.2, 5.6])
wall_x("south corridor wall", SOUTH_CORRIDOR[0], 0.0, WIDTH, south_doors)

# --- North rooms: six 5 m offices and a 10 m meeting room between the north corridor and the facade. ---
north_rooms = [(0, 5), (5, 10), (10, 20), (20, 25), (25, 30), (30, 35), (35, 40)]
north_doors = []
for i, (x0, x1) in enumerate(north_rooms):
    room = f"north room {i}"
    if i > 0:
        wall_z(f"{room} west wall", x0, NORTH_CORRIDOR[1] + WALL / 2, DEPTH)
    if x1 - x0 > 5:
        room = "north meeting room"
        north_doors += [x0 + 1.0, x1 - 1.0]
        box(f"{room} table top", "desk", [x0 + 2.0, 0.72, 16.2], [x1 - 2.0, 0.76, 17.8])
        for k, tx in enumerate((x0 + 2.3, x1 - 2.5)):
            box(f"{room} table foot {k}", "desk_frame", [tx, 0, 16.7], [tx + 0.2, 0.72, 17.3])
        for k in range(6):
            cx = x0 + 2.5 + 1.0 * k
            box(f"{room} chair south {k}", "chair", [cx, 0, 15.5], [cx + 0.5, 0.45, 16.0])
            box(f"{room} chair north {k}", "chair", [cx + 0.5, 0, 18.0], [cx + 1.0, 0.45, 18.5])
        box(f"{room} sideboard", "cabinet", [x0 + 3.0, 0, 19.45], [x1 - 3.0, 0.9, 19.95])
        for k in range(5):
            spot(f"{room} downlight {k}", x0 + 2.0 + 1.5 * k, 17.0, [16, 15, 13], inner=25, outer=45)
        for k, px in enumerate((x0 + 3.5, x1 - 3.5)):
            point(f"{room} pendant {k}", px, 2.3, 17.0, [10, 9, 7.5])
        spot(f"{room} entrance light", x0 + 5.0, 15.0, [12, 11, 10], inner=35, outer=60)
        continue
    door = x0 + (1.0 if i % 2 else 4.0)
    north_doors.append(door)
    for r, z0 in enumerate((18.9, 16.4)):
        for c, dx in enumerate((0.4, 2.9)):
            desk(f"{room} desk {r}.{c}", x0 + dx, z0, chair_south=True)
            spot(f"{room} downlight {r}.{c}", x0 + dx + 0.8, z0 + 0.4, [18, 17, 15])
    spot(f"{room} door light", door, 14.8, [12, 11, 10], inner=35, outer=60)
wall_x("north corridor wall", NORTH_CORRIDOR[1], 0.0, WIDTH, north_doors)

# --- Central block between the corridors: meeting rooms A and B, a kitchen, two small rooms. ---
central = [("meeting room A", 0.0, 9.5), ("meeting room B", 9.5, 19.0), ("kitchen", 21.0, 30.0),
           ("print room", 30.0, 35.0), ("quiet room", 35.0, 40.0)]
z0c, z1c = SOUTH_CORRIDOR[1], NORTH_CORRIDOR[0]
central_south_doors, central_north_doors = [], []
for name, x0, x1 in central:
    if x0 not in (0.0, CROSS_CORRIDOR[1]):
        wall_z(f"{name} west wall", x0, z0c + WALL / 2, z1c - WALL / 2)
    if name.startswith("meeting"):
        central_south_doors.append(x1 - 1.2)
        central_north_doors.append(x0 + 1.2)
        box(f"{name} table top", "desk", [x0 + 1.8, 0.72, 9.3], [x1 - 1.8, 0.76, 10.7])
        box(f"{name} table foot", "desk_frame", [x0 + 3.0, 0, 9.8], [x1 - 3.0, 0.72, 10.2])
        for k in range(5):
            cx = x0 + 2.3 + 1.0 * k
            box(f"{name} chair {k}", "chair", [cx, 0, 8.6], [cx + 0.5, 0.45, 9.1])
        for k in range(4):
            spot(f"{name} downlight {k}", x0 + 2.3 + 1.6 * k, 10.0, [16, 15, 13], inner=25, outer=45)
        point(f"{name} pendant", 0.5 * (x0 + x1), 2.2, 10.0, [8, 7.5, 6.5])
    elif name == "kitchen":
        central_south_doors.append(x0 + 1.2)
        central_north_doors.append(x1 - 1.2)
        box(f"{name} counter", "cabinet", [x0 + 2.0, 0, z1c - WALL / 2 - 0.65], [x1 - 2.0, 0.9, z1c - WALL / 2])
        box(f"{name} counter top", "desk", [x0 + 2.0, 0.9, z1c - WALL / 2 - 0.65], [x1 - 2.0, 0.94, z1c - WALL / 2])
        box(f"{name} table", "desk", [x0 + 3.0, 0.72, 9.0], [x0 + 6.0, 0.76, 10.0])
        box(f"{name} table foot", "desk_frame", [x0 + 4.3, 0, 9.3], [x0 + 4.7, 0.72, 9.7])
        for k in range(3):
            point(f"{name} pendant {k}", x0 + 3.5 + 1.0 * k, 2.1, 9.5, [6, 5.5, 4.5])
        for k in range(4):
            spot(f"{name} counter light {k}", x0 + 2.5 + 1.3 * k, z1c - 0.5, [10, 9.5, 8.5], inner=20, outer=40)
    else:
        central_south_doors.append(x0 + 1.0)
        box(f"{name} cabinet", "cabinet", [x1 - 1.6, 0, z1c - WALL / 2 - 0.5], [x1 - 0.2, 1.4, z1c - WALL / 2])
        box(f"{name} table", "desk", [x0 + 1.5, 0.72, 9.4], [x0 + 3.3, 0.76, 10.4])
        for k in range(2):
            spot(f"{name} downlight {k}", x0 + 1.5 + 2.0 * k, 10.0, [14, 13, 12])
        point(f"{name} lamp", x1 - 0.9, 1.6, z1c - 0.4, [4, 3.6, 3])
cross = (0.5 * sum(CROSS_CORRIDOR), CROSS_CORRIDOR[1] - CROSS_CORRIDOR[0] - WALL, 2.4)  # the cross corridor's ends
wall_x("central block south wall", z0c, 0.0, WIDTH, central_south_doors + [cross])
wall_x("central block north wall", z1c, 0.0, WIDTH, central_north_doors + [cross])
wall_z("cross corridor west wall", CROSS_CORRIDOR[0], z0c + WALL / 2, z1c - WALL / 2)
wall_z("cross corridor east wall", CROSS_CORRIDOR[1], z0c + WALL / 2, z1c - WALL / 2)

# --- Corridor lights: a spot every 2 m along each corridor, and two in the cross corridor. ---
for k in range(20):
    x = 1.0 + 2.0 * k
    spot(f"south corridor spot {k}", x, 0.5 * sum(SOUTH_CORRIDOR), [3, 3, 3], inner=35, outer=60)
    spot(f"north corridor spot {k}", x, 0.5 * sum(NORTH_CORRIDOR), [3, 3, 3], inner=35, outer=60)
for k, z in enumerate((9.2, 10.8)):
    spot(f"cross corridor spot {k}", 0.5 * sum(CROSS_CORRIDOR), z, [3, 3, 3], inner=35, outer=60)

scene = {
    "description": ("One office floor, 40 m x 20 m x 3 m: 22 rooms (offices, meeting rooms, a kitchen) on two "
                    f"corridors, walls with door openings, desks, and {len(lights)} small lights (ceiling spots over "
                    "desks, at doors and along the corridors; point lights for desk lamps and pendants), most of them "
                    "hidden from any one point. Generated by office-floor.py (see its docstring)."),
    "camera": {"position": [29.6, 1.6, 7.75], "look_at": [25.5, 1.0, 3.5], "up": [0, 1, 0], "fov_y": 60,
               "resolution": [640, 360]},
    "materials": {
        "floor": {"type": "diffuse", "albedo": [0.35, 0.33, 0.3]},
        "ceiling": {"type": "diffuse", "albedo": 0.8},
        "wall": {"type": "diffuse", "albedo": [0.62, 0.6, 0.57]},
        "desk": {"type": "diffuse", "albedo": [0.55, 0.42, 0.28]},
        "desk_frame": {"type": "diffuse", "albedo": 0.3},
        "chair": {"type": "diffuse", "albedo": [0.15, 0.2, 0.4]},
        "dark": {"type": "diffuse", "albedo": 0.05},
        "cabinet": {"type": "diffuse", "albedo": [0.7, 0.7, 0.68]},
    },
    "shapes": shapes,
    "lights": lights,
    "settings": {"patch_size": 0.5, "spp": 64, "seed": 1, "item_buffer_resolution": 256},
}


def dumps(value, indent=0):
    """JSON with two-space indentation; arrays of numbers (and short arrays of them) stay on one line."""
    pad, inner = "  " * indent, "  " * (indent + 1)
    if isinstance(value, dict):
        items = [f"{inner}{json.dumps(k)}: {dumps(v, indent + 1)}" for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(value, list):
        scalar = all(not isinstance(x, (list, dict)) for x in value)
        points = len(value) <= 4 and all(isinstance(x, list) and all(not isinstance(y, (list, dict)) for y in x)
                                         for x in value)
        if scalar or points:
            return json.dumps(value)
        return "[\n" + ",\n".join(inner + dumps(x, indent + 1) for x in value) + "\n" + pad + "]"
    return json.dumps(value)


text = dumps(scene) + "\n"
USAGE = "usage: python3 scenes/office-floor.py [output.json]   (default: standard output)"
if len(sys.argv) == 2 and sys.argv[1] in ("-h", "--help"):
    print(USAGE)
    sys.exit(0)
if len(sys.argv) > 2 or (len(sys.argv) == 2 and sys.argv[1].startswith("-")):
    print(USAGE, file=sys.stderr)
    sys.exit(2)
if len(sys.argv) == 2:
    with open(sys.argv[1], "w", encoding="utf-8") as out:
        out.write(text)
else:
    sys.stdout.write(text)
