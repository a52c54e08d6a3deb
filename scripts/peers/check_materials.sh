#!/usr/bin/env bash
# Mitsuba 3 against smlt on glTF's metallic-roughness BRDF: the means and RMSEs that
# docs/results.md quotes.
#  1. A plate of each kind (rough gold, red plastic, satin white, glTF's defaults) under a sun,
#     filling the view: smlt's reference against Mitsuba with `smlt_gltf` (mitsuba_gltf.py, the
#     spec's BRDF written independently) and against each plate's exact image (one bounce: the
#     BRDF at each pixel's directions × the sun's irradiance, evaluated by Mitsuba); and
#     Mitsuba's own `principled` (Disney's BRDF, not glTF's) against its exact image, which
#     states the difference to expect between the two models before it is measured. The
#     `specular` plate's KHR_materials_specular has a specularTexture and a specularColorTexture
#     of one texel, TEXEL: Mitsuba takes the untextured plate whose factors are the products the
#     spec defines (the alpha linear, the rgb sRGB-decoded), computed here. The `transmission`
#     plate is the red plastic with metallicFactor 0.6 and KHR_materials_transmission 0.9, its
#     metallicRoughnessTexture and transmissionTexture that texel: Mitsuba takes the plate of
#     the products (metallic × B, roughness × G, transmission × R, all linear), which its
#     converter mixes as `blendbsdf` of `smlt_gltf` and `smlt_thin` (mitsuba_thin.py: the glass
#     share is a rough thin wall); under the sun the BRDF's share reflects and the glass's
#     reflection lobe.
#  2. The `materials` scene (every lobe, a mirror included, under two area lamps): smlt's
#     reference against Mitsuba with `smlt_gltf`.
#   scripts/peers/check_materials.sh [OUT]   (default: /tmp/check-materials)
# Needs smlt built (cargo build --release), the peers' Python packages (requirements.txt) and
# DRJIT_LIBLLVM_PATH (a libLLVM >= 16; the plugin needs Mitsuba's llvm_ad_rgb variant).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
out="${1:-/tmp/check-materials}"
smlt="${CARGO_TARGET_DIR:-$root/target}/release/smlt"
size=(--width 128 --height 96 --max-depth 12)
: "${DRJIT_LIBLLVM_PATH:?set DRJIT_LIBLLVM_PATH to a libLLVM >= 16 (scripts/peers/README.md)}"
export DRJIT_LIBLLVM_PATH
mkdir -p "$out"
cd "$out"
"$smlt" scene materials --out materials.gltf >/dev/null
export TEXEL="192,237,100,128"
PYTHONPATH="$root/scripts/peers" python3 - <<'PY'
import os
import plate_scene
texel = [int(c) for c in os.environ["TEXEL"].split(",")]
plates = {
    "gold": {"baseColorFactor": [1.0, 0.78, 0.34, 1], "metallicFactor": 1.0, "roughnessFactor": 0.35},
    "plastic": {"baseColorFactor": [0.7, 0.1, 0.08, 1], "metallicFactor": 0.0, "roughnessFactor": 0.3},
    "satin": {"baseColorFactor": [0.8, 0.8, 0.78, 1], "metallicFactor": 0.0, "roughnessFactor": 0.6},
    "defaults": {"baseColorFactor": [0.6, 0.6, 0.6, 1]},
}
for name, pbr in plates.items():
    plate_scene.write(f"plate_{name}.gltf", name, pbr, {})
# The specular plate: red plastic with both of KHR_materials_specular's textures, and its
# untextured equal for Mitsuba.
srgb = lambda c: c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4  # noqa: E731
factor, color = 0.9, [1.0, 0.8, 0.6]
textured = {"specularFactor": factor, "specularTexture": {"index": 0},
            "specularColorFactor": color, "specularColorTexture": {"index": 0}}
plate_scene.write("plate_specular.gltf", "specular", plates["plastic"], {"KHR_materials_specular": textured},
                  mapped=True, texel=texel)
products = {"specularFactor": factor * texel[3] / 255,
            "specularColorFactor": [f * srgb(c / 255) for f, c in zip(color, texel)]}
plate_scene.write("plate_specular_factors.gltf", "specular", plates["plastic"], {"KHR_materials_specular": products},
                  mapped=True)
