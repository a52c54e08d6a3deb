#!/usr/bin/env python3
"""The Blender round trip: builds a small lamp-lit scene with a glass ball, a checker-textured
floor and a gold ball with Blender's Python module (`pip install bpy`), writes it with Blender's
own glTF exporter, renders the file back in Cycles (CPU) through Blender's own glTF importer,
and writes what smlt needs to render the same file.

    python3 blender_round_trip.py OUT [--samples 2048] [--width 160] [--height 120] [--no-glass] [--plain] [--draco]

OUT gets `round_trip.gltf` (+ .bin, and `checker.png` but with --plain), `cycles.exr` and
`cycles.txt` (the settings and what the render changed after the import). Then smlt's
path tracer, which renders what Cycles can: `smlt reference OUT/round_trip.gltf --device cpu
--width 160 --height 120 --spp 8192 --out OUT/smlt.exr`; and smlt's bidirectional estimator,
which also renders the lamps' caustics through the glass, in two independent halves:
`smlt render OUT/round_trip.gltf --device cpu --method naive --mutations-per-pixel 4096 --seed S
--width 160 --height 120 --max-depth 10 --out OUT/naive_S.exr` for S = 1, 2. Then
`python3 blender_round_trip.py OUT --compare [--picture PNG --ev EV]` prints the means, whole and
by quarter (Cycles against smlt pt; both against the naive halves' mean, with the halves'
spread), and draws Cycles | smlt pt | smlt naive side by side.

The scene: a checker floor, a back wall, a red box and a gold ball (flat-shaded, as smlt shades
with the geometric normal), and a clear glass ball in front (`--no-glass`: without it), lit by a
point lamp, a spot and a sun, seen by one camera. `--plain`: a grey floor (0.5) and a white ball
(0.8) instead of the checker and the gold, the scene of the first round trips (docs/results.md's
numbers; `--plain --no-glass` is the very first). `--draco`: exported with the exporter's Draco
mesh compression at its defaults (`KHR_draco_mesh_compression`; `check_blender_draco.py`). The wall, the box, the plain floor and ball
are Principled BSDFs with metallic 0, roughness 1 and specular IOR level 0 — Lambertian in
Cycles, and Lambertian in smlt (the exporter writes KHR_materials_specular specularFactor 0).
The checker floor is that Lambert with Base Color from an Image Texture (`checker_image`: 64×64
pixels, 8×8 squares, 8-bit sRGB 204 and 51, i.e. 0.8 and 0.2, linear 0.604 and 0.033) with
interpolation Closest (the exporter writes sampler magFilter NEAREST, minFilter
NEAREST_MIPMAP_NEAREST; Cycles looks the texel up without filtering or mipmaps) and extension
Repeat (wrap REPEAT, the default, not written), through a Mapping node (Point, scale 3) on the
plane's 0..1 UVs: the exporter writes it as KHR_texture_transform (scale [3, 3], offset [0, −2]:
glTF's v is Blender's 1 − v) and lists that extension in extensionsRequired; the importer makes
the Mapping node again. The exporter writes the image, encoded from its pixels, as
OUT/checker.png (GLTF_SEPARATE). The gold is a Principled BSDF with metallic 1, roughness 0.3
and base colour (1, 0.766, 0.336) (linear), exported as metallicFactor 1 (the default, not
written), roughnessFactor 0.3 and that baseColorFactor: Blender's roughness is glTF's (α = r²
in both), and with Specular Tint white (the default) Cycles' F82-tint metal Fresnel is Schlick's
with F0 = base colour, glTF's. Cycles' Principled BSDF defaults to multiscatter GGX, which adds
the light that glTF's single-scattering GGX loses on rough metal; the build sets 'GGX' and,
since the importer makes its Principled BSDFs with the default, the Cycles render sets every
Principled distribution to 'GGX' after import (it says so in `cycles.txt`; for the Lambert
materials and the smooth glass it changes nothing). `check_textured` refuses an export without
KHR_texture_transform, the floor's baseColorTexture, sampler (NEAREST, REPEAT), transform scale
or image file (with the checker's two values), or the gold's factors, and prints the floor's
material, texture, sampler and image JSON, its TEXCOORD_0 range and that range after the
transform (u 0..3, v −2..1). The glass is a Principled BSDF with Transmission Weight 1, roughness 0, IOR
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
Cycles: box pixel filter of 1 px, no denoising, no clamping, Filter Glossy 0, black world, 9
bounces (Cycles' count: its 0 is direct light only, smlt's `--max-depth 1`; so smlt's 10); the EXR is linear (no view transform). Like every path tracer, Cycles cannot render a
delta lamp's light through or off smooth glass onto a diffuse surface (L S+ D E: its shadow rays
stop at the glass and no BSDF sample hits a point, spot or sun lamp), nor can smlt's `pt`; the
difference between them and smlt's `naive` is that light.
"""

