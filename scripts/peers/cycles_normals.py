#!/usr/bin/env python3
"""Cycles' shading normals of a glTF scene, normal maps included, as an EXR in glTF's axes:
imports the file through Blender's own glTF importer (`pip install bpy`), renders it with
Cycles (CPU) from the file's camera with the view layer's Normal pass, and writes that pass.

    python3 cycles_normals.py SCENE.gltf --width 160 --height 120 --spp 16 --out normals.exr \\
        [--view 1] [--filter-width 0.01] [--compare OTHER.exr]

What the pass is: Cycles' world-space shading normal at the first hit, as its kernel writes it
(the average of the hit's BSDF closures' normals, weighted by the closures' weights, made unit
length), so it holds what the material's Normal input gives: for a glTF normalTexture, the
importer's Normal Map node (space Tangent, the primitive's TEXCOORD_n) over MikkTSpace tangents,
which Blender computes from the mesh's UVs and normals at render time; Blender's importer does
not read TANGENT (the render of a file without TANGENT is the same, see --compare). Two things
would make the pass differ from the Normal Map node's output, and are undone here:
- Cycles lifts a glossy closure's normal where its mirror reflection would point below the
  geometric surface (`ensure_valid_specular_reflection`, near the silhouette), and the pass
  averages that with the diffuse closure's normal: so each Principled BSDF's Normal input is
  moved to a Diffuse BSDF that replaces it at the Material Output (`--keep-materials`: not);
- the pass is a pixel's mean over its samples, which at a texel edge or the silhouette mixes
  normals (not unit length there): so the pixel filter is a Gaussian of --filter-width pixels
  (default 0.01, the smallest Cycles accepts: the samples sit within 0.005 px of the pixel's
  centre). Not a box: Blender's Cycles sync renders a box filter 1 px wide whatever the
  filter width says (`filter_width = (type == FILTER_BOX) ? 1.0f : filter_width`).
Also: no denoising, no adaptive sampling, max bounces 0 (the pass needs the first hit only),
a black world, the file's camera (the --view-th in depth-first node order, as smlt counts)
with its vertical field of view kept at --width x --height (sensor fit vertical).

How the pass is read (Blender 5.0): the render result's pixels are not readable from Python
(`Image("Render Result").pixels` is empty) and a multilayer EXR written by the render
(`write_still`) holds only Combined in 5.0, so a compositor node group
(`Scene.compositing_node_group`, 5.0's replacement of `Scene.node_tree`) links the Render
Layers node's Normal to a File Output node (a `file_output_items` entry of type VECTOR) that
writes a 32-bit multilayer EXR (channels Normal.X, .Y, .Z) into a temporary folder.

Axes and raster: Blender's importer turns glTF's Y-up into Blender's Z-up (x, y, z -> x, -z, y);
the pass is converted back, x_gltf = x_b, y_gltf = z_b, z_gltf = -y_b. The output is a float
RGB EXR (R, G, B = x, y, z), --width x --height, its first row the image's top (EXR's
increasing-y line order, as Blender writes its EXRs); pixels where the camera ray misses the
scene are (0, 0, 0). The script checks both against Blender's own ray casts
(`Scene.ray_cast`) through every pixel's centre: which pixels hit, and the angle between the
pass and the hit face's geometric normal, against the same for the image turned upside down
and mirrored left to right (a flipped raster shows as a larger angle there).

`--compare OTHER.exr` also prints the largest angle between this render's normals and
OTHER's (an EXR this script wrote) where both hit, and the pixels where only one hits.
"""

import argparse
import glob
import json
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_peer import named_cameras, use_view_camera  # noqa: E402


def read_exr(path, channels="RGB"):
    """The channels of a float EXR as (height, width, len(channels)) float64, top row first."""
    import Imath
    import OpenEXR

    f = OpenEXR.InputFile(path)
    dw = f.header()["dataWindow"]
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    pt = Imath.PixelType(Imath.PixelType.FLOAT)
    planes = [np.frombuffer(f.channel(c, pt), np.float32).reshape(h, w) for c in channels]
    return np.stack(planes, -1).astype(np.float64)


def write_exr(path, rgb):
    """(height, width, 3) as a 32-bit float RGB EXR, the first row the image's top."""
    import Imath
    import OpenEXR

    h, w = rgb.shape[:2]
    header = OpenEXR.Header(w, h)
    header["channels"] = {c: Imath.Channel(Imath.PixelType(Imath.PixelType.FLOAT)) for c in "RGB"}
    out = OpenEXR.OutputFile(path, header)
    out.writePixels({c: np.ascontiguousarray(rgb[..., i], dtype=np.float32).tobytes() for i, c in enumerate("RGB")})
    out.close()


