#!/usr/bin/env python3
"""The tangent-frame check scene: a smooth UV sphere with a normalTexture, half of it mapped
mirror-wise, built with Blender's Python module (`pip install bpy`) and written twice by
Blender's own glTF exporter, with and without TANGENT, to check how smlt builds the tangent
frame of glTF's normalTexture on a curved mesh against Blender (MikkTSpace tangents) and Cycles
(`cycles_normals.py` renders the files' shading normals).

    python3 tangent_scene.py OUT [--segments 24] [--rings 12] [--tilt 35] [--texels 64] [--blocks 8]

OUT gets `tangents.gltf` (+ `tangents.bin`), `no_tangents.gltf` (+ `no_tangents.bin`) and
`tangent_normals.png`, the normal map both name. Then
`python3 cycles_normals.py OUT/tangents.gltf --width 160 --height 120 --spp 16 --out normals.exr`.

The scene, in Blender's axes (Z up; the exporter writes glTF's Y up: x, y, z -> x, z, -y):
- a UV sphere of radius 1 at the origin (--segments around, --rings from pole to pole),
  smooth-shaded, with Blender's own UV map ("UVMap": u once around, from the seam on -x; v
  from the south pole, 0, to the north pole, 1). The UVs of every face whose centre has x < 0
  are then mirrored, u -> 1 - u, loop by loop (a face's corners, so a vertex shared by a
  mirrored and an unmirrored face gets both): that half is mapped orientation-reversed, and its
  MikkTSpace bitangent sign (Blender's `bitangent_sign`, glTF's TANGENT w: bitangent =
  w cross(normal, tangent)) is -1 where the other half's is +1. All UVs stay in [0, 1]. The
  vertices sit at multiples of 360 / segments degrees from +x, so with --segments a multiple
  of 4 (24: every 15 degrees) the plane x = 0 runs along edges and no face straddles it; the
  script refuses a sphere with a face centred on x = 0 (--segments 2 mod 4);
- a material: Principled BSDF, base colour 0.8, roughness 1, metallic 0, Specular IOR Level 0
  (Lambertian, as smlt's peers write it; the exporter adds KHR_materials_specular
  specularFactor 0), its Normal from a Normal Map node (space Tangent, the UV map "UVMap",
  strength 1: glTF's normalTexture, scale 1) of an Image Texture (Non-Color, Closest: the
  exporter writes sampler NEAREST) of `tangent_normals.png`: --texels square, 8-bit RGB,
  written here (`pattern`), packed into the .blend data so that the exporter copies its bytes;
- a perspective camera 3.5 from the origin, along (0.2, -1, 0.6) (normalised; above the
  equator, off every axis), looking at the origin with +Z up, vertical field of view 40
  degrees, render size 160 x 120 (aspect 4:3, exported as the camera's aspectRatio): the
  unmirrored half (x > 0) fills the image's right and middle, the mirrored half (x < 0) its
  left (about 2800 of the sphere's 7500 pixels), the boundary between them (x = 0, seen near
  y = -1) runs down the image a little left of its centre, and the north pole's region is near
  the top; the image's centre sees a flat block of the normal map on the unmirrored half;
- a sun (Blender 3 W/m^2, from above, off every axis), exported as a KHR_lights_punctual
  directional light, for a shaded render; the normals do not need it.

The normal map (`pattern`): --blocks x --blocks square blocks of texels, each one tangent-space
normal n, stored as glTF's normalTexture stores it, rgb = round((n + 1) / 2 * 255), with the
image's +y up in the image (glTF's and OpenGL's convention, and Blender's Normal Map node's:
green grows towards the image's top row, which is v = 1 in Blender and v = 0 in glTF, whose v
runs down). Block (i, j), i its column from the left and j its row from the top, gets kind
(i + 2 j) mod 6 of: flat (0, 0, 1); leaning +x; leaning +y; leaning -y; leaning -x; leaning
along (+x + y) / sqrt(2); each tilted by --tilt degrees (default 35) from +z. Neighbouring
blocks differ in both directions.

Checks (the script stops with a message where one fails): Blender's MikkTSpace signs
(`Mesh.calc_tangents`) are -1 on every loop of the mirrored faces and +1 on all others; with
Python's json, that tangents.gltf's primitive has TANGENT and no_tangents.gltf's does not, and
that both name a normalTexture whose image is `tangent_normals.png` with the pattern's bytes.
It prints the counts of TANGENT w = -1 and +1 (read from the .bin with numpy), and those on
either side of x = 0 (glTF's x is Blender's), and the time each step took.
"""

