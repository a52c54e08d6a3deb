#!/usr/bin/env bash
# Mitsuba 3 against smlt on a rough thin wall of glass (KHR_materials_transmission without
# KHR_materials_volume, roughnessFactor > 0): the means and RMSEs that docs/results.md quotes.
# A tinted glass plate of roughness 0.3 and 0.6 filling the view under a sun above it (what it
# reflects) and under a sun below it (what it lets through): smlt's reference against the
# plate's exact image (one bounce: the BSDF at each pixel's directions × the sun's irradiance)
# through `smlt_thin` (mitsuba_thin.py, written from the extension's text), and against the
# smooth thin wall's image there, which says how far the check could miss (a smooth wall
# passes the sun's light on to no pixel). Then each plate under a blue sky too (--environment
# 0.5,0.6,0.8), lit from both sides, where the lobes' sampling counts: smlt's reference
# against Mitsuba's render through the plugin, which samples its own way.
#   scripts/peers/check_thin_wall.sh [OUT]   (default: /tmp/check-thin-wall)
# Needs smlt built (cargo build --release), the peers' Python packages (requirements.txt) and
# DRJIT_LIBLLVM_PATH (a libLLVM >= 16; the plugin needs Mitsuba's llvm_ad_rgb variant).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
out="${1:-/tmp/check-thin-wall}"
smlt="${CARGO_TARGET_DIR:-$root/target}/release/smlt"
size=(--width 128 --height 96 --max-depth 12)
: "${DRJIT_LIBLLVM_PATH:?set DRJIT_LIBLLVM_PATH to a libLLVM >= 16 (scripts/peers/README.md)}"
export DRJIT_LIBLLVM_PATH
mkdir -p "$out"
cd "$out"
PYTHONPATH="$root/scripts/peers" python3 - <<'PY'
import plate_scene
for roughness in ["0.3", "0.6"]:
    pbr = {"baseColorFactor": [0.9, 0.8, 0.6, 1], "metallicFactor": 0.0, "roughnessFactor": float(roughness)}
    glass = {"KHR_materials_transmission": {"transmissionFactor": 1.0}}
    for sun, to_sun in [("above", plate_scene.TO_SUN), ("below", (0.4, -1.0, 0.3))]:
        plate_scene.write(f"plate_{roughness}_{sun}.gltf", "frosted", pbr, glass, to_sun=to_sun)
PY
for roughness in 0.3 0.6; do
    for sun in above below; do
        name="${roughness}_$sun"
        "$smlt" reference "plate_$name.gltf" --device cpu --spp 256 "${size[@]}" --out "ref_plate_$name.exr" 2>&1 | { grep -E "noise" | sed "s/^/$name: /" || true; }
    done
    "$smlt" reference "plate_${roughness}_below.gltf" --device cpu --spp 1024 "${size[@]}" --environment 0.5,0.6,0.8 \
        --out "ref_sky_$roughness.exr" 2>&1 | { grep -E "noise" | sed "s/^/$roughness under the sky: /" || true; }
done
PYTHONPATH="$root/scripts/peers" python3 - "${size[@]}" <<'PY'
import sys, tempfile
import mitsuba as mi
import numpy as np
mi.set_variant("llvm_ad_rgb")
import gltf_scene, mitsuba_peer, mitsuba_thin, plate_scene
mitsuba_thin.register()
w, h, depth = int(sys.argv[2]), int(sys.argv[4]), int(sys.argv[6])
m = lambda a: float(np.mean(a))  # noqa: E731
print("plate: smlt | exact (difference, RMSE) | smooth wall's exact (RMSE)")
skies = []
for roughness in ["0.3", "0.6"]:
    for sun in ["above", "below"]:
        name = f"{roughness}_{sun}"
        scene = gltf_scene.load(f"plate_{name}.gltf")
        mat, light = scene.materials[1], scene.lights[0]
        with tempfile.TemporaryDirectory() as folder:
            d = mitsuba_peer.scene_dict(mi, scene, 1, w, h, depth, folder)
            key = [k for k in d if k.startswith("mesh")][0]
            # The smooth wall (what smlt rendered before): Mitsuba's own thin dielectric.
            smooth = {"type": "thindielectric", "int_ior": mat.ior, "ext_ior": 1.0,
                      "specular_transmittance": {"type": "rgb", "value": list(mat.albedo)}}
            d[key]["bsdf"] = {"type": "smlt_thin", "alpha": float(roughness) ** 2, "ior": mat.ior,
                              "tint": list(mat.albedo)}
            exact = plate_scene.exact_image(mi, d, light, w, h)
            if sun == "below":
                d["environment"] = mitsuba_peer.environment_dict(mi, "0.5,0.6,0.8", 1.0, 0.0)
                sky = np.array(mi.render(mi.load_dict(d), spp=1024))
                del d["environment"]
            d[key]["bsdf"] = smooth
            smooth_img = plate_scene.exact_image(mi, d, light, w, h)
        ref = mitsuba_peer.read_exr(mi, f"ref_plate_{name}.exr")
        rmse = lambda a: float(np.sqrt(np.mean((ref - a) ** 2)))  # noqa: E731
        print(f"roughness {roughness}, sun {sun}: {m(ref):.5f} | {m(exact):.5f} ({100 * (m(ref) / m(exact) - 1):+.2f} %, "
              f"{rmse(exact):.1e}) | {m(smooth_img):.5f} ({rmse(smooth_img):.1e})")
        if sun == "below":
            ref_sky = mitsuba_peer.read_exr(mi, f"ref_sky_{roughness}.exr")
            rms = float(np.sqrt(np.mean((ref_sky - sky) ** 2)))
            skies.append(f"roughness {roughness} under the sky and the sun below: smlt {m(ref_sky):.5f}, Mitsuba "
                         f"(1024 spp) {m(sky):.5f} ({100 * (m(sky) / m(ref_sky) - 1):+.2f} %), RMSE {rms:.1e}")
print("\n".join(skies))
PY
