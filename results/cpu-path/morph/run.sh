#!/usr/bin/env bash
# The check of docs/results.md "Morph targets: Blender's shape keys": smlt on Blender's export of
# shape keys (morph targets and weights) against Blender's own evaluation of them and against
# Cycles (scripts/peers/check_blender_baked.py shape_keys). Needs smlt built (cargo build
# --release) and the peers' Python packages (scripts/peers/requirements.txt).
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
out="${1:-/tmp/check-morph}"
here="$(cd "$(dirname "$0")" && pwd)"
mkdir -p "$out"
python3 "$root/scripts/peers/check_blender_baked.py" shape_keys "$out" --spp 4096 --cycles-samples 1024 | tee "$here/check.txt"