# The transmission plate: the metallic-roughness texture and the transmission texture the same
# texel, and its untextured equal.
pbr = dict(plates["plastic"], metallicFactor=0.6, metallicRoughnessTexture={"index": 0})
glass = {"KHR_materials_transmission": {"transmissionFactor": 0.9, "transmissionTexture": {"index": 0}}}
plate_scene.write("plate_transmission.gltf", "transmission", pbr, glass, mapped=True, texel=texel)
pbr = dict(plates["plastic"], metallicFactor=0.6 * texel[2] / 255, roughnessFactor=0.3 * texel[1] / 255)
glass = {"KHR_materials_transmission": {"transmissionFactor": 0.9 * texel[0] / 255}}
plate_scene.write("plate_transmission_factors.gltf", "transmission", pbr, glass, mapped=True)
PY
for name in gold plastic satin defaults specular transmission; do
    peer=$name
    [ "$name" = specular ] || [ "$name" = transmission ] && peer=${name}_factors
    "$smlt" reference "plate_$name.gltf" --device cpu --spp 1024 "${size[@]}" --out "ref_plate_$name.exr" | { grep -E "noise" || true; }
    python3 "$root/scripts/peers/mitsuba_peer.py" "plate_$peer.gltf" "${size[@]}" --variant llvm_ad_rgb \
        --reference "ref_plate_$name.exr" --converged 1024 --label "plate_$name" | tail -1
done
PYTHONPATH="$root/scripts/peers" python3 - "${size[@]}" <<'PY'
# Each plate's exact image (one bounce, no shadow: the plate alone under the sun), for the
# glTF BRDF and for Mitsuba's principled, at the pixels' centres; against the renders.
import sys, tempfile
import mitsuba as mi
import numpy as np
mi.set_variant("llvm_ad_rgb")
import gltf_scene, mitsuba_gltf, mitsuba_peer, mitsuba_thin, plate_scene
mitsuba_gltf.register()
mitsuba_thin.register()
w, h, depth = int(sys.argv[2]), int(sys.argv[4]), int(sys.argv[6])
exact = lambda d, sun: plate_scene.exact_image(mi, d, sun, w, h)  # noqa: E731
print("plate: smlt | smlt_gltf exact | principled exact, principled render (means; principled vs glTF expected, measured)")
for name in ["gold", "plastic", "satin", "defaults", "specular", "transmission"]:
    textured = name in ("specular", "transmission")
    scene = gltf_scene.load(f"plate_{name}_factors.gltf" if textured else f"plate_{name}.gltf")
    mat, sun = scene.materials[1], scene.lights[0]
    with tempfile.TemporaryDirectory() as folder:
        d = mitsuba_peer.scene_dict(mi, scene, 1, w, h, depth, folder)
        gltf_img = exact(d, sun)
        if name == "transmission":
            # No principled: its transmission is another model again.
            ref = mitsuba_peer.read_exr(mi, f"ref_plate_{name}.exr")
            print(f"{name}: smlt {np.mean(ref):.5f} vs exact {np.mean(gltf_img):.5f} "
                  f"({100 * (np.mean(ref) / np.mean(gltf_img) - 1):+.2f} %)")
            continue
        key = [k for k in d if k.startswith("mesh")][0]
        d[key]["bsdf"] = {"type": "principled", "base_color": {"type": "rgb", "value": list(mat.albedo)},
                          "metallic": mat.metallic, "roughness": mat.alpha ** 0.5, "specular": 0.5}
        principled_img = exact(d, sun)
        rendered = np.array(mi.render(mi.load_dict(d), spp=256))
    ref = mitsuba_peer.read_exr(mi, f"ref_plate_{name}.exr")
    m = lambda a: float(np.mean(a))  # noqa: E731
    print(f"{name}: smlt {m(ref):.5f} vs exact {m(gltf_img):.5f} ({100 * (m(ref) / m(gltf_img) - 1):+.2f} %); "
          f"principled exact {m(principled_img):.5f}, render {m(rendered):.5f}: expected "
          f"{100 * (m(principled_img) / m(gltf_img) - 1):+.1f} %, measured {100 * (m(rendered) / m(ref) - 1):+.1f} %")
PY
"$smlt" reference materials.gltf --device cpu --spp 2048 "${size[@]}" --out ref_materials.exr | { grep -E "noise" || true; }
python3 "$root/scripts/peers/mitsuba_peer.py" materials.gltf "${size[@]}" --variant llvm_ad_rgb \
    --reference ref_materials.exr --converged 2048 --label materials | tail -1
