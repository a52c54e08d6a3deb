#!/usr/bin/env bash
# The check of docs/results.md "Draco: Blender's exporter": smlt on Blender's Draco export of the
# round-trip scene against the uncompressed export, Google's decoder and Cycles
# (scripts/peers/check_blender_draco.py). Needs smlt built (cargo build --release), the peers'
# Python packages (scripts/peers/requirements.txt) and `npm install @gltf-transform/cli` (on PATH
# or NODE_PATH). gltf-transform's Draco files are checked by ../optimised/run.sh.
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
out="${1:-/tmp/check-draco}"
here="$(cd "$(dirname "$0")" && pwd)"
mkdir -p "$out"
python3 "$root/scripts/peers/check_blender_draco.py" "$out" --spp 4096 --cycles-samples 1024 \
    | grep -v -E '^(\s*$|[0-9:]+ \| INFO|DracoEncoder)' | tee "$here/check.txt"
