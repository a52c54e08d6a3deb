#!/usr/bin/env python3
"""Mitsuba 3's path tracer as a peer of smlt's bench: converts one of smlt's glTF scene views
(`gltf_scene.py`), renders it at equal wall time in chunks of samples, and measures it against
smlt's reference with smlt's error definitions (RMSE on linear radiance; relMSE with 0.01 in the
denominator; PSNR with peak 1 on clamped values), writing rows in the format of the bench's
results.csv (method `mitsuba-path`; candidates = paths traced).

    python3 mitsuba_peer.py SCENE.gltf --view 1 --width 128 --height 72 --max-depth 10 \\
        --seconds 8 --repeats 3 --reference reference_scene_v1.exr --label scene --out peers.csv

`--converged SPP` renders once with that many samples instead and prints how its image
compares with the reference (the mean, and the error of the image and of its mirror image, to
catch a flipped or shifted raster) - a peer's numbers count only after this agrees.

Conversion: Lambert (glTF's BRDF with no metal and specularFactor 0) -> `diffuse` inside `twosided` (smlt's surfaces scatter on both sides;
`diffuse` alone is black from behind, which left the sunblind view, lit through the backs of its
slats, 99.6 % dark); emitters -> one-sided `area` lights of the same radiance; smlt's normalised
Phong lobe (any exponent > 0) -> `smlt_phong`, a Python BSDF plugin with smlt's own lobe,
sampling and two-sided semantics (`mitsuba_phong.py`, checked by `check_phong.py`); smlt's max
depth k (bounces, pbrt's maxdepth) -> Mitsuba's max_depth k + 1; box pixel filter (smlt's pixels
are box averages); KHR_lights_punctual -> `point`, `spot` (see `light_dict`) and `directional`
of the same radiometric values; glass (KHR_materials_transmission) -> `dielectric` (a solid:
`roughdielectric` with `ggx` of the same alpha where it is rough;
KHR_materials_volume, with a `homogeneous` purely absorbing interior medium and `volpath` where
it attenuates) or `thindielectric` (thin-walled: Mitsuba sums the slab's inter-reflections,
reflecting 2R/(1+R) where glTF's single interface reflects R; a rough thin wall -> `smlt_thin`,
a Python BSDF plugin written from the extension, `mitsuba_thin.py`), tinted by baseColor, blended
with the BRDF rest by `blendbsdf` where transmissionFactor < 1; KHR_materials_sheen -> `smlt_sheen`
over the whole BSDF (`mitsuba_sheen.py`, written from the extension's notes);
KHR_materials_clearcoat -> `smlt_coat` over that (`mitsuba_coat.py`, written from the extension); glTF's metallic-roughness BRDF
otherwise -> `smlt_gltf`, a Python BSDF plugin written from the spec (`mitsuba_gltf.py`: Mitsuba
has no glTF BRDF; `principled` is Disney's, see check_materials.sh); `--environment` as smlt's
-> `envmap` or `constant` (`environment_dict`); textures (baseColorTexture on Lambert, emissiveTexture
on an emitter) -> `bitmap` (`texture_dict`: Mitsuba's uv (0, 0) is the image's top-left as glTF's,
its `ply` reads u, v unflipped; its texel centres, sRGB decoding, NEAREST and bilinear filters
are glTF's; its one wrap mode for both axes is met by tiling the image where glTF's two differ;
an emitter's texture coordinates become its mesh's own, see `mesh_textures`);
smooth shading normals (glTF's NORMAL, world space from gltf_scene.py) -> the PLY's vertex normals
`nx`, `ny`, `nz`, loaded with `face_normals` false so that Mitsuba interpolates them as the
shading frame (a mesh without them keeps `face_normals` true: Mitsuba would otherwise make vertex
normals of its own); Mitsuba's BSDFs then see the shading frame alone, where smlt's give 0 to a
direction on which the geometric and the shading normal disagree (no light leaks), so the two
differ a little near a coarse mesh's silhouettes and terminator (check_normals.sh);
`--texture-rotation` reads KHR_texture_transform's rotation as smlt and the implementations
("example", the default) or as the extension's GLSL listing ("listing"; see gltf_scene.py).
Variants: `llvm_ad_rgb` when Mitsuba finds a libLLVM (set DRJIT_LIBLLVM_PATH; Debian's
libllvm19 unpacked with dpkg-deb -x works), else `scalar_rgb`."""

