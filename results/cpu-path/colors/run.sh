#!/usr/bin/env bash
# The check of docs/results.md "Vertex colours: Blender's colour attribute": smlt on Blender's
# export of a colour attribute its material reads (COLOR_0) against Blender's four materials of
# those colours, and against Cycles (scripts/peers/check_blender_baked.py vertex_colors). Needs
# smlt built (cargo build --release) and the peers' Python packages
# (scripts/peers/requirements.txt).
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
out="${1:-/tmp/check-colors}"
here="$(cd "$(dirname "$0")" && pwd)"
mkdir -p "$out"
python3 "$root/scripts/peers/check_blender_baked.py" vertex_colors "$out" --spp 4096 --cycles-samples 1024 | tee "$here/check.txt"
