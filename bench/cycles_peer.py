"""Render a firstshot JSON scene with Blender's Cycles, the peer a graphics user would pick instead.

An optional peer for measurements, never run in CI. Run it with Blender (Debian package `blender`, 3.4):

    blender -b --factory-startup -P bench/cycles_peer.py -- SCENE.json -o OUT.exr \
        [--spp N] [--seed S] [--width W --height H] [--threads T] [--max-depth D] [--pattern pmj|sobol]

What is matched (docs/measurements.md, "Cycles beside firstshot", says how it was checked):
- geometry: quads (non-planar ones split along v0-v2, as the scene loader does), boxes, icospheres and mesh files
  (OBJ, glTF, PLY through Blender's importers), each with its transform; y-up metres become Blender's z-up
  metres by a rotation of +90 degrees about x (det +1, so normals and handedness are kept);
- materials: diffuse (Diffuse BSDF, roughness 0 = Lambert), mirror (sharp Glossy BSDF), dielectric (sharp Glass
  BSDF), emission one-sided on the front face like firstshot's (an Emission shader masked by Backfacing);
  "glossy" (stretched Phong) has no Cycles equivalent and is refused;
- lights: point (Power in W with radius 0: Cycles' intensity is P/(4 pi) W/sr, checked on point-over-plane),
  directional (a Sun of Strength = irradiance in W/m^2, angle 0);
- camera: pinhole, vertical field of view, the scene's resolution or --width/--height; a 1-pixel box filter (the
  renderer's uniform jitter within the pixel);
- integrator: path tracing with NEE and MIS, --max-depth bounces (firstshot's count: 1 = direct light only ->
  Cycles max_bounces = depth - 1), no clamping, no caustics filter, no adaptive sampling, no denoising; the
  sampling pattern is Cycles' default (progressive multi-jitter) unless --pattern sobol.
Prints "cycles: WxH at N spp in S s" (Cycles' own render time, without Blender's start-up) on stdout.
"""
import argparse
import json
import math
import os
import sys
import time

import bpy  # noqa: E402  (only inside Blender)
from mathutils import Matrix, Vector


def to_blender(p):
    """firstshot (x, y up, z) -> Blender (x, -z, y up)."""
    return Vector((p[0], -p[2], p[1]))


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="cycles_peer.py")
    ap.add_argument("scene")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--spp", type=int, default=None)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--width", type=int, default=None)
    ap.add_argument("--height", type=int, default=None)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--max-depth", type=int, default=None)
    ap.add_argument("--pattern", choices=["pmj", "sobol"], default="pmj")
    return ap.parse_args(argv)


def fail(where, what):
    print(f"cycles_peer: error: {where}: {what}", file=sys.stderr)
    sys.exit(2)


def transform_matrix(t):
    """The scene format's transform (scale, rotate axis-angle, translate, or a row-major matrix) in firstshot axes."""
    if not t:
        return Matrix.Identity(4)
    if "matrix" in t:
        m = t["matrix"]
        return Matrix([m[0:4], m[4:8], m[8:12], m[12:16]])
    s = t.get("scale", 1.0)
    s = [s, s, s] if isinstance(s, (int, float)) else s
    m = Matrix.Diagonal((s[0], s[1], s[2], 1.0))
    if "rotate" in t:
        ax, ay, az, deg = t["rotate"]
        m = Matrix.Rotation(math.radians(deg), 4, Vector((ax, ay, az)).normalized()) @ m
    if "translate" in t:
        m = Matrix.Translation(Vector(t["translate"])) @ m
    return m


def polygons(shape, where):
    """(vertices, faces) of a quad, box or sphere in firstshot axes, before the transform."""
    kind = shape["type"]
    if kind == "quad":
        v = [Vector(p) for p in shape["vertices"]]
        n = (v[1] - v[0]).cross(v[2] - v[0])
        planar = abs(n.normalized().dot(v[3] - v[0])) < 1e-6 * max(1.0, (v[2] - v[0]).length)
        return v, ([(0, 1, 2, 3)] if planar else [(0, 1, 2), (0, 2, 3)])
    if kind == "box":
        lo, hi = shape["min"], shape["max"]
        v = [Vector((hi[0] if i & 1 else lo[0], hi[1] if i & 2 else lo[1], hi[2] if i & 4 else lo[2])) for i in range(8)]
        faces = [(0, 4, 6, 2), (1, 3, 7, 5), (0, 1, 5, 4), (2, 6, 7, 3), (0, 2, 3, 1), (4, 5, 7, 6)]
        return v, faces
    fail(where, f"shape type '{kind}' is not exported (quad, box, sphere, mesh are)")