def to_gltf(v):
    """Blender's Z-up axes to glTF's Y-up: (x, y, z) -> (x, z, -y), on the last axis."""
    return np.stack([v[..., 0], v[..., 2], -v[..., 1]], -1)


def angles(a, b):
    """Degrees between vectors a and b, on the last axis (atan2, exact near 0 as well)."""
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), (a * b).sum(-1)))


def diffuse_only(bpy):
    """Each Principled BSDF's Normal input moved to a Diffuse BSDF (its base colour) that takes
    its place at the material's output; returns what it changed."""
    notes = []
    for mat in bpy.data.materials:
        nt = mat.node_tree
        if nt is None:
            continue
        for node in list(nt.nodes):
            if node.type != "BSDF_PRINCIPLED":
                continue
            diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
            diffuse.inputs["Color"].default_value = node.inputs["Base Color"].default_value
            for link in node.inputs["Normal"].links:
                nt.links.new(link.from_socket, diffuse.inputs["Normal"])
            for link in list(node.outputs["BSDF"].links):
                to = link.to_socket
                nt.links.remove(link)
                nt.links.new(diffuse.outputs["BSDF"], to)
            normal = node.inputs["Normal"].links[0].from_node.type if node.inputs["Normal"].links else "none"
            notes.append(f"{mat.name}: Principled BSDF -> Diffuse BSDF, Normal from {normal}")
    return notes


def setup(a, folder):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    try:
        with open(a.scene) as f:
            doc = json.load(f)
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise SystemExit(f"{a.scene}: not a readable .gltf (JSON) file: {e}")
    bpy.ops.import_scene.gltf(filepath=named_cameras(doc, a.scene, folder))
    scene = bpy.context.scene
    cam = use_view_camera(doc, scene, a.view)
    notes = [] if a.keep_materials else diffuse_only(bpy)
    for mat in bpy.data.materials:
        for node in (mat.node_tree.nodes if mat.node_tree else []):
            if node.type == "NORMAL_MAP":
                notes.append(f"{mat.name}: Normal Map space {node.space}, UV map {node.uv_map!r},"
                             f" strength {node.inputs['Strength'].default_value:g}")
            if node.type == "TEX_IMAGE" and node.image is not None:
                notes.append(f"{mat.name}: image {node.image.name} {tuple(node.image.size)},"
                             f" {node.image.colorspace_settings.name}, {node.interpolation}")
    world = bpy.data.worlds.new("black")
    if world.node_tree is None:  # Blender < 5.0 (5.0 makes the nodes; use_nodes is deprecated)
        world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world

    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = a.spp
    c.seed = 0
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = 0
    c.pixel_filter_type = "GAUSSIAN"  # Cycles makes a box 1 px wide whatever filter_width says
    c.filter_width = a.filter_width
    if abs(c.filter_width - a.filter_width) > 1e-6:
        raise SystemExit(f"--filter-width {a.filter_width}: Cycles took {c.filter_width}")
    scene.render.resolution_x, scene.render.resolution_y = a.width, a.height
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    scene.render.film_transparent = True
    scene.view_settings.view_transform = "Standard"
    layer = scene.view_layers[0]
    layer.use_pass_normal = True

    tree = bpy.data.node_groups.new("normal pass", "CompositorNodeTree")
    scene.compositing_node_group = tree
    scene.render.use_compositing = True
    layers = tree.nodes.new("CompositorNodeRLayers")
    layers.layer = layer.name
    out = tree.nodes.new("CompositorNodeOutputFile")
    out.format.media_type = "MULTI_LAYER_IMAGE"
    out.format.color_depth = "32"
    out.format.exr_codec = "ZIP"
    out.file_output_items.new("VECTOR", "Normal")
    tree.links.new(layers.outputs["Normal"], out.inputs["Normal"])
    out.directory = os.path.join(folder, "pass") + os.sep
    out.file_name = "normal"
    # The render's own image (Combined), which nothing reads; PNG keeps it small.
    scene.render.filepath = os.path.join(folder, "combined.png")
    scene.render.image_settings.file_format = "PNG"
    return bpy, scene, cam, notes


def camera_rays(scene, cam, width, height):
    """World-space origins and unit directions (height, width, 3) of the rays through the pixels'
    centres, the first row the image's top (Blender's axes)."""
    mw = cam.matrix_world
    tr, br, bl, tl = [np.array(v) for v in cam.data.view_frame(scene=scene)]
    fx = (np.arange(width) + 0.5) / width
    fy = (np.arange(height) + 0.5) / height
    local = (tl[None, None, :] + fx[None, :, None] * (tr - tl)[None, None, :]
             + fy[:, None, None] * (bl - tl)[None, None, :])
    rot = np.array(mw.to_3x3())
    d = local @ rot.T
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    return np.array(mw.translation), d