import argparse
import json
import math
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from normal_map_scene import png  # noqa: E402

CAMERA_DIRECTION = (0.2, -1.0, 0.6)  # Blender's axes: from the origin towards the camera
CAMERA_DISTANCE = 3.5
CAMERA_YFOV = 40.0  # degrees
WIDTH, HEIGHT = 160, 120
SUN_DIRECTION = (0.3, 0.5, -1.0)  # Blender's axes: where the sun's light travels
IMAGE_NAME = "tangent_normals"
COMPONENTS = {5126: np.float32}
WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def pattern(texels, blocks, tilt):
    """The normal map as 8-bit RGB, (texels, texels, 3), its top row first (see the docstring)."""
    if texels % blocks:
        raise SystemExit(f"--texels {texels} is not a multiple of --blocks {blocks}")
    s, c = math.sin(math.radians(tilt)), math.cos(math.radians(tilt))
    d = s / math.sqrt(2.0)
    kinds = [(0.0, 0.0, 1.0), (s, 0.0, c), (0.0, s, c), (0.0, -s, c), (-s, 0.0, c), (d, d, c)]
    size = texels // blocks
    j, i = np.mgrid[0:texels, 0:texels] // size
    n = np.array(kinds)[(i + 2 * j) % len(kinds)]
    return np.round((n + 1.0) / 2.0 * 255.0).astype(np.uint8)


def look_rotation(direction):
    """The Euler rotation that points an object's -Z (a camera's or lamp's axis) along
    `direction`, its +Y up towards world +Z."""
    from mathutils import Vector

    return Vector(direction).to_track_quat("-Z", "Y").to_euler()


def mirror_uvs(mesh):
    """Mirrors u -> 1 - u on every loop of the faces whose centre has x < 0; returns the
    faces' mirrored flags."""
    uv = mesh.uv_layers.active.uv
    values = np.empty(len(mesh.loops) * 2, np.float32)
    uv.foreach_get("vector", values)
    values = values.reshape(-1, 2)
    centres = np.empty(len(mesh.polygons) * 3, np.float32)
    mesh.polygons.foreach_get("center", centres)
    mirrored = centres.reshape(-1, 3)[:, 0] < 0.0
    if np.any(np.abs(centres.reshape(-1, 3)[:, 0]) < 1e-4):
        raise SystemExit("a face's centre lies on x = 0: use --segments a multiple of 4")
    starts = np.empty(len(mesh.polygons), np.int32)
    totals = np.empty(len(mesh.polygons), np.int32)
    mesh.polygons.foreach_get("loop_start", starts)
    mesh.polygons.foreach_get("loop_total", totals)
    loop_face = np.repeat(np.arange(len(mesh.polygons)), totals)
    if not np.array_equal(np.repeat(starts, totals) + np.concatenate([np.arange(t) for t in totals]),
                          np.arange(len(mesh.loops))):
        raise SystemExit("the sphere's loops are not in face order")
    flip = mirrored[loop_face]
    values[flip, 0] = 1.0 - values[flip, 0]
    if values.min() < 0.0 or values.max() > 1.0:
        raise SystemExit(f"UVs outside [0, 1] after the mirror: {values.min(0)} .. {values.max(0)}")
    uv.foreach_set("vector", values.ravel())
    mesh.update()
    return mirrored, loop_face


def check_signs(mesh, mirrored, loop_face):
    """Blender's MikkTSpace bitangent signs: -1 on the mirrored faces' loops, +1 elsewhere."""
    mesh.calc_tangents(uvmap=mesh.uv_layers.active.name)
    signs = np.empty(len(mesh.loops), np.float32)
    mesh.loops.foreach_get("bitangent_sign", signs)
    mesh.free_tangents()
    want = np.where(mirrored[loop_face], -1.0, 1.0)
    wrong = int(np.count_nonzero(signs != want))
    if wrong:
        raise SystemExit(f"MikkTSpace signs: {wrong} of {len(signs)} loops not -1 on the mirrored half, +1 elsewhere")
    return (f"Blender's MikkTSpace bitangent signs: {int(np.count_nonzero(signs < 0))} loops -1 (all on the"
            f" {int(mirrored.sum())} mirrored faces), {int(np.count_nonzero(signs > 0))} loops +1"
            f" ({int((~mirrored).sum())} faces)")


