#!/usr/bin/env bash
# The check of docs/results.md "Optimised files": smlt on the files gltfpack and gltf-transform
# write, against gltf-transform's decoders and Cycles (scripts/peers/check_optimised.py).
# Needs smlt built (cargo build --release), the peers' Python packages
# (scripts/peers/requirements.txt) and `npm install gltfpack @gltf-transform/cli` on PATH.
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
out="${1:-/tmp/check-optimised}"
here="$(cd "$(dirname "$0")" && pwd)"
mkdir -p "$out"
python3 "$root/scripts/peers/tangent_scene.py" "$out/tangent_scene" > /dev/null
python3 "$root/scripts/peers/normal_map_scene.py" "$out/normal_map_scene" > /dev/null
python3 "$root/scripts/peers/check_optimised.py" "$out/small" --spp 512 \
    --scene tangents="$out/tangent_scene/tangents.gltf" \
    --scene normal_map="$out/normal_map_scene/normal_map.gltf" | tee "$here/check.txt"
# Sibenik (../shared/scenes, not committed): a large mesh, fewer samples.
python3 "$root/scripts/peers/check_optimised.py" "$out/sibenik" --spp 256 --no-default-scenes \
    --scene sibenik="$root/../shared/scenes/sibenik/sibenik.gltf" | tee "$here/check_sibenik.txt"