import argparse
import math
import os
import subprocess
import sys


GLASS_AT = (-0.5, 1.6, 0.5)  # Blender's Z-up metres: in front of the white ball, below the point lamp
GLASS_RADIUS = 0.5
# Not 1.5: at glTF's default ior Blender's exporter drops KHR_materials_ior (an empty extension,
# blender/exp/material/extensions/ior.py), so 1.52 (crown glass) makes it write the extension smlt reads.
GLASS_IOR = 1.52
# The textured scene (the default; --plain: the grey floor and white ball of the first round trips).
CHECKER_PIXELS, CHECKER_SQUARE = 64, 8  # 8 x 8 squares of 8 x 8 pixels
CHECKER_LIGHT, CHECKER_DARK = 204, 51  # 8-bit sRGB: 0.8 and 0.2
CHECKER_REPEAT = 3.0  # the Mapping node's UV scale: 3 x 3 checkers, 24 x 24 squares of 1/3 m on the 8 m floor
GOLD = (1.0, 0.766, 0.336)  # linear base colour
GOLD_ROUGHNESS = 0.3


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


def checker_image(bpy, np):
    """The floor's checker, CHECKER_PIXELS square, squares of CHECKER_SQUARE pixels alternating
    sRGB CHECKER_LIGHT and CHECKER_DARK (8-bit, so 204 and 51 exactly: linear 0.6038 and
    0.0331), the pixel (0, 0) — Blender's bottom left — light; no alpha. The exporter encodes
    it from these pixels and writes it as OUT/checker.png."""
    n, s = CHECKER_PIXELS, CHECKER_SQUARE
    img = bpy.data.images.new("checker", n, n, alpha=False)  # 8-bit, colour space sRGB
    y, x = np.mgrid[0:n, 0:n]
    light = ((x // s + y // s) % 2 == 0)[..., None]
    rgb = np.where(light, CHECKER_LIGHT / 255.0, CHECKER_DARK / 255.0) * np.ones(3)
    img.pixels.foreach_set(np.concatenate([rgb, np.ones((n, n, 1))], axis=2).astype(np.float32).ravel())
    img.update()
    return img


def build(out, glass=True, plain=False, draco=False, shape_keys=None, armature=None, vertex_colors=None):
    """Builds the scene in Blender and exports it to OUT/round_trip.gltf; its path. With
    `shape_keys` the white ball (`plain`) gets two shape keys, "squash" at 0.7 and "lift" at 0:
    "targets" exports them as morph targets with their weights (the exporter's default), "baked"
    exports Blender's own evaluation of the mix instead, a mesh without shape keys. With
    `armature` the ball is bent by a posed two-bone armature (`add_armature`): "posed" exports
    the skin with the pose (`export_rest_position_armature` off: the joints hold the current
    frame's pose), "baked" Blender's own evaluation of the posed mesh, without armature. With
    `vertex_colors` the ball's faces take four colours (`add_vertex_colors`): "attribute" as a
    colour attribute its material reads (exported as COLOR_0), "baked" as four materials of
    those base colours, one a face."""
    import bpy
    import numpy as np

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

    def checker_floor():
        # Lambert × texture: the material() Principled (metallic 0, roughness 1, specular IOR
        # level 0) with Base Color from an Image Texture (Closest: glTF magFilter NEAREST, a
        # point lookup in Cycles; Repeat: wrap REPEAT) through a Mapping node (Point, scale
        # CHECKER_REPEAT), which the exporter writes as KHR_texture_transform on the plane's
        # 0..1 UVs.
        m = material("floor", (1.0, 1.0, 1.0))
        nt = m.node_tree
        tex = nt.nodes.new("ShaderNodeTexImage")
        tex.image = checker_image(bpy, np)
        tex.interpolation = "Closest"
        tex.extension = "REPEAT"
        coords = nt.nodes.new("ShaderNodeTexCoord")
        mapping = nt.nodes.new("ShaderNodeMapping")
        mapping.vector_type = "POINT"
        mapping.inputs["Scale"].default_value = (CHECKER_REPEAT, CHECKER_REPEAT, 1.0)
        nt.links.new(coords.outputs["UV"], mapping.inputs["Vector"])
        nt.links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
        nt.links.new(tex.outputs["Color"], nt.nodes["Principled BSDF"].inputs["Base Color"])
        return m

    def gold():
        m = bpy.data.materials.new("gold")
        m.use_nodes = True
        p = m.node_tree.nodes["Principled BSDF"]
        p.distribution = "GGX"  # single scattering, glTF's; the importer's default is MULTI_GGX (cycles() sets it)
        p.inputs["Base Color"].default_value = (*GOLD, 1.0)
        p.inputs["Metallic"].default_value = 1.0
        p.inputs["Roughness"].default_value = GOLD_ROUGHNESS
        return m

    bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0, 0, 0))
    add(bpy.context.object, material("floor", (0.5, 0.5, 0.5)) if plain else checker_floor())
    bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0, -3.0, 2.0), rotation=(math.pi / 2, 0, 0))
    add(bpy.context.object, material("wall", (0.7, 0.68, 0.62)))
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(1.0, -0.8, 0.5), rotation=(0, 0, 0.4))
    add(bpy.context.object, material("red box", (0.6, 0.1, 0.08)))
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3, radius=0.6, location=(-0.9, 0.2, 0.6))
    ball = add(bpy.context.object, material("white ball", (0.8, 0.8, 0.8)) if plain else gold())
    if shape_keys:
        add_shape_keys(bpy, ball, baked=shape_keys == "baked")
    if armature:
        add_armature(bpy, ball, baked=armature == "baked")
    if vertex_colors:
        add_vertex_colors(bpy, ball, baked=vertex_colors == "baked")
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
    bpy.ops.export_scene.gltf(filepath=path, export_format="GLTF_SEPARATE", export_cameras=True, export_lights=True,
                              export_draco_mesh_compression_enable=draco, export_morph=shape_keys == "targets",
                              export_rest_position_armature=False)
    if glass:
        print(check_glass(path))
    if not plain:
        print(check_textured(path))
    return path