def build(a, png_path):
    """The scene in a new, empty Blender file (see the docstring)."""
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_uv_sphere_add(segments=a.segments, ring_count=a.rings, radius=1.0, location=(0, 0, 0))
    sphere = bpy.context.object
    sphere.name = sphere.data.name = "sphere"
    bpy.ops.object.shade_smooth()
    mirrored, loop_face = mirror_uvs(sphere.data)
    signs = check_signs(sphere.data, mirrored, loop_face)

    image = bpy.data.images.load(png_path)
    image.name = IMAGE_NAME
    image.colorspace_settings.name = "Non-Color"
    image.pack()  # the exporter copies a packed PNG's bytes (io_scene_gltf2 encode_image, "happy path")
    m = bpy.data.materials.new("normal mapped")
    if m.node_tree is None:  # Blender < 5.0 (5.0 makes the nodes; use_nodes is deprecated)
        m.use_nodes = True
    nt = m.node_tree
    p = nt.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (0.8, 0.8, 0.8, 1.0)
    p.inputs["Roughness"].default_value = 1.0
    p.inputs["Metallic"].default_value = 0.0
    p.inputs["Specular IOR Level"].default_value = 0.0
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = image
    tex.interpolation = "Closest"
    normal_map = nt.nodes.new("ShaderNodeNormalMap")
    normal_map.space = "TANGENT"
    normal_map.uv_map = sphere.data.uv_layers.active.name
    normal_map.inputs["Strength"].default_value = 1.0
    nt.links.new(tex.outputs["Color"], normal_map.inputs["Color"])
    nt.links.new(normal_map.outputs["Normal"], p.inputs["Normal"])
    sphere.data.materials.append(m)

    d = np.array(CAMERA_DIRECTION) / np.linalg.norm(CAMERA_DIRECTION)
    bpy.ops.object.camera_add(location=tuple(CAMERA_DISTANCE * d))
    cam = bpy.context.object
    cam.name = "camera"
    cam.rotation_euler = look_rotation(tuple(-d))
    cam.data.lens_unit = "FOV"
    cam.data.sensor_fit = "VERTICAL"
    cam.data.angle = math.radians(CAMERA_YFOV)
    scene.camera = cam
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    bpy.ops.object.light_add(type="SUN", location=(0, 0, 5))
    sun = bpy.context.object
    sun.name = "sun"
    sun.data.energy = 3.0
    sun.data.angle = 0.0
    sun.rotation_euler = look_rotation(SUN_DIRECTION)
    return signs


def export(path, tangents):
    import bpy

    bpy.ops.export_scene.gltf(filepath=path, export_format="GLTF_SEPARATE", export_tangents=tangents,
                              export_normals=True, export_texcoords=True, export_cameras=True, export_lights=True,
                              export_yup=True, export_materials="EXPORT")


def accessor(doc, folder, index):
    """An accessor's elements as a numpy array (float components, no sparse storage)."""
    acc = doc["accessors"][index]
    if acc["componentType"] not in COMPONENTS or "sparse" in acc:
        raise SystemExit(f"accessor {index}: {acc} is not a plain float accessor")
    width = WIDTHS[acc["type"]]
    view = doc["bufferViews"][acc["bufferView"]]
    dtype = np.dtype(COMPONENTS[acc["componentType"]]).newbyteorder("<")
    stride = view.get("byteStride", width * dtype.itemsize)
    with open(os.path.join(folder, doc["buffers"][view["buffer"]]["uri"]), "rb") as f:
        f.seek(view.get("byteOffset", 0) + acc.get("byteOffset", 0))
        raw = f.read(stride * (acc["count"] - 1) + width * dtype.itemsize)
    rows = np.lib.stride_tricks.as_strided(np.frombuffer(raw, np.uint8), (acc["count"], width * dtype.itemsize),
                                           (stride, 1))
    return rows.copy().view(dtype).reshape(acc["count"], width)