import dataclasses
import math
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gltf_scene  # noqa: E402
from peer_common import append_rows, arguments, equal_time_rows, errors, write_ply  # noqa: E402


WRAP = {gltf_scene.REPEAT: "repeat", gltf_scene.CLAMP_TO_EDGE: "clamp", gltf_scene.MIRRORED_REPEAT: "mirror"}


def decode(mi, tex, folder, srgb=True):
    """The texture's image as Mitsuba decodes it: (h, w, 3) linear float32, sRGB decoded by
    Mitsuba's Bitmap (what `bitmap` does with raw false) for a colour texture."""
    ext = ".jpg" if "jpeg" in tex.mime or tex.image[:2] == b"\xff\xd8" else ".png"
    path = os.path.join(folder, f"image{abs(hash(tex.image))}{ext}")
    with open(path, "wb") as f:
        f.write(tex.image)
    bitmap = mi.Bitmap(path)
    if not srgb:
        bitmap.set_srgb_gamma(False)
    return np.array(bitmap.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False))


def bake(texels, tex, coords):
    """(texels, Mitsuba wrap mode, 3 x 3 map of glTF's lookup coordinates to the baked image's):
    Mitsuba's `bitmap` has one wrap mode for both axes (and wants 2 x 2 texels at least), so an
    axis whose glTF mode differs is tiled into the image, exactly (texel for texel, the bilinear
    neighbours across each seam included): REPEAT + MIRRORED_REPEAT -> `repeat` over the image
    and its mirror image (period 2); CLAMP_TO_EDGE + another -> `clamp` over the periods that
    `coords` (the lookup coordinates at the mesh's vertices: an affine map's extremes) reach, one
    spare period each side. An image one texel wide or high is doubled along that axis (the
    same under every mode)."""
    modes = [tex.wrap_s, tex.wrap_t]  # u: the image's columns (numpy axis 1), v: its rows (axis 0)
    a = np.eye(3)
    mode = modes[0]
    if modes[0] != modes[1]:
        clamp = gltf_scene.CLAMP_TO_EDGE
        # the axis tiled: the one that is not CLAMP_TO_EDGE, or else the MIRRORED_REPEAT one
        tiled = modes[0] != clamp if clamp in modes else modes[0] == gltf_scene.MIRRORED_REPEAT
        axis = 0 if tiled else 1
        np_axis = 1 - axis
        mirrored = np.flip(texels, axis=np_axis)
        if clamp in modes:
            mode = clamp
            lo = math.floor(coords[:, axis].min()) - 1
            hi = math.floor(coords[:, axis].max()) + 2
            if hi - lo > 64:
                raise SystemExit(f"a texture's coordinates span {hi - lo} periods: too many to tile")
            mirror = modes[axis] == gltf_scene.MIRRORED_REPEAT
            texels = np.concatenate([mirrored if mirror and k % 2 else texels for k in range(lo, hi)], axis=np_axis)
            a[axis] = 0.0
            a[axis, axis] = 1.0 / (hi - lo)
            a[axis, 2] = -lo / (hi - lo)
        else:  # REPEAT on one axis, MIRRORED_REPEAT on `axis`
            mode = gltf_scene.REPEAT
            texels = np.concatenate([texels, mirrored], axis=np_axis)
            a[axis, axis] = 0.5
    for np_axis in (0, 1):
        if texels.shape[np_axis] == 1:
            texels = np.repeat(texels, 2, axis=np_axis)
    return np.ascontiguousarray(texels, dtype=np.float32), WRAP[mode], a


