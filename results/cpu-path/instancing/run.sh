#!/usr/bin/env bash
# The check of docs/results.md "Instanced meshes": the embedded Cornell box with its glossy block
# replaced by six copies (six nodes of one mesh, each its own TRS), then `gltf-transform instance`
# of that file (one node with EXT_mesh_gpu_instancing, which glTF-Transform does not mark
# required); smlt renders both (`smlt reference`, seed 1) and the images must be identical.
# Needs smlt built (cargo build --release), the peers' Python packages and
# `npm install @gltf-transform/cli` (GLTF_TRANSFORM or PATH).
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
out="${1:-/tmp/check-instancing}"
here="$(cd "$(dirname "$0")" && pwd)"
smlt="${CARGO_TARGET_DIR:-$root/target}/release/smlt"
transform="${GLTF_TRANSFORM:-gltf-transform}"
mkdir -p "$out"
"$smlt" scene cornell --out "$out/cornell.gltf" >/dev/null
python3 - "$out" <<'PY'
import json, math, sys
out = sys.argv[1]
d = json.load(open(f"{out}/cornell.gltf"))
glossy = next(i for i, m in enumerate(d["meshes"]) if m.get("name") == "glossy")
d["scenes"][0]["nodes"] = [n for n in d["scenes"][0]["nodes"] if d["nodes"][n].get("mesh") != glossy]
for k in range(6):
    a = k * math.pi / 3
    d["nodes"].append({"mesh": glossy, "translation": [0.6 * math.cos(a) + 0.2, 0, 0.6 * math.sin(a) + 0.2],
                       "scale": [0.3, 0.3 + 0.1 * k, 0.3], "rotation": [0, math.sin(a / 2), 0, math.cos(a / 2)]})
    d["scenes"][0]["nodes"].append(len(d["nodes"]) - 1)
json.dump(d, open(f"{out}/copies.gltf", "w"))
PY
"$transform" instance "$out/copies.gltf" "$out/instanced.gltf" 2>&1 | grep -i "instance:" | tee "$here/check.txt"
python3 -c "import json, sys; d = json.load(open(sys.argv[1])); print('extensionsUsed', d.get('extensionsUsed'), 'extensionsRequired', d.get('extensionsRequired'))" \
    "$out/instanced.gltf" | tee -a "$here/check.txt"
for f in copies instanced; do
    "$smlt" reference "$out/$f.gltf" --device cpu --spp 256 --width 96 --height 96 --seed 1 --out "$out/$f.exr" 2>&1 |
        grep -iE "warning" | tee -a "$here/check.txt" || true
done
python3 - "$out" "$root/scripts/peers" <<'PY' | tee -a "$here/check.txt"
import sys
out, peers = sys.argv[1], sys.argv[2]
sys.path.insert(0, peers)
from cycles_peer import read_exr
a, b = read_exr(f"{out}/copies.exr"), read_exr(f"{out}/instanced.exr")
print(f"smlt on the instanced file against the six copies: {100 * float((a == b).all(-1).mean()):.1f} % of pixels identical")
PY