def check_export(path, tangents, png_bytes):
    """What the brief wants of each file (see the docstring); returns lines to print."""
    folder = os.path.dirname(os.path.abspath(path))
    with open(path) as f:
        doc = json.load(f)
    prims = [p for m in doc["meshes"] for p in m["primitives"]]
    if len(prims) != 1:
        raise SystemExit(f"{path}: {len(prims)} primitives, not the sphere's one")
    (prim,) = prims
    attributes = prim["attributes"]
    if ("TANGENT" in attributes) != tangents:
        raise SystemExit(f"{path}: attributes {sorted(attributes)}, TANGENT {'missing' if tangents else 'present'}")
    mat = doc["materials"][prim["material"]]
    info = mat.get("normalTexture")
    if info is None:
        raise SystemExit(f"{path}: material {json.dumps(mat)} has no normalTexture")
    texture = doc["textures"][info["index"]]
    image = doc["images"][texture["source"]]
    sampler = doc["samplers"][texture["sampler"]] if "sampler" in texture else {}
    with open(os.path.join(folder, image.get("uri", "")), "rb") as f:
        same = f.read() == png_bytes
    if not same:
        raise SystemExit(f"{path}: the normalTexture's image {image} is not the pattern's PNG")
    lines = [f"{path}: attributes {', '.join(sorted(attributes))}; normalTexture {json.dumps(info)}, image"
             f" {image.get('uri')} (the pattern's bytes), sampler {json.dumps(sampler)};"
             f" camera {json.dumps(doc['cameras'][0])}"]
    if tangents:
        t = accessor(doc, folder, attributes["TANGENT"])
        x = accessor(doc, folder, attributes["POSITION"])[:, 0]
        w = t[:, 3]
        if not np.all(np.abs(np.abs(w) - 1.0) == 0.0):
            raise SystemExit(f"{path}: TANGENT w not all +-1: {np.unique(w)}")
        side = [(x < -1e-6, "x < 0"), (np.abs(x) <= 1e-6, "x = 0"), (x > 1e-6, "x > 0")]
        parts = ", ".join(f"{name}: {int(np.count_nonzero(s & (w < 0)))} / {int(np.count_nonzero(s & (w > 0)))}"
                          for s, name in side)
        lines.append(f"  TANGENT w: {int(np.count_nonzero(w < 0))} vertices -1, {int(np.count_nonzero(w > 0))} +1"
                     f" (of {len(w)}); by side, -1 / +1: {parts}; |xyz| {np.linalg.norm(t[:, :3], axis=1).min():.6f}"
                     f" .. {np.linalg.norm(t[:, :3], axis=1).max():.6f}")
    else:
        lines.append(f"  {doc['accessors'][attributes['POSITION']]['count']} vertices, no TANGENT")
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--segments", type=int, default=24, help="the sphere's segments around (a multiple of 4)")
    ap.add_argument("--rings", type=int, default=12, help="the sphere's rings from pole to pole")
    ap.add_argument("--tilt", type=float, default=35.0, help="the normal map's tilts, degrees")
    ap.add_argument("--texels", type=int, default=64, help="the normal map's size, texels square")
    ap.add_argument("--blocks", type=int, default=8, help="the normal map's blocks across")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    start = time.time()
    rgb = pattern(a.texels, a.blocks, a.tilt)
    with tempfile.TemporaryDirectory() as folder:
        source = os.path.join(folder, IMAGE_NAME + ".png")
        png_bytes = png(a.texels, a.texels, [[tuple(int(c) for c in px) for px in row] for row in rgb])
        with open(source, "wb") as f:
            f.write(png_bytes)
        signs = build(a, source)
    print(signs)
    print(f"built in {time.time() - start:.2f} s", flush=True)
    for name, tangents in (("tangents.gltf", True), ("no_tangents.gltf", False)):
        path = os.path.join(a.out, name)
        start = time.time()
        export(path, tangents)
        took = time.time() - start
        print("\n".join(check_export(path, tangents, png_bytes)))
        print(f"exported in {took:.2f} s", flush=True)


if __name__ == "__main__":
    main()
