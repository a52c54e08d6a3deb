#!/usr/bin/env python3
"""Blender's Cycles (CPU path tracer) as a peer of smlt's bench: imports one of smlt's glTF scene
views through Blender's own glTF importer (`pip install bpy`), renders it at equal wall time in
chunks of samples with different seeds, accumulated, and measures it against smlt's reference
with smlt's error definitions (`peer_common.py`), writing rows in the format of the bench's
results.csv (method `cycles-path`; candidates = paths traced = samples x pixels).

    python3 cycles_peer.py SCENE.gltf --view 1 --width 128 --height 96 --max-depth 12 \\
        --seconds 8 --repeats 3 --reference reference.exr --label caustic --out peers.csv

`--converged SPP` renders once with that many samples instead and prints how its image
compares with the reference (the mean, and the error of the image and of its mirror image, to
catch a flipped raster or a turned sky) - a peer's numbers count only after this agrees.

Timing: the wall time of each `bpy.ops.render.render` call counts, which renders `--chunk`
samples per pixel with its own seed; the import, the material changes, one untimed warm-up
render and reading each chunk's EXR back do not. Each call includes Cycles' sync of the scene
and BVH build and writing the chunk's small EXR (about 20 ms a call on `caustic` at 128x96
against about 12 ms a sample there; 32 samples a chunk keep that near 5 %): Blender 5.0.1's
persistent data (`use_persistent_data`), which would keep the synced scene, rendered every
later call's image the same as the first's here, whatever its samples or seed, so it is off.

What is set after the import, so that Cycles renders what smlt renders:
- point and spot lamps radius 0, sun angle 0 (true punctual lights, as glTF's; Blender's
  importer gives point and spot radius 0 already, the sun 0.526 deg); Blender's importer
  converts candela and lux with PBR_WATTS_TO_LUMENS = 683 as smlt reads them;
- Lambert surfaces (transmission 0, metallicFactor 0 and KHR_materials_specular specularFactor
  0, as smlt's generated scenes write them): the importer's Principled BSDF with Specular IOR
  Level 0 and roughness 1, Lambertian in Cycles as in smlt; any other opaque material keeps the
  importer's Principled BSDF with single-scattering GGX (glTF's; the importer makes
  multiscatter), which is Cycles' model, not glTF's BRDF (said in the notes); a material with
  smlt's Phong lobe (`extras.smlt_phong_exponent`, the generated banners) is refused: the
  importer reads it as Lambert and Cycles has no Phong closure; so is a rough thin wall of
  glass (roughness² ≥ 1e-3 without KHR_materials_volume), which passes smlt's reflection lobe
  mirrored through the plane, a closure Cycles lacks; and so is a sheen (KHR_materials_sheen),
  which the importer makes Cycles' own microfibre sheen, another model;
- emission one-sided, as smlt's emissive triangles (Cycles' emission is two-sided): the
  strength times (1 - Backfacing);
- solid glass (KHR_materials_volume thicknessFactor > 0): the importer's Principled BSDF with
  Transmission Weight 1 (baseColor tints the refraction, the reflection is white, as in glTF),
  distribution GGX (single scattering, as smlt's; Principled's default is multiscatter GGX);
  the importer's Volume Absorption gets Cycles' sigma = density (1 - colour) equal to glTF's
  sigma = -ln(attenuationColor) / attenuationDistance (the importer sets colour =
  attenuationColor, density = 1 / distance, which is not glTF's Beer-Lambert law);
- smooth thin-walled glass (no volume): Cycles has none, so a Mix of Transparent BSDF (the tint)
  and a sharp Glossy BSDF by the Fresnel factor of one interface of the glTF ior from either
  side (the Fresnel node's IOR input is swapped on back faces, where Cycles uses 1 / IOR),
  straight through as glTF's thin wall. A Transparent BSDF lets Cycles' shadow rays through,
  so Cycles lights the floor through the pane by next-event estimation where smlt's path
  tracer (a shadow ray stops at smooth glass) finds that light only by BSDF sampling;
- black world, or `--environment FILE --environment-strength S --environment-rotation DEG` as
  smlt's: an Environment Texture of the same file (Closest interpolation: smlt looks texels
  up at the nearest; its importance map at the image's width, see `environment`),
  Background strength S, turned so that smlt's orientation holds (smlt,
  as Mitsuba's `envmap`: the image's centre column looks along glTF +Z, its first quarter
  along +X; Blender's importer turns glTF's Y-up into Z-up, x, y, z -> x, -z, y; Cycles'
  equirectangular centre column looks along its +X, its first quarter along +Y; so the
  Mapping node turns the lookup direction by 90 - DEG deg about Blender's Z, which is glTF's
  +Y); a constant colour -> the Background colour;
- box pixel filter of 1 px (smlt's pixels are box averages), no denoising, no clamping, no
  adaptive sampling, Filter Glossy 0, light threshold 0, caustics on, max bounces k - 1 for
  smlt's --max-depth k (pbrt's maxdepth: 1 is direct light only, which is Cycles' max_bounces
  0; with max_bounces k Cycles rendered `slit` 1.56 % brighter than smlt's reference at 2048 spp,
  with k - 1 -0.09 %), every kind's bounces k - 1; transparent bounces k (smlt counts a pass
  through a thin wall as a bounce, Cycles does not count transparent ones towards max_bounces);
- the camera: the importer's, the view-th camera in depth-first node order (smlt's), its
  vertical field of view kept at any aspect ratio (sensor fit vertical), rendered at
  --width x --height; the EXR is linear (view transform Standard).
"""