def texture_dict(mi, tex, factor, uv, folder, srgb=True, mesh=np.eye(3), texels=None):
    """glTF texture `tex` times `factor` as Mitsuba's `bitmap`, for a mesh with glTF texture
    coordinates uv (n, 3, 2) that Mitsuba's mesh holds as `mesh` (3 x 3, affine) maps them, or as
    the lookup's own coordinates where `mesh` is None: the texels decoded by Mitsuba (`decode`),
    baked for its wrap mode (`bake`), times the factor (exact: filtering is linear), stored as
    float32 (`format` variant: its default keeps 8-bit images in half precision),
    KHR_texture_transform and the bake's map as `to_uv`. Returns the dict and the lookup's map
    of glTF's mesh coordinates to the bitmap's. `texels`, where given, replace the decoded image."""
    texels = decode(mi, tex, folder, srgb) if texels is None else texels
    coords = tex.coordinates(uv.reshape(-1, 2))
    texels, mode, a = bake(texels, tex, coords)
    texels = texels * np.asarray(factor, dtype=np.float32)
    lookup = a @ np.vstack([tex.transform, [0.0, 0.0, 1.0]])
    to_uv = np.eye(3) if mesh is None else lookup @ np.linalg.inv(mesh)
    return {"type": "bitmap", "bitmap": mi.Bitmap(texels), "raw": True, "format": "variant",
            "filter_type": "nearest" if tex.nearest else "bilinear", "wrap_mode": mode,
            "to_uv": mi.ScalarTransform3f(mi.ScalarMatrix3f(to_uv.tolist()))}, lookup


def alpha_texels(mi, tex, folder):
    """The texture's alpha channel (h, w, 1) as stored (linear: glTF's alpha is never sRGB)."""
    path = os.path.join(folder, f"alpha{abs(hash(tex.image))}.png")
    with open(path, "wb") as f:
        f.write(tex.image)
    raw = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGBA, mi.Struct.Type.UInt8, srgb_gamma=False)
    return np.array(raw)[:, :, 3:4].astype(np.float32) / 255.0


def opacity_dict(mi, mat, uv, folder, mesh=np.eye(3)):
    """glTF's cut-out of `mat` (alphaMode MASK or BLEND) as the opacity of Mitsuba's `mask`: the
    factor's alpha x the base colour texture's alpha, filtered as the texture is. BLEND: that
    opacity (a `mask` passes light through 1 - opacity of the surface, smlt's stochastic
    opacity in expectation). MASK: 0 or 1 by alphaCutoff — Mitsuba has no threshold, so the
    glTF lookup (gltf_scene.sample, numpy, from the spec) is evaluated at the centres of a grid
    32 x finer than the texture's and thresholded there, the result a NEAREST bitmap (exact for
    a NEAREST texture; the bilinear silhouette to a thirty-second of a texel)."""
    tex = mat.base_color_texture
    if tex is None:
        value = mat.opacity if mat.alpha_mode == "BLEND" else float(mat.opacity >= mat.alpha_cutoff)
        return {"type": "rgb", "value": [value] * 3}
    alpha = alpha_texels(mi, tex, folder) * mat.opacity
    if mat.alpha_mode == "MASK":
        h, w = alpha.shape[:2]
        k = 1 if tex.nearest else 32
        ys, xs = (np.arange(h * k) + 0.5) / (h * k), (np.arange(w * k) + 0.5) / (w * k)
        grid = np.stack(np.meshgrid(xs, ys), axis=-1)  # (h k, w k, 2): (u, v) at the fine centres
        alpha = (gltf_scene.sample(alpha, tex, grid) >= mat.alpha_cutoff).astype(np.float32)
        tex = dataclasses.replace(tex, nearest=True)
    d, _ = texture_dict(mi, tex, 1.0, uv, folder, mesh=mesh, texels=np.repeat(alpha, 3, axis=2))
    return d


