#!/usr/bin/env bash
# The check of docs/results.md "Anisotropy: Mitsuba 3": smlt's KHR_materials_anisotropy on three
# mapped plates against their exact images through the `smlt_gltf` Mitsuba plugin
# (scripts/peers/check_anisotropy.sh). Needs smlt built (cargo build --release), the peers'
# Python packages (scripts/peers/requirements.txt) and DRJIT_LIBLLVM_PATH (a libLLVM >= 16).
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
here="$(cd "$(dirname "$0")" && pwd)"
"$root/scripts/peers/check_anisotropy.sh" "${1:-/tmp/check-anisotropy}" | tee "$here/check.txt"
