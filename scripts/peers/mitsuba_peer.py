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
reflecting 2R/(1+R) where glTF's single interface reflects R), tinted by baseColor, blended
with the BRDF rest by `blendbsdf` where transmissionFactor < 1; glTF's metallic-roughness BRDF
otherwise -> `smlt_gltf`, a Python BSDF plugin written from the spec (`mitsuba_gltf.py`: Mitsuba
has no glTF BRDF; `principled` is Disney's, see check_materials.sh); `--environment` as smlt's
-> `envmap` or `constant` (`environment_dict`).
Variants: `llvm_ad_rgb` when Mitsuba finds a libLLVM (set DRJIT_LIBLLVM_PATH; Debian's
libllvm19 unpacked with dpkg-deb -x works), else `scalar_rgb`."""

import math
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gltf_scene  # noqa: E402
from peer_common import append_rows, arguments, equal_time_rows, errors, write_ply  # noqa: E402


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
        write_ply(path, tris)
        rgb = {"type": "rgb", "value": list(mat.albedo)}
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
        medium = None
        if mat.transmission > 0:
            glass = {"type": "thindielectric" if mat.thin_walled else "dielectric",
                     "int_ior": mat.ior, "ext_ior": 1.0, "specular_transmittance": rgb}
            if mat.rough_glass:
                glass.update({"type": "roughdielectric", "distribution": "ggx", "alpha": mat.alpha,
                              "sample_visible": True})
            if mat.transmission < 1:
                glass = {"type": "blendbsdf", "weight": mat.transmission, "bsdf_0": bsdf, "bsdf_1": glass}
            bsdf = glass
            if not mat.thin_walled and max(mat.attenuation) > 0:
                # an rgb value must lie in [0, 1]: the medium's `scale` carries the magnitude
                top = max(mat.attenuation)
                medium = {"type": "homogeneous", "albedo": 0.0, "scale": top,
                          "sigma_t": {"type": "rgb", "value": [c / top for c in mat.attenuation]}}
                d["integrator"]["type"] = "volpath"
        shape = {"type": "ply", "filename": path, "face_normals": True, "bsdf": bsdf}
        if medium is not None:
            shape["interior"] = medium
        if max(mat.emission) > 0:
            shape["emitter"] = {"type": "area", "radiance": {"type": "rgb", "value": list(mat.emission)}}
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
    scene = gltf_scene.load(a.scene)
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