import json
import math
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peer_common import append_rows, arguments, equal_time_rows, errors  # noqa: E402


def camera_node_names(doc):
    """Names of the camera nodes in depth-first scene order (smlt's view numbering)."""
    names = []
    root = doc["scenes"][doc.get("scene", 0)]
    stack = list(reversed(root["nodes"]))
    while stack:
        i = stack.pop()
        node = doc["nodes"][i]
        if "camera" in node:
            names.append((node.get("name"), node["camera"]))
        stack.extend(reversed(node.get("children", [])))
    return names


def thin_glass(nt, principled, ior):
    """glTF's thin wall in Cycles: Fresnel(ior) of one interface from either side mixes a sharp
    white Glossy (reflection) over a Transparent of the tint (straight through)."""
    nodes, links = nt.nodes, nt.links
    geometry = nodes.new("ShaderNodeNewGeometry")
    swap = nodes.new("ShaderNodeMath")  # ior on front faces, 1 / ior on back faces
    swap.operation = "MULTIPLY_ADD"
    links.new(geometry.outputs["Backfacing"], swap.inputs[0])
    swap.inputs[1].default_value = 1.0 / ior - ior
    swap.inputs[2].default_value = ior
    fresnel = nodes.new("ShaderNodeFresnel")
    links.new(swap.outputs[0], fresnel.inputs["IOR"])
    transparent = nodes.new("ShaderNodeBsdfTransparent")
    transparent.inputs["Color"].default_value = principled.inputs["Base Color"].default_value
    glossy = nodes.new("ShaderNodeBsdfGlossy")
    glossy.distribution = "GGX"
    glossy.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    glossy.inputs["Roughness"].default_value = 0.0
    mix = nodes.new("ShaderNodeMixShader")
    links.new(fresnel.outputs[0], mix.inputs["Fac"])
    links.new(transparent.outputs[0], mix.inputs[1])
    links.new(glossy.outputs[0], mix.inputs[2])
    return mix