def add_mesh_object(name, verts, faces, matrix, flip, material):
    if flip:
        faces = [tuple(reversed(f)) for f in faces]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(to_blender(matrix @ v)) for v in verts], [], faces)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    obj.data.materials.append(material)
    bpy.context.scene.collection.objects.link(obj)


def import_mesh(path, matrix, flip, material, where):
    before = set(bpy.data.objects)
    ext = os.path.splitext(path)[1].lower()
    if ext == ".obj":
        bpy.ops.wm.obj_import(filepath=path, forward_axis="NEGATIVE_Z", up_axis="Y")
    elif ext in (".gltf", ".glb"):
        bpy.ops.import_scene.gltf(filepath=path)
    elif ext == ".ply":
        bpy.ops.import_mesh.ply(filepath=path)
    else:
        fail(where, f"mesh file {path}: no importer for '{ext}'")
    axes = Matrix.Rotation(math.radians(90), 4, "X")  # firstshot axes -> Blender axes
    for obj in set(bpy.data.objects) - before:
        if obj.type != "MESH":
            bpy.data.objects.remove(obj)
            continue
        # The importers already turned y-up files into z-up: undo that, apply the scene's transform, redo it.
        obj.matrix_world = axes @ matrix @ axes.inverted() @ obj.matrix_world
        obj.data.materials.clear()
        obj.data.materials.append(material)
        if flip:
            obj.data.flip_normals()


def make_material(name, m, where):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    kind = m.get("type", "diffuse")

    def rgb(key, default):
        c = m.get(key, default)
        c = [c, c, c] if isinstance(c, (int, float)) else c
        return (c[0], c[1], c[2], 1.0)

    if kind == "diffuse":
        bsdf = nodes.new("ShaderNodeBsdfDiffuse")
        bsdf.inputs["Color"].default_value = rgb("albedo", 0.0)
        bsdf.inputs["Roughness"].default_value = 0.0
    elif kind == "mirror":
        bsdf = nodes.new("ShaderNodeBsdfGlossy")
        bsdf.distribution = "SHARP"
        bsdf.inputs["Color"].default_value = rgb("specular", 1.0)
    elif kind == "dielectric":
        bsdf = nodes.new("ShaderNodeBsdfGlass")
        bsdf.distribution = "SHARP"
        bsdf.inputs["Color"].default_value = rgb("transmittance", 1.0)
        bsdf.inputs["IOR"].default_value = m["ior"]
    else:
        fail(where, f"material type '{kind}' has no Cycles equivalent")
    shader = bsdf.outputs[0]
    emission = rgb("emission", 0.0)
    if max(emission[:3]) > 0:
        # One-sided like firstshot's area lights: emission times (1 - backfacing), added to the BSDF.
        em = nodes.new("ShaderNodeEmission")
        em.inputs["Color"].default_value = emission
        em.inputs["Strength"].default_value = 1.0
        geo = nodes.new("ShaderNodeNewGeometry")
        mix = nodes.new("ShaderNodeMixShader")
        links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
        links.new(em.outputs[0], mix.inputs[1])
        add = nodes.new("ShaderNodeAddShader")
        links.new(mix.outputs[0], add.inputs[0])
        links.new(shader, add.inputs[1])
        shader = add.outputs[0]
    links.new(shader, out.inputs["Surface"])
    return mat


def add_light(i, light):
    kind, name = light["type"], light.get("name", f"lights[{i}]")
    if kind == "point":
        if "power" not in light:
            fail(name, "only point lights given by 'power' (W) are exported")
        p = light["power"]
        p = [p, p, p] if isinstance(p, (int, float)) else p
        energy = max(p)
        data = bpy.data.lights.new(name, "POINT")
        data.energy = energy
        data.color = [c / energy for c in p] if energy > 0 else (0, 0, 0)
        data.shadow_soft_size = 0.0
        obj = bpy.data.objects.new(name, data)
        obj.location = to_blender(light["position"])
    elif kind == "directional":
        e = light["irradiance"]
        e = [e, e, e] if isinstance(e, (int, float)) else e
        data = bpy.data.lights.new(name, "SUN")
        data.energy = max(e)
        data.color = [c / max(e) for c in e] if max(e) > 0 else (0, 0, 0)
        data.angle = 0.0
        obj = bpy.data.objects.new(name, data)
        d = to_blender(light["direction"]).normalized()
        obj.rotation_euler = d.to_track_quat("-Z", "Y").to_euler()  # a sun shines along its local -z
    else:
        fail(name, f"light type '{kind}' is not exported (point, directional are)")
    bpy.context.scene.collection.objects.link(obj)