def mesh_textures(mi, mat, uv, folder):
    """A textured material's (mesh texture coordinates (n, 3, 2), reflectance, radiance): the
    `bitmap`s of its baseColorTexture and emissiveTexture (None without). Mitsuba's `area`
    emitter samples a spatially varying radiance by the bitmap's own texel distribution over
    [0, 1]² and maps the sampled uv onto the shape as mesh coordinates (`eval_parameterization`,
    src/emitters/area.cpp: `to_uv` is not applied there), so an emissive texture's lookup
    coordinates become the mesh's own, its `to_uv` the identity (the other texture's `to_uv`
    undoes that), and they must cover [0, 1]² once: checked (total uv area 1, none outside),
    refused otherwise, as Mitsuba's light sampling would then be biased."""
    reflectance = radiance = None
    mesh_uv = uv
    if mat.emissive_texture:
        radiance, lookup = texture_dict(mi, mat.emissive_texture, mat.emission, uv, folder, mesh=None)
        mesh_uv = uv @ lookup[:2, :2].T + lookup[:2, 2]
        e1, e2 = mesh_uv[:, 1] - mesh_uv[:, 0], mesh_uv[:, 2] - mesh_uv[:, 0]
        area = np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum() / 2
        if abs(area - 1) > 1e-4 or mesh_uv.min() < -1e-5 or mesh_uv.max() > 1 + 1e-5:
            raise SystemExit(f"material {mat.name!r}: its emissiveTexture's coordinates cover {area:.4f} of"
                             f" [0, 1]² within [{mesh_uv.min():.3f}, {mesh_uv.max():.3f}]: Mitsuba's `area`"
                             " emitter samples a texture only where they cover it once")
        mesh = lookup
    else:
        mesh = np.eye(3)
    if mat.base_color_texture:
        reflectance, _ = texture_dict(mi, mat.base_color_texture, mat.albedo, uv, folder, mesh=mesh)
    return mesh_uv, reflectance, radiance


