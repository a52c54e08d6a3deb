#!/usr/bin/env bash
# Mitsuba 3 against smlt on glTF's clear coat (KHR_materials_clearcoat): the means and RMSEs that
# docs/results.md quotes.
#  1. A plate of each kind under a sun, filling the view: a white Lambert under a rough coat
#     (0.3), red paint (the glTF BRDF, roughness 0.5) under a smooth coat, a black base under a
#     rough coat (0.5: the coat alone reflects) and rough gold under a half-strength glossy coat
#     (0.2). smlt's reference against Mitsuba with `smlt_coat` (mitsuba_coat.py, the extension
#     written independently, over Mitsuba's `diffuse` or mitsuba_gltf.py's `smlt_gltf`) and
#     against each plate's exact image (one bounce: the coated BSDF at each pixel's directions ×
#     the sun's irradiance, evaluated by Mitsuba).
#  2. The `coated` scene (every kind of base and coat, smooth coats' mirrors included, under two
#     area lamps): smlt's reference against Mitsuba with the plugins.
#   scripts/peers/check_clearcoat.sh [OUT]   (default: /tmp/check-clearcoat)
# Needs smlt built (cargo build --release), the peers' Python packages (requirements.txt) and
# DRJIT_LIBLLVM_PATH (a libLLVM >= 16; the plugins need Mitsuba's llvm_ad_rgb variant).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
out="${1:-/tmp/check-clearcoat}"
smlt="${CARGO_TARGET_DIR:-$root/target}/release/smlt"
size=(--width 128 --height 96 --max-depth 12)
: "${DRJIT_LIBLLVM_PATH:?set DRJIT_LIBLLVM_PATH to a libLLVM >= 16 (scripts/peers/README.md)}"
export DRJIT_LIBLLVM_PATH
mkdir -p "$out"
cd "$out"
"$smlt" scene coated --out coated.gltf >/dev/null
PYTHONPATH="$root/scripts/peers" python3 - <<'PY'
import plate_scene
lambert = {"KHR_materials_specular": {"specularFactor": 0.0}}
plates = {
    "lacquer": ({"baseColorFactor": [0.8, 0.8, 0.78, 1], "metallicFactor": 0.0}, lambert, (1.0, 0.3)),
    "paint": ({"baseColorFactor": [0.6, 0.05, 0.04, 1], "metallicFactor": 0.0, "roughnessFactor": 0.5}, {}, (1.0, 0.0)),
    "piano": ({"baseColorFactor": [0.0, 0.0, 0.0, 1], "metallicFactor": 0.0}, lambert, (1.0, 0.5)),
    "gold": ({"baseColorFactor": [1.0, 0.78, 0.34, 1], "metallicFactor": 1.0, "roughnessFactor": 0.4}, {}, (0.5, 0.2)),
}
for name, (pbr, ext, (coat, roughness)) in plates.items():
    ext = dict(ext, KHR_materials_clearcoat={"clearcoatFactor": coat, "clearcoatRoughnessFactor": roughness})
    plate_scene.write(f"plate_{name}.gltf", name, pbr, ext)
PY
for name in lacquer paint piano gold; do
    "$smlt" reference "plate_$name.gltf" --device cpu --spp 1024 "${size[@]}" --out "ref_plate_$name.exr" | { grep -E "noise" || true; }
    python3 "$root/scripts/peers/mitsuba_peer.py" "plate_$name.gltf" "${size[@]}" --variant llvm_ad_rgb \
        --reference "ref_plate_$name.exr" --converged 1024 --label "plate_$name" | tail -1
done
PYTHONPATH="$root/scripts/peers" python3 - "${size[@]}" <<'PY'
# Each plate's exact image (one bounce, no shadow: the plate alone under the sun) through the
# plugins, at the pixels' centres; against smlt's reference.
import sys, tempfile
import mitsuba as mi
import numpy as np
mi.set_variant("llvm_ad_rgb")
import gltf_scene, mitsuba_coat, mitsuba_gltf, mitsuba_peer, plate_scene
mitsuba_gltf.register()
mitsuba_coat.register()
w, h, depth = int(sys.argv[2]), int(sys.argv[4]), int(sys.argv[6])
def exact(scene):
    with tempfile.TemporaryDirectory() as folder:
        d = mitsuba_peer.scene_dict(mi, scene, 1, w, h, depth, folder)
        return plate_scene.exact_image(mi, d, scene.lights[0], w, h)
print("plate: smlt mean | exact mean (smlt_coat over the base, one bounce) | difference | RMSE of smlt to exact"
      " | the base alone's exact mean (what the coat changes)")
for name in ["lacquer", "paint", "piano", "gold"]:
    scene = gltf_scene.load(f"plate_{name}.gltf")
    coated = exact(scene)
    scene.materials[1].clearcoat = 0.0
    bare = exact(scene)
    ref = mitsuba_peer.read_exr(mi, f"ref_plate_{name}.exr")
    m = lambda a: float(np.mean(a))  # noqa: E731
    rmse = float(np.sqrt(np.mean((ref - coated) ** 2)))
    print(f"{name}: {m(ref):.5f} | {m(coated):.5f} | {100 * (m(ref) / m(coated) - 1):+.2f} % | {rmse:.2e} | {m(bare):.5f}")
PY
"$smlt" reference coated.gltf --device cpu --spp 2048 "${size[@]}" --out ref_coated.exr | { grep -E "noise" || true; }
python3 "$root/scripts/peers/mitsuba_peer.py" coated.gltf "${size[@]}" --variant llvm_ad_rgb \
    --reference ref_coated.exr --converged 2048 --label coated | tail -1
