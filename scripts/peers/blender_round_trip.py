#!/usr/bin/env python3
"""The Blender round trip: builds a small lamp-lit scene with a glass ball with Blender's Python
module (`pip install bpy`), writes it with Blender's own glTF exporter, renders the file back in
Cycles (CPU) through Blender's own glTF importer, and writes what smlt needs to render the same
file.

    python3 blender_round_trip.py OUT [--samples 2048] [--width 160] [--height 120] [--no-glass]

OUT gets `round_trip.gltf` (+ .bin), `cycles.exr` and `cycles.txt` (the settings). Then smlt's
path tracer, which renders what Cycles can: `smlt reference OUT/round_trip.gltf --device cpu
--width 160 --height 120 --spp 8192 --out OUT/smlt.exr`; and smlt's bidirectional estimator,
which also renders the lamps' caustics through the glass, in two independent halves:
`smlt render OUT/round_trip.gltf --device cpu --method naive --mutations-per-pixel 4096 --seed S
--width 160 --height 120 --max-depth 10 --out OUT/naive_S.exr` for S = 1, 2. Then
`python3 blender_round_trip.py OUT --compare [--picture PNG --ev EV]` prints the means, whole and
by quarter (Cycles against smlt pt; both against the naive halves' mean, with the halves'
spread), and draws Cycles | smlt pt | smlt naive side by side.

The scene: a grey floor, a back wall, a red box and a white ball (flat-shaded, as smlt shades
with the geometric normal), and a clear glass ball in front (`--no-glass`: without it, the
scene of the first round trip), lit by a point lamp, a spot and a sun, seen by one camera. The
opaque materials are Principled BSDFs with metallic 0, roughness 1 and specular IOR level 0 —
Lambertian in Cycles, and Lambertian in smlt (the exporter writes KHR_materials_specular
specularFactor 0). The glass is a Principled BSDF with Transmission Weight 1, roughness 0, IOR
1.52 and a "glTF Material Output" group whose Thickness is 1 (`glass_material`): the exporter
writes KHR_materials_transmission, KHR_materials_ior (only where the IOR is not glTF's default
1.5: at 1.5 it drops the extension) and KHR_materials_volume (only with that Thickness > 0;
without it the glTF glass would be thin-walled and would not bend light in smlt, where Cycles
always refracts through a closed mesh); `check_glass` refuses an export without them.
Blender's importer gives point and spot lamps radius 0 (a new lamp made in Blender has 0.1 m)
but its sun the default angle of 0.526°; the Cycles render sets every radius and angle to 0
after import, so that both renderers light the scene with true punctual lights, and says what
it changed (`cycles.txt`). The spot's cone is 40° with Blender's blend 0.01 (exported as
19.8°–20° half-angles): Blender's smoothstep blend and glTF's ramp differ only in that 0.2°.
Cycles: box pixel filter of 1 px, no denoising, no clamping, Filter Glossy 0, black world, 10
bounces; the EXR is linear (no view transform). Like every path tracer, Cycles cannot render a
delta lamp's light through or off smooth glass onto a diffuse surface (L S+ D E: its shadow rays
stop at the glass and no BSDF sample hits a point, spot or sun lamp), nor can smlt's `pt`; the
difference between them and smlt's `naive` is that light.
"""

import argparse
import math
import os
import sys


GLASS_AT = (-0.5, 1.6, 0.5)  # Blender's Z-up metres: in front of the white ball, below the point lamp
GLASS_RADIUS = 0.5
# Not 1.5: at glTF's default ior Blender's exporter drops KHR_materials_ior (an empty extension,
# blender/exp/material/extensions/ior.py), so 1.52 (crown glass) makes it write the extension smlt reads.
GLASS_IOR = 1.52


def glass_material():
    """Clear glass as Blender makes it and as its exporter writes it: a Principled BSDF with
    Transmission Weight 1, Roughness 0, IOR GLASS_IOR, metallic 0 and a white base colour
    (KHR_materials_transmission, KHR_materials_ior), and the exporter's "glTF Material Output"
    node group with a Thickness input > 0, which is what io_scene_gltf2 (Blender 5.0,
    blender/exp/material/extensions/volume.py) reads to write KHR_materials_volume: without it
    the exporter writes no volume and the glTF surface is thin-walled (no bending); with it the
    ball is a solid dielectric, as Cycles renders a closed glass mesh."""
    import bpy

    m = bpy.data.materials.new("glass")
    m.use_nodes = True
    nodes = m.node_tree.nodes
    p = nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    p.inputs["Metallic"].default_value = 0.0
    p.inputs["Roughness"].default_value = 0.0
    p.inputs["IOR"].default_value = GLASS_IOR
    p.inputs["Transmission Weight"].default_value = 1.0
    # The group io_scene_gltf2's importer makes (blender/com/material_helpers.py,
    # create_settings_group): inputs Occlusion and Thickness, matched by the group's name.
    group = bpy.data.node_groups.get("glTF Material Output")
    if group is None:
        group = bpy.data.node_groups.new("glTF Material Output", "ShaderNodeTree")
        group.interface.new_socket("Occlusion", in_out="INPUT", socket_type="NodeSocketFloat")
        group.interface.new_socket("Thickness", in_out="INPUT", socket_type="NodeSocketFloat")
        group.nodes.new("NodeGroupOutput")
        group.nodes.new("NodeGroupInput")
    settings = nodes.new("ShaderNodeGroup")
    settings.node_tree = group
    settings.inputs["Thickness"].default_value = 2 * GLASS_RADIUS  # any value > 0 makes it a solid
    return m


