#!/usr/bin/env bash
# Mitsuba 3 against smlt under glass: the `caustic` scene without its spot lamp (where
# Mitsuba's path tracer renders every path: its area lamp's caustic by BSDF sampling), and each
# glass alone in it (the clear solid ball, the absorbing amber block, the thin pane, the others
# removed), and the clear ball made rough (roughnessFactor 0.5): the means and RMSEs that
# docs/results.md quotes.
#   scripts/peers/check_glass.sh [OUT]   (default: /tmp/check-glass)
# Needs smlt built (cargo build --release) and the peers' Python packages (requirements.txt).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
out="${1:-/tmp/check-glass}"
smlt="${CARGO_TARGET_DIR:-$root/target}/release/smlt"
size=(--width 128 --height 96 --max-depth 12)
mkdir -p "$out"
cd "$out"
"$smlt" scene caustic --out caustic.gltf >/dev/null
# The scene without punctual lights, and one file per glass material with the other glass gone.
PYTHONPATH="$root/scripts/peers" python3 - <<'PY'
import json

import gltf_scene

doc = gltf_scene.without_punctual_lights(json.load(open("caustic.gltf")))
json.dump(doc, open("glass_all.gltf", "w"))
glass = [i for i, m in enumerate(doc["materials"]) if "KHR_materials_transmission" in m.get("extensions", {})]
for g in glass:
    one = json.loads(json.dumps(doc))
    name = one["materials"][g]["name"].split()[0]
    keep = [n for n in one["nodes"] if "mesh" not in n
            or one["meshes"][n["mesh"]]["primitives"][0].get("material") not in set(glass) - {g}]
    one["nodes"] = keep
    one["scenes"][0]["nodes"] = list(range(len(keep)))
    json.dump(one, open(f"glass_{name}.gltf", "w"))
PY
# The clear ball made rough (roughnessFactor 0.5: GGX α 0.25), alone.
python3 - <<'PY'
import json
doc = json.load(open("glass_clear.gltf"))
for m in doc["materials"]:
    if "KHR_materials_transmission" in m.get("extensions", {}):
        m["pbrMetallicRoughness"]["roughnessFactor"] = 0.5
json.dump(doc, open("glass_frosted.gltf", "w"))
PY
for variant in glass_*.gltf; do
    name="$(basename "$variant" .gltf)"
    "$smlt" reference "$variant" --spp 4096 "${size[@]}" --out "ref_$name.exr" | { grep -E "noise" || true; }
    python3 "$root/scripts/peers/mitsuba_peer.py" "$variant" "${size[@]}" --reference "ref_$name.exr" \
        --converged 4096 --label "$name" | tail -1
done