def fix_materials(bpy, doc, notes):
    """Makes the importer's materials smlt's (see the docstring)."""
    by_name = {m.get("name"): m for m in doc.get("materials", [])}
    for mat in bpy.data.materials:
        if mat.node_tree is None or mat.name not in by_name:
            continue
        spec = by_name[mat.name]
        ext = spec.get("extensions", {})
        nt = mat.node_tree
        principled = next((n for n in nt.nodes if n.type == "BSDF_PRINCIPLED"), None)
        out = next((n for n in nt.nodes if n.type == "OUTPUT_MATERIAL"), None)
        if principled is None or out is None:
            raise SystemExit(f"material {mat.name}: the importer made no Principled BSDF")
        if "smlt_phong_exponent" in spec.get("extras", {}):
            # smlt's generated scenes' Phong lobe (the banners): Blender's importer reads it as
            # Lambert and Cycles has no Phong closure, so the render would be another scene.
            raise SystemExit(f"material {mat.name!r}: smlt's Phong lobe (extras.smlt_phong_exponent), which"
                             " Cycles cannot render")
        t = float(ext.get("KHR_materials_transmission", {}).get("transmissionFactor", 0.0))
        ior = float(ext.get("KHR_materials_ior", {}).get("ior", 1.5))
        volume = ext.get("KHR_materials_volume")
        thin = volume is None or volume.get("thicknessFactor", 0.0) <= 0
        roughness = float(spec.get("pbrMetallicRoughness", {}).get("roughnessFactor", 1.0))
        if t > 0 and thin and roughness ** 2 >= 1e-3:
            # smlt's rough thin wall passes its reflection lobe mirrored through the plane (the
            # extension's thin-walled BTDF); Cycles has no such closure.
            raise SystemExit(f"material {mat.name!r}: a rough thin wall of glass (roughness {roughness:g}),"
                             " which Cycles cannot render")
        if max(ext.get("KHR_materials_sheen", {}).get("sheenColorFactor", [0, 0, 0])) > 0:
            # The importer makes Cycles' Principled sheen of it, a microfibre model of its own,
            # not the extension's Charlie lobe with albedo scaling.
            raise SystemExit(f"material {mat.name!r}: KHR_materials_sheen, whose lobe Cycles does not have")
        if principled.inputs["Emission Strength"].default_value > 0 and max(spec.get("emissiveFactor", [0, 0, 0])) > 0:
            geometry = nt.nodes.new("ShaderNodeNewGeometry")
            front = nt.nodes.new("ShaderNodeMath")  # strength x (1 - backfacing)
            front.operation = "MULTIPLY_ADD"
            strength = principled.inputs["Emission Strength"].default_value
            links_in = principled.inputs["Emission Strength"].links
            if links_in:
                raise SystemExit(f"material {mat.name}: emission strength is linked")
            nt.links.new(geometry.outputs["Backfacing"], front.inputs[0])
            front.inputs[1].default_value = -strength
            front.inputs[2].default_value = strength
            nt.links.new(front.outputs[0], principled.inputs["Emission Strength"])
            notes.append(f"{mat.name}: emission one-sided (strength {strength:g})")
        pbr = spec.get("pbrMetallicRoughness", {})
        lambert = (float(ext.get("KHR_materials_specular", {}).get("specularFactor", 1.0)) == 0.0
                   and float(pbr.get("metallicFactor", 1.0)) == 0.0)
        if t == 0 and not lambert:
            principled.distribution = "GGX"
            notes.append(f"{mat.name}: not Lambertian in glTF: the importer's Principled BSDF kept"
                         " with single-scattering GGX (Cycles' model, not glTF's BRDF)")
            continue
        if t == 0:
            principled.inputs["Specular IOR Level"].default_value = 0.0
            principled.inputs["Roughness"].default_value = 1.0
            principled.inputs["Metallic"].default_value = 0.0
            notes.append(f"{mat.name}: Lambert (Principled, Specular IOR Level 0, roughness 1)")
            continue
        principled.distribution = "GGX"
        if thin:
            glass = thin_glass(nt, principled, ior)
            shader = glass
            notes.append(f"{mat.name}: thin wall, Mix(Fresnel {ior:g}) of Transparent and sharp Glossy")
        else:
            principled.inputs["Transmission Weight"].default_value = 1.0
            shader = principled
            notes.append(f"{mat.name}: solid glass, Principled transmission 1, ior {principled.inputs['IOR'].default_value:g},"
                         f" roughness {principled.inputs['Roughness'].default_value:g}, GGX")
            absorb = next((n for n in nt.nodes if n.type == "VOLUME_ABSORPTION"), None)
            d = volume.get("attenuationDistance", math.inf)
            if absorb is not None and math.isfinite(d):
                sigma = [-math.log(max(c, 1e-30)) / d for c in volume.get("attenuationColor", [1, 1, 1])]
                density = max(sigma)
                absorb.inputs["Density"].default_value = density
                absorb.inputs["Color"].default_value = (*[1 - s / density for s in sigma], 1.0)
                notes.append(f"{mat.name}: absorption sigma {', '.join(f'{s:.4f}' for s in sigma)} per unit")
        if t < 1:
            diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
            diffuse.inputs["Color"].default_value = principled.inputs["Base Color"].default_value
            mix = nt.nodes.new("ShaderNodeMixShader")
            mix.inputs["Fac"].default_value = t
            nt.links.new(diffuse.outputs[0], mix.inputs[1])
            nt.links.new(shader.outputs[0], mix.inputs[2])
            shader = mix
        nt.links.new(shader.outputs[0], out.inputs["Surface"])


