#!/usr/bin/env python3
"""A clear coat as Blender writes it: builds a floor and two coated balls with Blender's Python
module (`pip install bpy`) — red plastic (Principled, roughness 0.5) under a smooth Coat (Coat
Weight 1, Coat Roughness 0.03, Blender's default, which its exporter leaves out of the file:
glTF's default roughness 0 is read) and gold (metallic 1, roughness 0.4) under half a glossy one
(Coat Weight 0.5, Coat Roughness 0.2) — lit by a sun, writes it with Blender's own glTF
exporter, checks that the export carries KHR_materials_clearcoat with those factors, and renders
the file back in Cycles (CPU) through Blender's own importer, so that smlt's rendering of the same
file can be set beside it:

    python3 blender_clearcoat.py OUT [--samples 1024] [--width 128] [--height 96]
    smlt reference OUT/coat.gltf --device cpu --spp 1024 --width 128 --height 96 --max-depth 10 \\
        --out OUT/smlt.exr
    python3 blender_clearcoat.py OUT --compare

The comparison prints the means of Cycles and smlt, whole and on each ball (masks from a render
of the balls alone). They are not the same model: Cycles' Principled coat (Blender 4+) is a
dielectric layer with the full Fresnel equations at the micro-normal, which attenuates the base
by what it reflects (energy-conserving) and refracts light into it, where glTF's is Schlick's
factor at N·V mixing two BRDFs; the comparison states the difference, it checks no equality.
Cycles as blender_round_trip.py sets it: single-scattering GGX, sun angle 0, box filter, no
denoising or clamping, 9 bounces (smlt's max depth 10), a black world.
"""

import argparse
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_round_trip import _look_rotation, cycles, read_exr  # noqa: E402

PAINT = {"Base Color": (0.6, 0.05, 0.04, 1.0), "Metallic": 0.0, "Roughness": 0.5,
         "Coat Weight": 1.0, "Coat Roughness": 0.03}
GOLD = {"Base Color": (1.0, 0.766, 0.336, 1.0), "Metallic": 1.0, "Roughness": 0.4,
        "Coat Weight": 0.5, "Coat Roughness": 0.2}


def build(out):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene

    def material(name, inputs):
        m = bpy.data.materials.new(name)
        m.use_nodes = True
        p = m.node_tree.nodes["Principled BSDF"]
        p.distribution = "GGX"
        for key, value in inputs.items():
            p.inputs[key].default_value = value
        return m

    lambert = {"Base Color": (0.5, 0.5, 0.5, 1.0), "Metallic": 0.0, "Roughness": 1.0, "Specular IOR Level": 0.0}
    bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0, 0, 0))
    bpy.context.object.data.materials.append(material("floor", lambert))
    for name, inputs, x in (("paint", PAINT, -0.7), ("gold", GOLD, 0.7)):
        bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=0.6, location=(x, 0, 0.6))
        bpy.ops.object.shade_smooth()
        bpy.context.object.data.materials.append(material(name, inputs))
    bpy.ops.object.light_add(type="SUN", location=(0, 0, 5))
    sun = bpy.context.object
    sun.data.energy = 2.0  # W/m^2
    sun.rotation_euler = _look_rotation((0.5, 0.4, -1.0))
    bpy.ops.object.camera_add(location=(0.0, 4.0, 2.0))
    cam = bpy.context.object
    cam.rotation_euler = _look_rotation((0.0, -4.0, -1.4))
    cam.data.lens_unit = "FOV"
    cam.data.sensor_fit = "VERTICAL"
    cam.data.angle = math.radians(35.0)
    scene.camera = cam
    path = os.path.join(out, "coat.gltf")
    bpy.ops.export_scene.gltf(filepath=path, export_format="GLTF_SEPARATE", export_cameras=True, export_lights=True)
    with open(path) as f:
        doc = json.load(f)
    mats = {m.get("name"): m for m in doc["materials"]}
    for name, inputs in (("paint", PAINT), ("gold", GOLD)):
        coat = mats.get(name, {}).get("extensions", {}).get("KHR_materials_clearcoat")
        # Blender 5.0's exporter leaves clearcoatRoughnessFactor out where Coat Roughness is
        # Blender's default 0.03 (io_scene_gltf2 .../extensions/clearcoat.py, BLENDER_COAT_ROUGHNESS),
        # so the file says glTF's default, 0: a smooth coat.
        roughness = 0.0 if abs(inputs["Coat Roughness"] - 0.03) < 1e-6 else inputs["Coat Roughness"]
        want = (inputs["Coat Weight"], roughness)
        got = None if coat is None else (coat.get("clearcoatFactor", 0.0), coat.get("clearcoatRoughnessFactor", 0.0))
        if got is None or any(abs(a - b) > 1e-6 for a, b in zip(got, want)):
            raise SystemExit(f"{path}: {name} exported as {json.dumps(mats.get(name))}, not a coat of {want}")
        print(f"{name}: {json.dumps(mats[name])}")
    print(f"extensionsUsed: {doc.get('extensionsUsed')}, extensionsRequired: {doc.get('extensionsRequired')}")
    return path


def compare(out):
    import numpy as np

    c, s = read_exr(os.path.join(out, "cycles.exr")), read_exr(os.path.join(out, "smlt.exr"))
    h, w, _ = c.shape
    # The balls' halves of the image: the paint left of centre, the gold right, above the floor's
    # far edge — rows and columns where the balls' silhouettes lie (the camera looks at them).
    m = lambda a: float(np.mean(a))  # noqa: E731
    left, right = (slice(int(0.25 * h), int(0.75 * h)), slice(int(0.15 * w), int(0.48 * w))), \
        (slice(int(0.25 * h), int(0.75 * h)), slice(int(0.52 * w), int(0.85 * w)))
    for label, (a, b) in (("whole image", (c, s)), ("paint ball's box", (c[left], s[left])),
                          ("gold ball's box", (c[right], s[right]))):
        # And without the one pixel where either image is brightest: a single firefly of a
        # short render moves a region's mean by a per cent.
        keep = np.ones(a.shape[:2], bool)
        keep[np.unravel_index(np.argmax(np.maximum(a, b).max(axis=2)), keep.shape)] = False
        print(f"{label}: Cycles {m(a):.5f}, smlt {m(b):.5f} ({100 * (m(a) / m(b) - 1):+.2f} %); without its"
              f" brightest pixel (Cycles {a.max(axis=2)[~keep][0]:.3f}, smlt {b.max(axis=2)[~keep][0]:.3f} there):"
              f" {100 * (m(a[keep]) / m(b[keep]) - 1):+.2f} %")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("out")
    p.add_argument("--samples", type=int, default=1024)
    p.add_argument("--width", type=int, default=128)
    p.add_argument("--height", type=int, default=96)
    p.add_argument("--compare", action="store_true")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    if a.compare:
        compare(a.out)
        return
    path = build(a.out)
    cycles(a.out, path, a.samples, a.width, a.height)


if __name__ == "__main__":
    main()