def ray_casts(bpy, scene, origin, dirs):
    """Blender's own closest hits: (hit mask, geometric normals) per pixel, Blender's axes."""
    from mathutils import Vector

    depsgraph = bpy.context.evaluated_depsgraph_get()
    h, w = dirs.shape[:2]
    hit = np.zeros((h, w), bool)
    ng = np.zeros((h, w, 3))
    o = Vector(origin)
    for j in range(h):
        for i in range(w):
            result, _, normal, _, _, _ = scene.ray_cast(depsgraph, o, Vector(dirs[j, i]))
            if result:
                hit[j, i] = True
                ng[j, i] = normal
    return hit, ng


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--view", type=int, default=1)
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=120)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--filter-width", type=float, default=0.01, help="Gaussian pixel filter, pixels (Cycles: >= 0.01)")
    ap.add_argument("--keep-materials", action="store_true", help="render the importer's materials as they are")
    ap.add_argument("--compare", default=None, help="an EXR this script wrote: the largest angle to it")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        start = time.time()
        bpy, scene, cam, notes = setup(a, folder)
        print("\n".join(notes))
        print(f"imported and set up in {time.time() - start:.2f} s (Blender {bpy.app.version_string})", flush=True)
        start = time.time()
        bpy.ops.render.render(write_still=True)
        took = time.time() - start
        written = sorted(glob.glob(os.path.join(folder, "pass", "*.exr")))
        if len(written) != 1:
            raise SystemExit(f"the File Output node wrote {written}, not one EXR")
        normals = to_gltf(read_exr(written[0], ("Normal.X", "Normal.Y", "Normal.Z")))
    print(f"rendered {a.width}x{a.height} at {a.spp} spp in {took:.2f} s", flush=True)
    write_exr(a.out, normals)

    length = np.linalg.norm(normals, axis=-1)
    background = length == 0.0
    on = ~background
    print(f"{a.out}: {int(background.sum())} background pixels (0, 0, 0), {int(on.sum())} on the scene;"
          f" |n| there {length[on].min():.6f} .. {length[on].max():.6f},"
          f" {int(np.count_nonzero(np.abs(length[on] - 1.0) > 1e-3))} pixels off unit length by > 1e-3")
    h, w = a.height, a.width
    for j in (h // 2 - 1, h // 2):  # the four pixels about the image's centre (its middle with even sizes)
        for i in (w // 2 - 1, w // 2):
            n = normals[j, i]
            print(f"  pixel row {j}, column {i} (its centre {i + 0.5}, {j + 0.5} px from the top left):"
                  f" n = ({n[0]:+.6f}, {n[1]:+.6f}, {n[2]:+.6f}), glTF axes")

    start = time.time()
    origin, dirs = camera_rays(scene, cam, w, h)
    hit, ng = ray_casts(bpy, scene, origin, dirs)
    ng = to_gltf(ng)
    both = hit & on
    print(f"  Blender's ray casts through the pixel centres ({time.time() - start:.2f} s): {int(hit.sum())} hit;"
          f" {int((hit & background).sum())} hit where the pass is background,"
          f" {int((~hit & on).sum())} miss where it is not")
    unit = normals / np.where(length > 0, length, 1.0)[..., None]
    for label, flip in (("as written", lambda x: x), ("upside down", lambda x: x[::-1]),
                        ("mirrored", lambda x: x[:, ::-1])):
        f_unit, f_on = flip(unit), flip(on)
        sel = hit & f_on
        t = angles(f_unit[sel], ng[sel])
        print(f"  pass vs the hit face's geometric normal, {label}: {int(sel.sum())} pixels, angle mean"
              f" {t.mean():.2f}, median {np.median(t):.2f}, max {t.max():.2f} deg;"
              f" hit masks differ at {int(np.count_nonzero(hit != f_on))} pixels")
    if not both.any():
        raise SystemExit("no pixel where both the pass and the ray casts hit")

    if a.compare:
        other = read_exr(a.compare)
        if other.shape != normals.shape:
            raise SystemExit(f"{a.compare}: {other.shape[1]}x{other.shape[0]}, not {w}x{h}")
        o_len = np.linalg.norm(other, axis=-1)
        sel = on & (o_len > 0)
        t = angles(unit[sel], other[sel] / o_len[sel, None])
        worst = tuple(int(v) for v in np.argwhere(sel)[int(np.argmax(t))])
        where = f" (at row, column {worst})" if t.max() > 0 else ""
        print(f"  against {a.compare}: max angle {t.max():.6f} deg{where},"
              f" mean {t.mean():.6f} deg over {int(sel.sum())} pixels; largest |difference| of components"
              f" {np.abs(normals - other).max():.3e}; background in only one:"
              f" {int(np.count_nonzero(on != (o_len > 0)))} pixels")


if __name__ == "__main__":
    main()
