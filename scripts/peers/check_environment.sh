#!/usr/bin/env bash
# Mitsuba 3 against smlt under the environment light: the `caustic` scene without its spot lamp
# (glass, a diffuse floor and wall, an area lamp) lit by a lat-long sky (a smooth gradient with
# a sun, written here as sky.exr, turned 40° about +Y, strength 1.5) and by a constant colour,
# and a grey plate alone under the sky: the means and RMSEs that docs/results.md quotes.
#   scripts/peers/check_environment.sh [OUT]   (default: /tmp/check-environment)
# Needs smlt built (cargo build --release) and the peers' Python packages (requirements.txt).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
out="${1:-/tmp/check-environment}"
smlt="${CARGO_TARGET_DIR:-$root/target}/release/smlt"
size=(--width 128 --height 96 --max-depth 12)
mkdir -p "$out"
cd "$out"
"$smlt" scene caustic --out caustic.gltf >/dev/null
PYTHONPATH="$root/scripts/peers" python3 - <<'PY'
import json

import gltf_scene
import numpy as np
import OpenEXR

# The sky: blue above the horizon growing paler towards it, a dim ground, a sun (a Gaussian
# 1.4° wide, 25° above the horizon) holding about half the power; smooth at the texels'
# scale, where Mitsuba's bilinear lookup and smlt's nearest texel agree. Mitsuba spreads the
# rows from pole to pole (row j at θ = π j / (h − 1), where smlt, pbrt and the usual texel
# convention put its centre at π (j + ½) / h): a feature's solid angle is h / (h − 1) times
# smlt's there, +0.2 % at this height.
w, h = 1024, 512
v, u = np.meshgrid((np.arange(h) + 0.5) / h, (np.arange(w) + 0.5) / w, indexing="ij")
sky = np.zeros((h, w, 3), np.float32)
t = np.clip(v * 2, 0, 1)[..., None]
sky[:] = np.where(v[..., None] < 0.5, (1 - t) * [0.25, 0.45, 1.0] + t * [0.8, 0.85, 0.9], [0.12, 0.1, 0.08])
d2 = ((u - 0.3) * w) ** 2 + ((v - (0.5 - 25 / 180)) * h) ** 2  # in texels
sky += (400.0 * np.exp(-d2 / (2 * 8.0 ** 2)))[..., None] * np.array([1.0, 0.9, 0.75], np.float32)
header = OpenEXR.Header(w, h)
OpenEXR.OutputFile("sky.exr", header).writePixels({c: sky[..., i].astype(np.float32).tobytes() for i, c in enumerate("RGB")})

doc = gltf_scene.without_punctual_lights(json.load(open("caustic.gltf")))
json.dump(doc, open("sky_caustic.gltf", "w"))
PY
python3 - <<'PY'
import base64, json, struct
# A grey Lambertian plate seen from above at an angle: only the environment lights it.
p = [(-1, 0, 1), (1, 0, 1), (1, 0, -1), (-1, 0, -1)]
data = b"".join(struct.pack("<3f", *v) for v in p) + struct.pack("<6H", 0, 1, 2, 0, 2, 3)
doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
       "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
       "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
       "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 0, 1]},
                     {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
       # Lambert: glTF's BRDF with no metal and no dielectric layer
       "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0},
                      "extensions": {"KHR_materials_specular": {"specularFactor": 0}}}],
       "extensionsUsed": ["KHR_materials_specular"],
       "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
       "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.01}}],
       # the camera at (0, 1.6, 1.6) looking at the origin: a rotation of -45° about X
       "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 1.6, 1.6], "rotation": [-0.38268343, 0, 0, 0.92387953]}]}
json.dump(doc, open("plate.gltf", "w"))
PY
run() {
    local name="$1" scene="$2"
    shift 2
    "$smlt" reference "$scene" --device cpu --spp 2048 "${size[@]}" "$@" --out "ref_$name.exr" | { grep -E "noise" || true; }
    python3 "$root/scripts/peers/mitsuba_peer.py" "$scene" "${size[@]}" --reference "ref_$name.exr" \
        --converged 2048 --label "$name" "$@" | tail -1
}
run plate_sky plate.gltf --environment sky.exr --environment-strength 1.5 --environment-rotation 40
run caustic_sky sky_caustic.gltf --environment sky.exr --environment-strength 1.5 --environment-rotation 40
run caustic_constant sky_caustic.gltf --environment 0.5,0.6,0.8
