#!/usr/bin/env bash
# Mitsuba 3 against smlt on glTF's sheen (KHR_materials_sheen): the means and RMSEs that
# docs/results.md quotes. Three plates filling the view: a pink velvet sheen (roughness 0.5)
# over red plastic, a white satin sheen (roughness 0.25) over rough gold, and the velvet with
# a sheenColorTexture and a sheenRoughnessTexture of one texel, TEXEL (Mitsuba takes the
# untextured plate of the products the spec defines: rgb sRGB-decoded, alpha linear). Under a
# sun: smlt's reference against the plate's exact image (one bounce: the BSDF at each pixel's
# directions × the sun's irradiance) through `smlt_sheen` (mitsuba_sheen.py, written from the
# extension's notes, with its own quadrature of the albedo E) over `smlt_gltf`, and against the
# base alone, which says how far the check could miss. Under a blue sky too (--environment
# 0.5,0.6,0.8), where the layer's sampling counts: smlt's reference against Mitsuba's render
# through the plugins, which sample their own way.
#   scripts/peers/check_sheen.sh [OUT]   (default: /tmp/check-sheen)
# Needs smlt built (cargo build --release), the peers' Python packages (requirements.txt) and
# DRJIT_LIBLLVM_PATH (a libLLVM >= 16; the plugins need Mitsuba's llvm_ad_rgb variant).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
out="${1:-/tmp/check-sheen}"
smlt="${CARGO_TARGET_DIR:-$root/target}/release/smlt"
size=(--width 128 --height 96 --max-depth 12)
: "${DRJIT_LIBLLVM_PATH:?set DRJIT_LIBLLVM_PATH to a libLLVM >= 16 (scripts/peers/README.md)}"
export DRJIT_LIBLLVM_PATH
mkdir -p "$out"
cd "$out"
export TEXEL="192,237,100,128"
PYTHONPATH="$root/scripts/peers" python3 - <<'PY'
import os
import plate_scene
texel = [int(c) for c in os.environ["TEXEL"].split(",")]
srgb = lambda c: c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4  # noqa: E731
plastic = {"baseColorFactor": [0.5, 0.05, 0.06, 1], "metallicFactor": 0.0, "roughnessFactor": 0.7}
gold = {"baseColorFactor": [1.0, 0.78, 0.34, 1], "metallicFactor": 1.0, "roughnessFactor": 0.4}
velvet = {"sheenColorFactor": [0.9, 0.4, 0.6], "sheenRoughnessFactor": 0.5}
plates = {
    "velvet": (plastic, velvet),
    "satin": (gold, {"sheenColorFactor": [1.0, 1.0, 1.0], "sheenRoughnessFactor": 0.25}),
}
for name, (pbr, sheen) in plates.items():
    plate_scene.write(f"plate_{name}.gltf", name, pbr, {"KHR_materials_sheen": sheen})
    plate_scene.write(f"bare_{name}.gltf", name, pbr, {})
textured = dict(velvet, sheenColorTexture={"index": 0}, sheenRoughnessTexture={"index": 0})
plate_scene.write("plate_textured.gltf", "textured", plastic, {"KHR_materials_sheen": textured}, mapped=True,
                  texel=texel)
products = {"sheenColorFactor": [f * srgb(c / 255) for f, c in zip(velvet["sheenColorFactor"], texel)],
            "sheenRoughnessFactor": velvet["sheenRoughnessFactor"] * texel[3] / 255}
plate_scene.write("plate_textured_factors.gltf", "textured", plastic, {"KHR_materials_sheen": products}, mapped=True)
plate_scene.write("bare_textured.gltf", "textured", plastic, {}, mapped=True)
PY
for name in velvet satin textured; do
    "$smlt" reference "plate_$name.gltf" --device cpu --spp 256 "${size[@]}" --out "ref_plate_$name.exr" 2>&1 | { grep -E "noise" | sed "s/^/$name: /" || true; }
    "$smlt" reference "plate_$name.gltf" --device cpu --spp 1024 "${size[@]}" --environment 0.5,0.6,0.8 \
        --out "ref_sky_$name.exr" 2>&1 | { grep -E "noise" | sed "s/^/$name under the sky: /" || true; }
done
PYTHONPATH="$root/scripts/peers" python3 - "${size[@]}" <<'PY'
import sys, tempfile
import mitsuba as mi
import numpy as np
mi.set_variant("llvm_ad_rgb")
import gltf_scene, mitsuba_gltf, mitsuba_peer, mitsuba_sheen, plate_scene
mitsuba_gltf.register()
mitsuba_sheen.register()
w, h, depth = int(sys.argv[2]), int(sys.argv[4]), int(sys.argv[6])
m = lambda a: float(np.mean(a))  # noqa: E731


def images(path, sky):
    scene = gltf_scene.load(path)
    with tempfile.TemporaryDirectory() as folder:
        d = mitsuba_peer.scene_dict(mi, scene, 1, w, h, depth, folder)
        exact = plate_scene.exact_image(mi, d, scene.lights[0], w, h)
        rendered = None
        if sky:
            d["environment"] = mitsuba_peer.environment_dict(mi, "0.5,0.6,0.8", 1.0, 0.0)
            rendered = np.array(mi.render(mi.load_dict(d), spp=1024))
    return exact, rendered


print("plate: smlt | exact (difference, RMSE) | the base alone's exact (RMSE)")
skies = []
for name in ["velvet", "satin", "textured"]:
    peer = "textured_factors" if name == "textured" else name
    exact, sky = images(f"plate_{peer}.gltf", True)
    bare, _ = images(f"bare_{name}.gltf", False)
    ref = mitsuba_peer.read_exr(mi, f"ref_plate_{name}.exr")
    rmse = lambda a: float(np.sqrt(np.mean((ref - a) ** 2)))  # noqa: E731
    print(f"{name}: {m(ref):.5f} | {m(exact):.5f} ({100 * (m(ref) / m(exact) - 1):+.2f} %, {rmse(exact):.1e}) | "
          f"{m(bare):.5f} ({rmse(bare):.1e})")
    ref_sky = mitsuba_peer.read_exr(mi, f"ref_sky_{name}.exr")
    rms = float(np.sqrt(np.mean((ref_sky - sky) ** 2)))
    skies.append(f"{name} under the sky and the sun: smlt {m(ref_sky):.5f}, Mitsuba (1024 spp) {m(sky):.5f} "
                 f"({100 * (m(sky) / m(ref_sky) - 1):+.2f} %), RMSE {rms:.1e}")
print("\n".join(skies))
PY