def environment(bpy, scene, source, strength, rotation):
    world = bpy.data.worlds.new("smlt")
    world.use_nodes = True
    nt = world.node_tree
    background = nt.nodes["Background"]
    background.inputs["Strength"].default_value = strength if source else 0.0
    if source:
        try:
            values = [float(v) for v in source.split(",")]
        except ValueError:
            values = None
        if values is not None:
            rgb = values * 3 if len(values) == 1 else values
            background.inputs["Color"].default_value = (*rgb, 1.0)
        else:
            tex = nt.nodes.new("ShaderNodeTexEnvironment")
            tex.image = bpy.data.images.load(os.path.abspath(source))
            tex.interpolation = "Closest"
            # The importance map at the image's own width (smlt samples texel by texel). The
            # default, automatic at 1024, is rebuilt in every render call and cost 0.9 s a call
            # on the showcase's 512x256 sky (32 samples: 0.46 s).
            world.cycles.sampling_method = "MANUAL"
            world.cycles.sample_map_resolution = tex.image.size[0]
            coords = nt.nodes.new("ShaderNodeTexCoord")
            mapping = nt.nodes.new("ShaderNodeMapping")
            mapping.vector_type = "POINT"
            mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(90.0 - rotation))
            nt.links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
            nt.links.new(mapping.outputs[0], tex.inputs["Vector"])
            nt.links.new(tex.outputs["Color"], background.inputs["Color"])
    scene.world = world


def named_cameras(doc, path, folder):
    """The glTF to import: `path` itself, or where a camera node has no name (smlt's generated
    scenes write none; Blender's importer then names the object after the camera, "Camera",
    "Camera.001", which no longer says which node it was) a copy in `folder` with each such node
    named "smlt camera node I" (I its node index) and its relative URIs made absolute. `doc` gets the same names."""
    unnamed = [i for i, node in enumerate(doc["nodes"]) if "camera" in node and not node.get("name")]
    if not unnamed:
        return path
    for i in unnamed:
        doc["nodes"][i]["name"] = f"smlt camera node {i}"
    base = os.path.dirname(os.path.abspath(path))
    for item in doc.get("buffers", []) + doc.get("images", []):
        uri = item.get("uri")
        if uri and not uri.startswith("data:"):
            item["uri"] = os.path.join(base, uri)
    copy = os.path.join(folder, "named_cameras.gltf")
    with open(copy, "w") as f:
        json.dump(doc, f)
    return copy


def use_view_camera(doc, scene, view):
    """Makes the imported camera of the glTF's `view`-th camera node (1, 2, ... in depth-first
    node order, as smlt counts views) the scene's, its vertical field of view the file's (sensor
    fit vertical, so that any render size keeps it); returns it."""
    names = camera_node_names(doc)
    if not 1 <= view <= len(names):
        raise SystemExit(f"view {view}: the scene has {len(names)} cameras")
    name, index = names[view - 1]
    imported = [o for o in scene.objects if o.type == "CAMERA"]
    cams = [o for o in imported if o.name == name] if name else imported if len(names) == 1 else []
    if len(cams) != 1:
        raise SystemExit(f"view {view}: no single imported camera for glTF camera node {name!r}")
    cam = cams[0]
    cam.data.lens_unit = "FOV"
    cam.data.sensor_fit = "VERTICAL"
    cam.data.angle = doc["cameras"][index]["perspective"]["yfov"]
    scene.camera = cam
    return cam