def build(out, glass=True):
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
    if glass:
        bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=4, radius=GLASS_RADIUS, location=GLASS_AT)
        add(bpy.context.object, glass_material())

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
    if glass:
        print(check_glass(path))
    return path


def check_glass(path):
    """That Blender's export of the glass is a solid dielectric glTF: the three extensions used,
    and the glass material's transmission 1, ior GLASS_IOR, roughness 0 and thicknessFactor > 0."""
    import json

    with open(path) as f:
        doc = json.load(f)
    used = set(doc.get("extensionsUsed", []))
    wanted = {"KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume"}
    if not wanted <= used:
        raise SystemExit(f"{path}: the export lacks {sorted(wanted - used)} (extensionsUsed: {sorted(used)})")
    (m,) = [m for m in doc["materials"] if m.get("name") == "glass"]
    ext = m["extensions"]
    facts = (ext["KHR_materials_transmission"].get("transmissionFactor", 0.0),
             ext["KHR_materials_ior"].get("ior", 1.5),
             m.get("pbrMetallicRoughness", {}).get("roughnessFactor", 1.0),
             ext["KHR_materials_volume"].get("thicknessFactor", 0.0))
    if facts[0] != 1.0 or abs(facts[1] - GLASS_IOR) > 1e-6 or facts[2] != 0.0 or not facts[3] > 0.0:
        raise SystemExit(f"{path}: glass exported as transmission, ior, roughness, thickness = {facts}")
    return (f"{path}: glass exported with {', '.join(sorted(wanted))}: transmissionFactor {facts[0]}, "
            f"ior {facts[1]}, roughnessFactor {facts[2]}, thicknessFactor {facts[3]}; "
            f"extensionsRequired {doc.get('extensionsRequired', [])}")


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
    c.blur_glossy = 0.0  # "Filter Glossy" (default 1) blurs sharp glass seen after a diffuse bounce: a bias
    c.light_sampling_threshold = 0.0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.filepath = os.path.join(out, "cycles.exr")
    import time

    start = time.time()
    bpy.ops.render.render(write_still=True)
    took = time.time() - start
    with open(os.path.join(out, "cycles.txt"), "w") as f:
        f.write(f"Cycles {bpy.app.version_string}, {samples} spp, {width}x{height}, box filter 1 px, 10 bounces,"
                f" filter glossy 0; rendered in {took:.1f} s\n")
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
    """Means whole and by quarter: Cycles against `smlt reference` (smlt's path tracer, which
    renders what Cycles can), and, where OUT/naive_*.exr exist (the multiplexed estimator's
    independent halves), smlt's bidirectional render against both: the light only it renders
    (the lamps' caustics through the glass), with the halves' spread as its noise."""
    import glob

    a, b = read_exr(os.path.join(out, "cycles.exr")), read_exr(os.path.join(out, "smlt.exr"))
    halves = [read_exr(p) for p in sorted(glob.glob(os.path.join(out, "naive_*.exr")))]
    c = sum(halves) / len(halves) if halves else None
    if picture:
        side_by_side([a, b] + ([c] if c is not None else []), picture, ev)
    h, w = a.shape[:2]
    regions = {
        "whole image": (slice(0, h), slice(0, w)),
        "top left": (slice(0, h // 2), slice(0, w // 2)),
        "top right": (slice(0, h // 2), slice(w // 2, w)),
        "bottom left": (slice(h // 2, h), slice(0, w // 2)),
        "bottom right": (slice(h // 2, h), slice(w // 2, w)),
    }
    for name, (ys, xs) in regions.items():
        ma, mb = a[ys, xs].mean(), b[ys, xs].mean()
        line = f"{name}: Cycles {ma:.5f}, smlt pt {mb:.5f} (Cycles {100 * (ma / mb - 1):+.2f} %)"
        if c is not None:
            mc = c[ys, xs].mean()
            line += f"; smlt naive {mc:.5f} (Cycles {100 * (ma / mc - 1):+.2f} %, pt {100 * (mb / mc - 1):+.2f} %)"
            if len(halves) == 2:
                spread = abs(halves[0][ys, xs].mean() - halves[1][ys, xs].mean()) / 2
                line += f", halves {halves[0][ys, xs].mean():.5f} {halves[1][ys, xs].mean():.5f} (±{100 * spread / mc:.2f} %)"
        print(line)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--samples", type=int, default=1024)
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=120)
    ap.add_argument("--compare", action="store_true", help="compare OUT/cycles.exr, OUT/smlt.exr [and OUT/naive_*.exr]")
    ap.add_argument("--picture", default=None, help="with --compare: write Cycles | smlt pt [| smlt naive] as a PNG")
    ap.add_argument("--ev", type=float, default=0.0, help="the picture's exposure")
    ap.add_argument("--no-glass", action="store_true", help="the scene without its glass ball (the lamps, box and ball alone)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    if a.compare:
        compare(a.out, a.picture, a.ev)
        return
    path = build(a.out, glass=not a.no_glass)
    cycles(a.out, path, a.samples, a.width, a.height)


if __name__ == "__main__":
    sys.exit(main())