def add_shape_keys(bpy, obj, baked):
    """Two shape keys on `obj`: "squash" (z × 0.4, x × 1.5) at 0.7 and "lift" (y + 0.5) at 0.
    `baked`: the object's mesh replaced by Blender's evaluation of the mix, without keys."""
    obj.shape_key_add(name="Basis")
    squash = obj.shape_key_add(name="squash")
    for v in squash.data:
        v.co.z *= 0.4
        v.co.x *= 1.5
    squash.value = 0.7
    lift = obj.shape_key_add(name="lift")
    for v in lift.data:
        v.co.y += 0.5
    lift.value = 0.0
    if baked:
        evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
        mesh = bpy.data.meshes.new_from_object(evaluated)
        obj.shape_key_clear()
        obj.data = mesh


# The ball's face colours (linear RGB), face f taking colour f mod 4.
FACE_COLORS = [(0.8, 0.1, 0.1), (0.1, 0.7, 0.2), (0.15, 0.2, 0.8), (0.75, 0.7, 0.1)]


def add_vertex_colors(bpy, obj, baked):
    """Face f of `obj` (the ball) coloured FACE_COLORS[f mod 4]: as a face-corner colour attribute
    that a new material (Lambert, as `material()`) reads into its Base Color, or (`baked`) as
    four such materials with those base colours, one a face."""
    def lambert(name):
        m = bpy.data.materials.new(name)
        m.use_nodes = True
        p = m.node_tree.nodes["Principled BSDF"]
        p.inputs["Metallic"].default_value = 0.0
        p.inputs["Roughness"].default_value = 1.0
        p.inputs["Specular IOR Level"].default_value = 0.0
        return m, p

    mesh = obj.data
    mesh.materials.clear()
    if baked:
        for k, rgb in enumerate(FACE_COLORS):
            m, p = lambert(f"face colour {k}")
            p.inputs["Base Color"].default_value = (*rgb, 1.0)
            mesh.materials.append(m)
        for face in mesh.polygons:
            face.material_index = face.index % 4
        return
    colors = mesh.color_attributes.new("face colours", "FLOAT_COLOR", "CORNER")
    for face in mesh.polygons:
        for corner in face.loop_indices:
            colors.data[corner].color = (*FACE_COLORS[face.index % 4], 1.0)
    m, p = lambert("vertex colours")
    attribute = m.node_tree.nodes.new("ShaderNodeVertexColor")
    attribute.layer_name = "face colours"
    m.node_tree.links.new(attribute.outputs["Color"], p.inputs["Base Color"])
    mesh.materials.append(m)