def build_scene(desc, base, args):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    mats = {}
    for name, m in desc.get("materials", {}).items():
        mats[name] = make_material(name, m, f"{args.scene}: materials.{name}")
    for i, shape in enumerate(desc.get("shapes", [])):
        where = f"{args.scene}: shapes[{i}]"
        matrix = transform_matrix(shape.get("transform"))
        flip = bool(shape.get("flip_normals", False))
        mat = mats[shape["material"]]
        if shape["type"] == "mesh":
            import_mesh(os.path.join(base, shape["file"]), matrix, flip, mat, where)
        elif shape["type"] == "sphere":
            bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=shape.get("subdivisions", 3) + 1,
                                                  radius=shape["radius"])
            obj = bpy.context.active_object
            axes = Matrix.Rotation(math.radians(90), 4, "X")
            obj.matrix_world = axes @ matrix @ Matrix.Translation(Vector(shape["center"]))
            obj.data.materials.append(mat)
            if flip:
                obj.data.flip_normals()
        else:
            v, faces = polygons(shape, where)
            add_mesh_object(shape.get("name", f"shape{i}"), v, faces, matrix, flip, mat)
    for i, light in enumerate(desc.get("lights", [])):
        add_light(i, light)
    cam = desc["camera"]
    data = bpy.data.cameras.new("camera")
    data.sensor_fit = "VERTICAL"
    data.angle_y = math.radians(cam.get("fov_y", 45.0))
    obj = bpy.data.objects.new("camera", data)
    eye, at = to_blender(cam["position"]), to_blender(cam["look_at"])
    up = to_blender(cam.get("up", [0, 1, 0]))
    forward = (at - eye).normalized()
    right = forward.cross(up).normalized()
    true_up = right.cross(forward)
    rot = Matrix((right, true_up, -forward)).transposed()  # columns: camera x, y, z (looks along -z)
    obj.matrix_world = Matrix.Translation(eye) @ rot.to_4x4()
    scene.collection.objects.link(obj)
    scene.camera = obj
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    res = cam.get("resolution", [512, 512])
    settings = desc.get("settings", {})
    return scene, res, settings


def configure(scene, res, settings, args):
    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x = args.width or res[0]
    r.resolution_y = args.height or res[1]
    r.resolution_percentage = 100
    r.threads_mode = "FIXED" if args.threads else "AUTO"
    if args.threads:
        r.threads = args.threads
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    r.image_settings.color_mode = "RGB"
    c = scene.cycles
    c.device = "CPU"
    c.samples = args.spp or settings.get("spp", 64)
    c.seed = args.seed
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.light_sampling_threshold = 0.0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    depth = args.max_depth or settings.get("max_depth", 16)
    bounces = max(depth - 1, 0)
    c.max_bounces = bounces
    for key in ("diffuse_bounces", "glossy_bounces", "transmission_bounces", "transparent_max_bounces"):
        setattr(c, key, bounces)
    c.volume_bounces = 0
    c.sampling_pattern = "SOBOL" if args.pattern == "sobol" else "PROGRESSIVE_MULTI_JITTER"
    scene.view_settings.view_transform = "Standard"


def main():
    args = parse_args()
    try:
        with open(args.scene) as f:
            desc = json.load(f)
    except (OSError, ValueError) as e:
        fail(args.scene, str(e))
    scene, res, settings = build_scene(desc, os.path.dirname(os.path.abspath(args.scene)), args)
    configure(scene, res, settings, args)
    scene.render.filepath = os.path.abspath(args.output)
    t0 = time.time()
    bpy.ops.render.render(write_still=True)
    seconds = time.time() - t0
    print(f"cycles: {scene.render.resolution_x}x{scene.render.resolution_y} at {scene.cycles.samples} spp in "
          f"{seconds:.3f} s", flush=True)


main()