def scene_dict(mi, scene, view, width, height, max_depth, folder):
    cam = scene.cameras[view - 1]
    target = cam.position + cam.forward
    d = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": max_depth + 1, "hide_emitters": False},
        "sensor": {
            "type": "perspective",
            "fov_axis": "y",
            "fov": math.degrees(cam.yfov),
            "to_world": mi.ScalarTransform4f().look_at(
                origin=cam.position.tolist(), target=target.tolist(), up=cam.up.tolist()
            ),
            "film": {
                "type": "hdrfilm",
                "width": width,
                "height": height,
                "rfilter": {"type": "box"},
                "pixel_format": "rgb",
            },
            "sampler": {"type": "independent", "sample_count": 1},
        },
    }
    for m, tris in scene.triangles.items():
        mat = scene.materials[m]
        path = os.path.join(folder, f"mesh{m}.ply")
        uv = None
        if mat.textures:
            sets = {t.tex_coord for t in mat.textures}
            if len(sets) > 1:
                raise SystemExit(f"material {mat.name!r}: textures on TEXCOORD_0 and _1 (a Mitsuba mesh has one set)")
            uv = scene.texcoords[m][:, :, :, sets.pop()]
            if mat.metallic_roughness_texture or mat.phong > 0 or not mat.lambertian or mat.transmission > 0:
                raise SystemExit(f"material {mat.name!r}: Mitsuba's peer reads textures on Lambert surfaces"
                                 " (baseColorTexture) and emitters (emissiveTexture) only")
        reflectance = radiance = None
        if uv is not None:
            uv, reflectance, radiance = mesh_textures(mi, mat, uv, folder)
        # smooth shading normals (glTF's NORMAL) as the PLY's vertex normals, which Mitsuba
        # interpolates (`face_normals` false); a mesh without them stays flat, as before
        normals = scene.normals.get(m)
        write_ply(path, tris, uv, normals)
        rgb = reflectance or {"type": "rgb", "value": list(mat.albedo)}
        if mat.phong > 0:
            # mitsuba_phong.py's plugin, registered in main()
            bsdf = {"type": "smlt_phong", "reflectance": list(mat.albedo), "exponent": mat.phong}
        elif mat.lambertian:
            # smlt's surfaces scatter on both sides; Mitsuba's `diffuse` alone is black from behind
            bsdf = {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": rgb}}
        else:
            # glTF's BRDF: mitsuba_gltf.py's plugin (two-sided), registered in main()
            bsdf = {"type": "smlt_gltf", "base_color": list(mat.albedo), "metallic": mat.metallic,
                    "alpha": mat.alpha, "f0": list(mat.f0), "f90": mat.specular}
        if mat.alpha_mode in ("MASK", "BLEND") and max(mat.emission) == 0:
            # glTF's cut-outs (smlt's shared/src/cutout.rs): Mitsuba's `mask` over the surface
            bsdf = {"type": "mask", "opacity": opacity_dict(mi, mat, scene.texcoords[m][:, :, :, 0]
                                                             if mat.base_color_texture else None, folder),
                    "bsdf": bsdf}
        medium = None
        if mat.transmission > 0:
            glass = {"type": "thindielectric" if mat.thin_walled else "dielectric",
                     "int_ior": mat.ior, "ext_ior": 1.0, "specular_transmittance": rgb}
            if mat.rough_glass and mat.thin_walled:
                glass = {"type": "smlt_thin", "alpha": mat.alpha, "ior": mat.ior, "tint": list(mat.albedo)}
            elif mat.rough_glass:
                glass.update({"type": "roughdielectric", "distribution": "ggx", "alpha": mat.alpha,
                              "sample_visible": True})
            if mat.transmission < 1:
                glass = {"type": "blendbsdf", "weight": mat.transmission, "bsdf_0": bsdf, "bsdf_1": glass}
                if glass["bsdf_1"]["type"] == "thindielectric":
                    # Measured on 3.9.1 (check_materials.sh's transmission plate): `path` renders
                    # this blend 46 % dark; `direct` and the BSDF's `eval` agree with smlt.
                    print(f"warning: {mat.name}: Mitsuba's `path` renders blendbsdf with thindielectric dark",
                          file=sys.stderr)
            bsdf = glass
            if not mat.thin_walled and max(mat.attenuation) > 0:
                # an rgb value must lie in [0, 1]: the medium's `scale` carries the magnitude
                top = max(mat.attenuation)
                medium = {"type": "homogeneous", "albedo": 0.0, "scale": top,
                          "sigma_t": {"type": "rgb", "value": [c / top for c in mat.attenuation]}}
                d["integrator"]["type"] = "volpath"
        if max(mat.sheen_color) > 0:
            # KHR_materials_sheen over everything but the coat: mitsuba_sheen.py's plugin
            bsdf = {"type": "smlt_sheen", "color": list(mat.sheen_color), "roughness": mat.sheen_roughness,
                    "base": bsdf}
        if mat.clearcoat > 0:
            # KHR_materials_clearcoat over everything: mitsuba_coat.py's plugin, registered in main()
            bsdf = {"type": "smlt_coat", "clearcoat": mat.clearcoat, "alpha": mat.clearcoat_roughness ** 2,
                    "base": bsdf}
        shape = {"type": "ply", "filename": path, "face_normals": normals is None, "bsdf": bsdf}
        if medium is not None:
            shape["interior"] = medium
        if max(mat.emission) > 0:
            radiance = radiance or {"type": "rgb", "value": list(mat.emission)}
            shape["emitter"] = {"type": "area", "radiance": radiance}
        d[f"mesh{m}"] = shape
    for i, light in enumerate(scene.lights):
        d[f"light{i}"] = light_dict(mi, light)
    return d


def environment_dict(mi, source, strength, rotation):
    """smlt's `--environment` as Mitsuba's emitter: a constant colour -> `constant`; a lat-long
    image -> `envmap` of the same file, `scale` the strength, turned about +Y by `rotation`
    degrees (smlt maps directions to the image as `envmap` does). Mitsuba looks its texels up
    bilinearly where smlt takes the nearest: the two agree on a map that is smooth at its texels'
    scale."""
    try:
        values = [float(v) for v in source.split(",")]
    except ValueError:
        values = None
    if values is not None:
        rgb = values * 3 if len(values) == 1 else values
        return {"type": "constant", "radiance": {"type": "rgb", "value": [c * strength for c in rgb]}}
    return {"type": "envmap", "filename": os.path.abspath(source), "scale": strength,
            "to_world": mi.ScalarTransform4f().rotate(axis=[0, 1, 0], angle=rotation)}


def light_dict(mi, light):
    """A glTF punctual light as Mitsuba's emitter of the same radiometric value. Mitsuba's spot
    ramps linearly in angle between beam_width and cutoff_angle, glTF's as the square of a ramp
    in cos θ: the two agree only where the ramp is narrow (smlt's `lamps`: 0.2°)."""
    value = {"type": "rgb", "value": list(light.intensity)}
    if light.kind == "point":
        return {"type": "point", "position": light.position.tolist(), "intensity": value}
    if light.kind == "directional":
        return {"type": "directional", "direction": light.direction.tolist(), "irradiance": value}
    up = [0.0, 1.0, 0.0] if abs(light.direction[1]) < 0.9 else [1.0, 0.0, 0.0]
    return {
        "type": "spot",
        "intensity": value,
        "cutoff_angle": math.degrees(light.outer),
        "beam_width": math.degrees(light.inner),
        "to_world": mi.ScalarTransform4f().look_at(
            origin=light.position.tolist(), target=(light.position + light.direction).tolist(), up=up
        ),
    }


def read_exr(mi, path):
    return np.array(mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False))


