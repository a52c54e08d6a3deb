#!/usr/bin/env bash
# The check of docs/results.md "Skins: Blender's posed armature": smlt on Blender's export of a
# posed armature (a skin whose joints hold the pose) against Blender's own evaluation of the pose
# and against Cycles (scripts/peers/check_blender_baked.py armature). Needs smlt built (cargo
# build --release) and the peers' Python packages (scripts/peers/requirements.txt).
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
out="${1:-/tmp/check-skin}"
here="$(cd "$(dirname "$0")" && pwd)"
mkdir -p "$out"
python3 "$root/scripts/peers/check_blender_baked.py" armature "$out" --spp 4096 --cycles-samples 1024 | tee "$here/check.txt"
