#!/usr/bin/env bash
# Mitsuba 3 against smlt on KHR_materials_anisotropy: the means and RMSEs that docs/results.md
# quotes. A plate with NORMAL and TEXCOORD_0 (its tangent frame: plate_scene.FRAME) of each kind
# (a brushed gold metal along the tangent and turned 1 rad, a red dielectric turned 0.5 rad, and
# the gold turned 0.3 rad by its factor and again by a uniform anisotropyTexture, TEXEL, whose
# direction 2·rg − 1 and strength factor b the exact image takes as the spec defines them)
# under a sun, filling the view: smlt's reference against the plate's exact image (one bounce:
# the BRDF at each pixel's directions × the sun's irradiance) through `smlt_gltf`
# (mitsuba_gltf.py: the extension's V_GGX_anisotropic and D_GGX_anisotropic, written from its
# text, in the direction that the spec's frame gives), and against the isotropic plate's exact
# image, which says how far the check could miss. Then each plate under a blue sky too
# (--environment 0.5,0.6,0.8), where the lobe's sampling counts: smlt's reference against
# Mitsuba's render through the plugin, which samples with Mitsuba's anisotropic GGX.
#   scripts/peers/check_anisotropy.sh [OUT]   (default: /tmp/check-anisotropy)
# Needs smlt built (cargo build --release), the peers' Python packages (requirements.txt) and
# DRJIT_LIBLLVM_PATH (a libLLVM >= 16; the plugin needs Mitsuba's llvm_ad_rgb variant).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
out="${1:-/tmp/check-anisotropy}"
smlt="${CARGO_TARGET_DIR:-$root/target}/release/smlt"
size=(--width 128 --height 96 --max-depth 12)
: "${DRJIT_LIBLLVM_PATH:?set DRJIT_LIBLLVM_PATH to a libLLVM >= 16 (scripts/peers/README.md)}"
export DRJIT_LIBLLVM_PATH
mkdir -p "$out"
cd "$out"
export TEXEL="140,250,160,255"
PYTHONPATH="$root/scripts/peers" python3 - <<'PY'
import os
import plate_scene
texel = [int(c) for c in os.environ["TEXEL"].split(",")]
gold = {"baseColorFactor": [1.0, 0.78, 0.34, 1], "metallicFactor": 1.0, "roughnessFactor": 0.3}
red = {"baseColorFactor": [0.7, 0.1, 0.08, 1], "metallicFactor": 0.0, "roughnessFactor": 0.25}
plates = {
    "brushed": (gold, {"anisotropyStrength": 0.8}),
    "turned": (gold, {"anisotropyStrength": 0.8, "anisotropyRotation": 1.0}),
    "satin": (red, {"anisotropyStrength": 0.7, "anisotropyRotation": 0.5}),
    "textured": (gold, {"anisotropyStrength": 0.8, "anisotropyRotation": 0.3, "anisotropyTexture": {"index": 0}}),
}
for name, (pbr, ext) in plates.items():
    plate_scene.write(f"plate_{name}.gltf", name, pbr, {"KHR_materials_anisotropy": ext}, mapped=True,
                      texel=texel if "anisotropyTexture" in ext else None)
PY
for name in brushed turned satin textured; do
    "$smlt" reference "plate_$name.gltf" --device cpu --spp 256 "${size[@]}" --out "ref_plate_$name.exr" 2>&1 | { grep -E "noise" | sed "s/^/$name: /" || true; }
    "$smlt" reference "plate_$name.gltf" --device cpu --spp 1024 "${size[@]}" --environment 0.5,0.6,0.8 \
        --out "ref_sky_$name.exr" 2>&1 | { grep -E "noise" | sed "s/^/$name under the sky: /" || true; }
done
PYTHONPATH="$root/scripts/peers" python3 - "${size[@]}" <<'PY'
import json, math, os, sys, tempfile
import mitsuba as mi
import numpy as np
mi.set_variant("llvm_ad_rgb")
import gltf_scene, mitsuba_gltf, mitsuba_peer, plate_scene
mitsuba_gltf.register()
w, h, depth = int(sys.argv[2]), int(sys.argv[4]), int(sys.argv[6])
(tx, ty, tz), (bx, by, bz) = plate_scene.FRAME
print("plate: smlt | exact anisotropic (difference, RMSE) | exact isotropic (difference, RMSE)")
skies = []
texel = [int(c) / 255 for c in os.environ["TEXEL"].split(",")]
for name in ["brushed", "turned", "satin", "textured"]:
    scene = gltf_scene.load(f"plate_{name}.gltf")
    mat, sun = scene.materials[1], scene.lights[0]
    ext = json.load(open(f"plate_{name}.gltf"))["materials"][0]["extensions"]["KHR_materials_anisotropy"]
    strength, rotation = ext.get("anisotropyStrength", 0.0), ext.get("anisotropyRotation", 0.0)
    if "anisotropyTexture" in ext:
        # The spec: the texel's direction 2·rg − 1 turned by the rotation; its b times the strength.
        rotation += math.atan2(2 * texel[1] - 1, 2 * texel[0] - 1)
        strength *= texel[2]
    c, s = math.cos(rotation), math.sin(rotation)
    direction = [c * tx + s * bx, c * ty + s * by, c * tz + s * bz]
    images = {}
    with tempfile.TemporaryDirectory() as folder:
        d = mitsuba_peer.scene_dict(mi, scene, 1, w, h, depth, folder)
        key = [k for k in d if k.startswith("mesh")][0]
        base = {"type": "smlt_gltf", "base_color": list(mat.albedo), "metallic": mat.metallic,
                "alpha": mat.alpha, "f0": list(mat.f0), "f90": mat.specular}
        d[key]["bsdf"] = dict(base, alpha_t=mat.alpha + (1 - mat.alpha) * strength ** 2, alpha_b=mat.alpha,
                              direction=direction)
        images["anisotropic"] = plate_scene.exact_image(mi, d, sun, w, h)
        d["environment"] = mitsuba_peer.environment_dict(mi, "0.5,0.6,0.8", 1.0, 0.0)
        sky = np.array(mi.render(mi.load_dict(d), spp=1024))
        del d["environment"]
        d[key]["bsdf"] = base
        images["isotropic"] = plate_scene.exact_image(mi, d, sun, w, h)
    ref = mitsuba_peer.read_exr(mi, f"ref_plate_{name}.exr")
    m = lambda a: float(np.mean(a))  # noqa: E731
    cells = []
    for kind in ["anisotropic", "isotropic"]:
        img = images[kind]
        rmse = float(np.sqrt(np.mean((ref - img) ** 2)))
        cells.append(f"{m(img):.5f} ({100 * (m(ref) / m(img) - 1):+.2f} %, {rmse:.1e})")
    print(f"{name}: {m(ref):.5f} | " + " | ".join(cells))
    ref_sky = mitsuba_peer.read_exr(mi, f"ref_sky_{name}.exr")
    rmse = float(np.sqrt(np.mean((ref_sky - sky) ** 2)))
    skies.append(f"{name} under the sky: smlt {m(ref_sky):.5f}, Mitsuba (1024 spp) {m(sky):.5f} "
                 f"({100 * (m(sky) / m(ref_sky) - 1):+.2f} %), RMSE {rmse:.1e}")
print("\n".join(skies))
PY