def add_armature(bpy, obj, baked):
    """A two-bone armature bending `obj` (the ball, radius 0.6): "lower" from the ball's bottom to
    its centre, "upper" from its centre to its top (its child); the ball's lower half weighted to
    "lower", its upper half to "upper", blended linearly over 0.9 about the equator (over a
    narrower band, the blend folds the faces there). The armature object is moved and turned, and
    the ball made its child in place, so the exporter writes the ball's node under a transformed
    node (which a skinned mesh does not apply). Posed: "upper" turned 35° about its x axis,
    "lower" moved 0.1 along its x axis. `baked`: the ball's mesh replaced by Blender's evaluation
    of the pose, the armature removed."""
    from mathutils import Vector

    centre = obj.matrix_world.translation.copy()
    bpy.ops.object.armature_add(location=(0.2, -0.1, 0.05), rotation=(0, 0, math.radians(20.0)))
    arm = bpy.context.object
    to_armature = arm.matrix_world.inverted()
    bpy.ops.object.mode_set(mode="EDIT")
    lower = arm.data.edit_bones[0]
    lower.name = "lower"
    lower.head, lower.tail = to_armature @ (centre - Vector((0, 0, 0.6))), to_armature @ centre
    upper = arm.data.edit_bones.new("upper")
    upper.head, upper.tail = to_armature @ centre, to_armature @ (centre + Vector((0, 0, 0.6)))
    upper.parent = lower
    bpy.ops.object.mode_set(mode="OBJECT")
    obj.parent = arm
    obj.matrix_parent_inverse = to_armature  # the ball keeps its place
    obj.modifiers.new("armature", "ARMATURE").object = arm
    groups = obj.vertex_groups.new(name="lower"), obj.vertex_groups.new(name="upper")
    for v in obj.data.vertices:
        w = min(max((v.co.z + 0.45) / 0.9, 0.0), 1.0)
        groups[0].add([v.index], 1.0 - w, "REPLACE")
        groups[1].add([v.index], w, "REPLACE")
    arm.pose.bones["upper"].rotation_mode = "XYZ"
    arm.pose.bones["upper"].rotation_euler = (math.radians(35.0), 0, 0)
    arm.pose.bones["lower"].location = (0.1, 0, 0)
    bpy.context.view_layer.update()
    if baked:
        evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
        mesh = bpy.data.meshes.new_from_object(evaluated)
        world = obj.matrix_world.copy()
        obj.modifiers.clear()
        obj.vertex_groups.clear()
        obj.parent = None
        obj.matrix_world = world
        obj.data = mesh
        bpy.data.objects.remove(arm)


def in_own_python(code):
    """Runs `code` with this module imported as `blender_round_trip`, in a Python process of its
    own (bpy's scene is the process's, so each build or render starts clean): its stdout."""
    here = os.path.dirname(os.path.abspath(__file__))
    prelude = f"import sys; sys.path.insert(0, {here!r}); import blender_round_trip; "
    return subprocess.run([sys.executable, "-c", prelude + code], capture_output=True, text=True,
                          check=True).stdout


