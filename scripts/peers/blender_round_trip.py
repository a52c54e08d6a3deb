#!/usr/bin/env python3
"""The Blender round trip: builds a small lamp-lit scene with Blender's Python module (`pip
install bpy`), writes it with Blender's own glTF exporter, renders the file back in Cycles
(CPU) through Blender's own glTF importer, and writes what smlt needs to render the same file.

    python3 blender_round_trip.py OUT [--samples 1024] [--width 160] [--height 120]

OUT gets `round_trip.gltf` (+ .bin), `cycles.exr` and `cycles.txt` (the settings). Then
`smlt reference OUT/round_trip.gltf --width 160 --height 120 --spp 4096 --out OUT/smlt.exr` and
`python3 blender_round_trip.py OUT --compare [--picture PNG --ev EV]` prints the means of both
images, whole and by quarter (and draws them side by side, with OUT/render.exr third if there is
one: `smlt render OUT/round_trip.gltf --time 20 --width 160 --height 120 --out OUT/render.exr`).

The scene: a grey floor, a back wall, a red box and a white ball (flat-shaded, as smlt shades
with the geometric normal), lit by a point lamp, a spot and a sun, seen by one camera. Every
material is a Principled BSDF with metallic 0, roughness 1 and specular IOR level 0 — Lambertian
in Cycles, and what smlt reads of glTF today (the base colour as a Lambert albedo; the
exporter's KHR_materials_specular is ignored with a warning). Blender's importer gives point
and spot lamps radius 0 (a new lamp made in Blender has 0.1 m) but its sun the default angle of
0.526°; the Cycles render sets every radius and angle to 0 after import, so that both renderers
light the scene with true punctual lights, and says what it changed (`cycles.txt`). The spot's
cone is 40° with Blender's blend 0.01 (exported as 19.8°–20° half-angles): Blender's smoothstep
blend and glTF's ramp differ only in that 0.2°. Cycles: box pixel filter of 1 px, no denoising, no clamping, black world,
10 bounces; the EXR is linear (no view transform).
"""

import argparse
import math
import os
import sys


def build(out):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene

    def material(name, rgb):
        m = bpy.data.materials.new(name)
        m.use_nodes = True
        p = m.node_tree.nodes["Principled BSDF"]
        p.inputs["Base Color"].default_value = (*rgb, 1.0)
        p.inputs["Metallic"].default_value = 0.0
        p.inputs["Roughness"].default_value = 1.0
        p.inputs["Specular IOR Level"].default_value = 0.0
        return m

    def add(obj, mat):
        obj.data.materials.append(mat)
        return obj

    bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0, 0, 0))
    add(bpy.context.object, material("floor", (0.5, 0.5, 0.5)))
    bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0, -3.0, 2.0), rotation=(math.pi / 2, 0, 0))
    add(bpy.context.object, material("wall", (0.7, 0.68, 0.62)))
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(1.0, -0.8, 0.5), rotation=(0, 0, 0.4))
    add(bpy.context.object, material("red box", (0.6, 0.1, 0.08)))
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3, radius=0.6, location=(-0.9, 0.2, 0.6))
    add(bpy.context.object, material("white ball", (0.8, 0.8, 0.8)))

    bpy.ops.object.light_add(type="POINT", location=(-2.0, 0.5, 2.2))
    bpy.context.object.data.energy = 150.0  # W
    bpy.ops.object.light_add(type="SPOT", location=(2.5, 1.5, 3.0))
    spot = bpy.context.object
    spot.data.energy = 400.0
    spot.data.spot_size = math.radians(40.0)
    spot.data.spot_blend = 0.01
    direction = (1.0 - 2.5, -0.8 - 1.5, 0.5 - 3.0)
    spot.rotation_euler = _look_rotation(direction)
    bpy.ops.object.light_add(type="SUN", location=(0, 0, 5))
    sun = bpy.context.object
    sun.data.energy = 1.5  # W/m^2
    sun.rotation_euler = _look_rotation((0.4, 0.6, -1.0))

    bpy.ops.object.camera_add(location=(0.3, 6.5, 3.0))
    cam = bpy.context.object
    cam.rotation_euler = _look_rotation((-0.3, -6.5, -2.3))
    cam.data.lens_unit = "FOV"
    cam.data.sensor_fit = "VERTICAL"
    cam.data.angle = math.radians(45.0)
    scene.camera = cam

    path = os.path.join(out, "round_trip.gltf")
    bpy.ops.export_scene.gltf(filepath=path, export_format="GLTF_SEPARATE", export_cameras=True, export_lights=True)
    return path