def setup(a):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    try:
        with open(a.scene) as f:
            doc = json.load(f)
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise SystemExit(f"{a.scene}: not a readable .gltf (JSON) file: {e}")
    with tempfile.TemporaryDirectory() as folder:
        bpy.ops.import_scene.gltf(filepath=named_cameras(doc, a.scene, folder))
    scene = bpy.context.scene
    notes = []
    for obj in scene.objects:
        if obj.type == "LIGHT":
            light = obj.data
            if light.type in ("POINT", "SPOT"):
                light.shadow_soft_size = 0.0
            if light.type == "SUN":
                light.angle = 0.0
            notes.append(f"{obj.name}: {light.type} {light.energy:.4f}, radius/angle 0")
    use_view_camera(doc, scene, a.view)
    fix_materials(bpy, doc, notes)
    environment(bpy, scene, a.environment, a.environment_strength, a.environment_rotation)
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.use_adaptive_sampling = False
    c.use_denoising = False
    # Cycles' max_bounces 0 is direct light only, pbrt's (and smlt's) max depth 1: one less.
    k = a.max_depth
    if k < 1:
        raise SystemExit(f"--max-depth {k}: Cycles renders at least direct light (max depth 1)")
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = k - 1
    c.transparent_max_bounces = k
    c.volume_bounces = 0
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = c.caustics_refractive = True
    c.light_sampling_threshold = 0.0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.use_animated_seed = False
    scene.render.use_persistent_data = False  # on, every later render repeats the first's image (see above)
    scene.render.resolution_x, scene.render.resolution_y = a.width, a.height
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.exr_codec = "NONE"
    return bpy, scene, notes


def read_exr(path):
    import Imath
    import OpenEXR

    f = OpenEXR.InputFile(path)
    dw = f.header()["dataWindow"]
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    return np.stack([np.frombuffer(f.channel(c, Imath.PixelType(Imath.PixelType.FLOAT)), np.float32).reshape(h, w)
                     for c in "RGB"], -1).astype(np.float64)


def main():
    ap = arguments(__doc__)
    ap.add_argument("--chunk", type=int, default=32, help="samples per pixel per render call")
    ap.add_argument("--converged", type=int, default=0, help="check: render SPP samples once and compare")
    ap.add_argument("--save", default=None, help="with --converged: keep the image as this EXR")
    ap.add_argument("--environment", default=None, help="as smlt's: FILE.exr|.hdr or R,G,B")
    ap.add_argument("--environment-strength", type=float, default=1.0)
    ap.add_argument("--environment-rotation", type=float, default=0.0, help="degrees about +Y")
    a = ap.parse_args()
    label = a.label or os.path.splitext(os.path.basename(a.scene))[0]
    reference = read_exr(a.reference)
    if reference.shape[:2] != (a.height, a.width):
        raise SystemExit(f"the reference is {reference.shape[1]}x{reference.shape[0]}, not {a.width}x{a.height}")
    bpy, scene, notes = setup(a)
    print("; ".join(notes), flush=True)
    with tempfile.TemporaryDirectory() as folder:
        exr = os.path.join(folder, "chunk.exr")
        scene.render.filepath = exr

        def render(spp, seed):
            scene.cycles.samples = spp
            scene.cycles.seed = seed
            start = time.time()
            bpy.ops.render.render(write_still=True)
            took = time.time() - start
            return read_exr(exr), took

        render(1, 999_999)  # untimed warm-up
        if a.converged:
            img, took = render(a.converged, 1)
            mean_i, mean_r = img.mean(), reference.mean()
            flipped = errors(img[:, ::-1], reference)[0]
            print(f"{label} v{a.view}: {a.converged} spp in {took:.1f} s with Cycles {bpy.app.version_string}; mean"
                  f" {mean_i:.5f} against the reference's {mean_r:.5f} ({100 * (mean_i / mean_r - 1):+.2f} %);"
                  f" RMSE {errors(img, reference)[0]:.5f}, mirrored {flipped:.5f}")
            if a.save:
                import shutil

                shutil.copyfile(exr, a.save)
            return
        rows = equal_time_rows(render, a.chunk, a.seconds, a.repeats, reference, label, a.view, "cycles-path")
    append_rows(a.out, rows)


if __name__ == "__main__":
    main()