def check_textured(path):
    """That Blender's export of the textured scene is what it was built as: extensionsUsed has
    KHR_texture_transform; the floor's baseColorTexture has a sampler (magFilter NEAREST, wrap
    REPEAT) and an image file beside the .gltf holding the checker's two sRGB values, its
    KHR_texture_transform scale CHECKER_REPEAT, and the floor material is still Lambert
    (metallicFactor 0, KHR_materials_specular specularFactor 0); the gold material has
    metallicFactor 1, roughnessFactor GOLD_ROUGHNESS and baseColorFactor GOLD and no texture.
    Returns the JSON of the floor's material, texture, sampler and image, and its TEXCOORD_0
    range (the plane's UVs, before the transform) and that range after the transform."""
    import json
    import bpy
    import numpy as np

    def refuse(why):
        raise SystemExit(f"{path}: {why}")

    with open(path) as f:
        doc = json.load(f)
    used = set(doc.get("extensionsUsed", []))
    if "KHR_texture_transform" not in used:
        refuse(f"the export lacks KHR_texture_transform (extensionsUsed: {sorted(used)})")
    mats = {m.get("name"): m for m in doc["materials"]}
    floor, gold = mats.get("floor"), mats.get("gold")
    if floor is None or gold is None:
        refuse(f"no floor or gold material (materials: {sorted(mats)})")
    pbr = floor.get("pbrMetallicRoughness", {})
    info = pbr.get("baseColorTexture")
    if info is None:
        refuse(f"the floor has no baseColorTexture: {json.dumps(floor)}")
    if pbr.get("metallicFactor", 1.0) != 0.0 or \
            floor.get("extensions", {}).get("KHR_materials_specular", {}).get("specularFactor", 1.0) != 0.0:
        refuse(f"the floor is not Lambert × texture: {json.dumps(floor)}")
    if any(abs(c - 1.0) > 1e-6 for c in pbr.get("baseColorFactor", [1, 1, 1, 1])):
        refuse(f"the floor's baseColorFactor is not 1: {json.dumps(floor)}")
    texture = doc["textures"][info["index"]]
    if "sampler" not in texture or "source" not in texture:
        refuse(f"the floor's texture has no sampler or no source: {texture}")
    sampler, image = doc["samplers"][texture["sampler"]], doc["images"][texture["source"]]
    if sampler.get("magFilter") != 9728 or sampler.get("wrapS", 10497) != 10497 or sampler.get("wrapT", 10497) != 10497:
        refuse(f"the floor's sampler is not NEAREST, REPEAT: {sampler}")
    transform = info.get("extensions", {}).get("KHR_texture_transform")
    if transform is None or any(abs(v - CHECKER_REPEAT) > 1e-6 for v in transform.get("scale", [1, 1])):
        refuse(f"the floor's texture has no KHR_texture_transform of scale {CHECKER_REPEAT}: {info}")
    png = os.path.join(os.path.dirname(path), image.get("uri", ""))
    if "uri" not in image or not os.path.isfile(png):
        refuse(f"the floor's image {image} is not a file beside the export")
    img = bpy.data.images.load(png)
    values = sorted(set(np.round(np.array(img.pixels[:]).reshape(-1, 4)[:, :3] * 255).astype(int).ravel()))
    w, h = img.size
    bpy.data.images.remove(img)
    if values != sorted({CHECKER_LIGHT, CHECKER_DARK}) or (w, h) != (CHECKER_PIXELS, CHECKER_PIXELS):
        refuse(f"{png}: {w}x{h} with 8-bit values {values}, not the checker's")
    g = gold.get("pbrMetallicRoughness", {})
    facts = (g.get("metallicFactor", 1.0), g.get("roughnessFactor", 1.0), g.get("baseColorFactor", [1, 1, 1, 1])[:3])
    if facts[0] != 1.0 or abs(facts[1] - GOLD_ROUGHNESS) > 1e-6 or any(abs(a - b) > 1e-6 for a, b in zip(facts[2], GOLD)) \
            or "baseColorTexture" in g or "metallicRoughnessTexture" in g:
        refuse(f"gold exported as {json.dumps(gold)}")
    described = (f"{path}: floor material {json.dumps(floor)}\n  texture {json.dumps(texture)}, sampler {json.dumps(sampler)},"
                 f" image {json.dumps(image)} ({w}x{h}, 8-bit sRGB values {values})\n"
                 f"  gold material {json.dumps(gold)}")
    # The floor's TEXCOORD_n, read from the buffer (the exporter need not write min/max).
    (floor_mesh,) = [m for m in doc["meshes"] if any(p.get("material") == doc["materials"].index(floor)
                                                        for p in m["primitives"])]
    if any("KHR_draco_mesh_compression" in p.get("extensions", {}) for p in floor_mesh["primitives"]):
        return described + "\n  TEXCOORD_n: in a Draco stream, not read here"
    uv = []
    for prim in floor_mesh["primitives"]:
        acc = doc["accessors"][prim["attributes"][f"TEXCOORD_{info.get('texCoord', 0)}"]]
        view = doc["bufferViews"][acc["bufferView"]]
        with open(os.path.join(os.path.dirname(path), doc["buffers"][view["buffer"]]["uri"]), "rb") as f:
            f.seek(view.get("byteOffset", 0) + acc.get("byteOffset", 0))
            stride = view.get("byteStride", 8)
            raw = np.frombuffer(f.read(stride * acc["count"]), dtype=np.uint8).reshape(acc["count"], stride)
        uv.append(raw[:, :8].copy().view(np.float32).reshape(-1, 2))
    uv = np.concatenate(uv)
    scale, offset = transform.get("scale", [1, 1]), transform.get("offset", [0, 0])
    if transform.get("rotation", 0.0) != 0.0:
        refuse(f"the floor's texture transform rotates: {transform}")
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    tlo, thi = [lo[i] * scale[i] + offset[i] for i in (0, 1)], [hi[i] * scale[i] + offset[i] for i in (0, 1)]
    return (described + f"\n  TEXCOORD_{info.get('texCoord', 0)} u {lo[0]:g}..{hi[0]:g}, v {lo[1]:g}..{hi[1]:g};"
            f" after KHR_texture_transform u {min(tlo[0], thi[0]):g}..{max(tlo[0], thi[0]):g},"
            f" v {min(tlo[1], thi[1]):g}..{max(tlo[1], thi[1]):g}")


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
    for mat in bpy.data.materials:
        for node in (mat.node_tree.nodes if mat.node_tree else []):
            if node.type == "BSDF_PRINCIPLED" and node.distribution != "GGX":
                # glTF's microfacet BRDF is single-scattering GGX; the importer's Principled
                # BSDF gets Blender's default, multiscatter GGX (brighter rough metal).
                notes.append(f"{mat.name}: Principled distribution {node.distribution} set to GGX")
                node.distribution = "GGX"
            if node.type == "TEX_IMAGE" and node.image is not None:
                notes.append(f"{mat.name}: image {node.image.name} ({node.image.size[0]}x{node.image.size[1]},"
                             f" {node.image.colorspace_settings.name}), {node.interpolation}, {node.extension}")
            if node.type == "MAPPING":
                notes.append(f"{mat.name}: mapping {node.vector_type}, location "
                             f"{tuple(round(v, 6) for v in node.inputs['Location'].default_value)}, scale "
                             f"{tuple(round(v, 6) for v in node.inputs['Scale'].default_value)}")
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
    # smlt's --max-depth 10: Cycles' max_bounces counts one less (its 0 is direct light only)
    c.max_bounces = c.diffuse_bounces = 9
    c.glossy_bounces = c.transmission_bounces = 9
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
        f.write(f"Cycles {bpy.app.version_string}, {samples} spp, {width}x{height}, box filter 1 px, 9 bounces"
                f" (smlt's max depth 10),"
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
    ap.add_argument("--plain", action="store_true",
                    help="the untextured scene of the first round trips: grey floor and white ball, no checker, no gold")
    ap.add_argument("--draco", action="store_true",
                    help="export with the exporter's Draco mesh compression (KHR_draco_mesh_compression, its defaults)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    if a.compare:
        compare(a.out, a.picture, a.ev)
        return
    path = build(a.out, glass=not a.no_glass, plain=a.plain, draco=a.draco)
    cycles(a.out, path, a.samples, a.width, a.height)


if __name__ == "__main__":
    sys.exit(main())
