#!/usr/bin/env bash
# The check of docs/results.md "KTX2 textures": smlt on files with KTX2 textures (Binomial's
# Basis Universal encoder; ETC1S and UASTC with Zstandard) against the same files transcoded by
# Binomial's transcoder, against the files as written, and against Cycles
# (scripts/peers/check_ktx2.py). Needs smlt built (cargo build --release), the peers' Python
# packages (scripts/peers/requirements.txt) and
# `npm install @gltf-transform/cli ktx2-encoder@0.6.0 three@0.170.0` (NODE_PATH names its
# node_modules).
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
out="${1:-/tmp/check-ktx2}"
here="$(cd "$(dirname "$0")" && pwd)"
mkdir -p "$out"
python3 "$root/scripts/peers/check_ktx2.py" "$out" --spp 1024 --cycles-samples 1024 | tee "$here/check.txt"