def main():
    ap = arguments(__doc__)
    ap.add_argument("--chunk", type=int, default=4, help="samples per pixel per render call")
    ap.add_argument("--converged", type=int, default=0, help="check: render SPP samples once and compare")
    ap.add_argument("--variant", default=None)
    ap.add_argument("--environment", default=None, help="as smlt's: FILE.exr|.hdr or R,G,B")
    ap.add_argument("--environment-strength", type=float, default=1.0)
    ap.add_argument("--environment-rotation", type=float, default=0.0, help="degrees about +Y")
    ap.add_argument("--texture-rotation", choices=["listing", "example"], default="example",
                    help="KHR_texture_transform's rotation: as smlt and the implementations, or as the GLSL listing")
    ap.add_argument("--save", default=None, help="with --converged: write the image to this EXR")
    a = ap.parse_args()

    import mitsuba as mi

    variant = a.variant
    if variant is None:
        variant = "scalar_rgb"
        if os.environ.get("DRJIT_LIBLLVM_PATH"):
            variant = "llvm_ad_rgb"
    mi.set_variant(variant)
    import mitsuba_phong  # after set_variant: the plugin derives from the variant's mi.BSDF

    mitsuba_phong.register()
    import mitsuba_gltf

    mitsuba_gltf.register()
    import mitsuba_coat

    mitsuba_coat.register()
    import mitsuba_sheen

    mitsuba_sheen.register()
    import mitsuba_thin

    mitsuba_thin.register()
    scene = gltf_scene.load(a.scene, rotation=a.texture_rotation)
    label = a.label or os.path.splitext(os.path.basename(a.scene))[0]
    reference = read_exr(mi, a.reference)
    if reference.shape[:2] != (a.height, a.width):
        raise SystemExit(f"the reference is {reference.shape[1]}x{reference.shape[0]}, not {a.width}x{a.height}")
    with tempfile.TemporaryDirectory() as folder:
        d = scene_dict(mi, scene, a.view, a.width, a.height, a.max_depth, folder)
        if a.environment:
            d["environment"] = environment_dict(mi, a.environment, a.environment_strength, a.environment_rotation)
        m_scene = mi.load_dict(d)
        if a.converged:
            start = time.time()
            img = np.array(m_scene.integrator().render(m_scene, seed=1, spp=a.converged))
            took = time.time() - start
            if a.save:
                mi.Bitmap(img.astype(np.float32)).write(a.save)
            mean_i, mean_r = img.mean(), reference.mean()
            flipped = errors(img[:, ::-1], reference)[0]
            print(f"{label} v{a.view}: {a.converged} spp in {took:.1f} s with {variant}; mean {mean_i:.5f} against the"
                  f" reference's {mean_r:.5f} ({100 * (mean_i / mean_r - 1):+.2f} %); RMSE {errors(img, reference)[0]:.5f},"
                  f" mirrored {flipped:.5f}")
            return

        def render(spp, seed):
            start = time.time()
            img = np.array(m_scene.integrator().render(m_scene, seed=seed, spp=spp))
            return img, time.time() - start

        rows = equal_time_rows(render, a.chunk, a.seconds, a.repeats, reference, label, a.view, "mitsuba-path")
    append_rows(a.out, rows)


if __name__ == "__main__":
    main()