def _look_rotation(direction):
    """The Euler rotation that points an object's −Z (a lamp's or camera's axis) along
    `direction`, its +Y up towards world +Z."""
    from mathutils import Vector

    return Vector(direction).to_track_quat("-Z", "Y").to_euler()


def cycles(out, path, samples, width, height):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    scene = bpy.context.scene
    notes = []
    for obj in scene.objects:
        if obj.type == "LIGHT":
            light = obj.data
            if light.type in ("POINT", "SPOT"):
                notes.append(f"{obj.name}: radius {light.shadow_soft_size:.3f} m set to 0")
                light.shadow_soft_size = 0.0
            if light.type == "SUN":
                notes.append(f"{obj.name}: angle {math.degrees(light.angle):.3f} deg set to 0")
                light.angle = 0.0
            notes.append(f"{obj.name}: {light.type} energy {light.energy:.4f}")
        if obj.type == "CAMERA":
            scene.camera = obj
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.max_bounces = c.diffuse_bounces = 10
    c.glossy_bounces = c.transmission_bounces = 10
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.filepath = os.path.join(out, "cycles.exr")
    bpy.ops.render.render(write_still=True)
    with open(os.path.join(out, "cycles.txt"), "w") as f:
        f.write(f"Cycles {bpy.app.version_string}, {samples} spp, {width}x{height}, box filter 1 px, 10 bounces\n")
        f.write("\n".join(notes) + "\n")
    print("\n".join(notes))


def read_exr(path):
    import bpy
    import numpy as np

    img = bpy.data.images.load(path)
    w, h = img.size
    px = np.array(img.pixels[:], dtype=np.float64).reshape(h, w, 4)[::-1, :, :3]  # top row first
    return px


def side_by_side(images, path, ev):
    """The images side by side as one sRGB PNG at exposure `ev` (clipped, no tone curve), through
    Mitsuba's Bitmap (a peers' requirement)."""
    import mitsuba as mi
    import numpy as np

    mi.set_variant("scalar_rgb")
    row = np.concatenate(images, axis=1) * 2.0**ev
    bitmap = mi.Bitmap(np.clip(row, 0, 1).astype(np.float32), mi.Bitmap.PixelFormat.RGB)
    bitmap.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, srgb_gamma=True).write(path)


def compare(out, picture, ev):
    a, b = read_exr(os.path.join(out, "cycles.exr")), read_exr(os.path.join(out, "smlt.exr"))
    if picture:
        extra = [read_exr(os.path.join(out, "render.exr"))] if os.path.exists(os.path.join(out, "render.exr")) else []
        side_by_side([a, b] + extra, picture, ev)
    h, w = a.shape[:2]
    print(f"whole image: Cycles {a.mean():.5f}, smlt {b.mean():.5f} ({100 * (a.mean() / b.mean() - 1):+.2f} %)")
    for name, (ys, xs) in {
        "top left": (slice(0, h // 2), slice(0, w // 2)),
        "top right": (slice(0, h // 2), slice(w // 2, w)),
        "bottom left": (slice(h // 2, h), slice(0, w // 2)),
        "bottom right": (slice(h // 2, h), slice(w // 2, w)),
    }.items():
        ma, mb = a[ys, xs].mean(), b[ys, xs].mean()
        print(f"{name}: Cycles {ma:.5f}, smlt {mb:.5f} ({100 * (ma / mb - 1):+.2f} %)")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--samples", type=int, default=1024)
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=120)
    ap.add_argument("--compare", action="store_true", help="compare OUT/cycles.exr with OUT/smlt.exr")
    ap.add_argument("--picture", default=None, help="with --compare: write Cycles | smlt [| OUT/render.exr] as a PNG")
    ap.add_argument("--ev", type=float, default=0.0, help="the picture's exposure")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    if a.compare:
        compare(a.out, a.picture, a.ev)
        return
    path = build(a.out)
    cycles(a.out, path, a.samples, a.width, a.height)


if __name__ == "__main__":
    sys.exit(main())
