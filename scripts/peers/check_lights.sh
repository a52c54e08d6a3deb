#!/usr/bin/env bash
# Mitsuba 3 against smlt's path tracer under each punctual light of a scene, one light at a
# time and all together: the means and RMSEs that docs/results.md quotes.
#   scripts/peers/check_lights.sh [SCENE.gltf] [OUT]   (default: scenes/lamps.gltf, /tmp/check-lights)
# Needs smlt built (cargo build --release) and the peers' Python packages (requirements.txt).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
scene="$(realpath "${1:-$root/scenes/lamps.gltf}")"
out="${2:-/tmp/check-lights}"
smlt="${CARGO_TARGET_DIR:-$root/target}/release/smlt"
size=(--width 128 --height 96 --max-depth 10)
mkdir -p "$out"
cd "$out"
# One file per light: the scene with every other light's node stripped of its light.
python3 - "$scene" <<'PY'
import json, os, sys
doc = json.load(open(sys.argv[1]))
for i, light in enumerate(doc["extensions"]["KHR_lights_punctual"]["lights"]):
    one = json.loads(json.dumps(doc))
    for node in one["nodes"]:
        ext = node.get("extensions", {}).get("KHR_lights_punctual")
        if ext is not None and ext["light"] != i:
            del node["extensions"]
    json.dump(one, open(f"light{i}_{light['type']}.gltf", "w"))
PY
for variant in light*_*.gltf "$scene"; do
    name="$(basename "$variant" .gltf)"
    "$smlt" reference "$variant" --spp 4096 "${size[@]}" --out "ref_$name.exr" | grep -E "noise"
    python3 "$root/scripts/peers/mitsuba_peer.py" "$variant" "${size[@]}" --reference "ref_$name.exr" \
        --converged 4096 --label "$name" | tail -1
done
