#!/usr/bin/env bash
# The paper's Table 3 (million mutations/s) and Figure 7 (speedup over naive) on a Vulkan GPU in
# one call: `smlt bench` of naive, s2–s6 and rc2–rc64 on Sibenik and the Sponza with the
# banner (both views) at 1920×1080, with the per-pass profile ("inside an iteration") and the
# ray-casting ceiling, every table and plot in one folder.
#
#   scripts/gpu-tables.sh [--short] [OUT]      (OUT: default gpu-tables)
#
# --short: the same runs at 64×36 for 1 s each (1 024 candidates, 4 096 bootstrap samples), to
# check the script on any Vulkan device (CI runs it on lavapipe). Without it the whole run takes about 6 minutes on a big GPU (a tested
# budget of 8): SECONDS_PER_METHOD (default 5) and REFERENCE_SPP (default 256) change it.
# SMLT: the smlt binary (default: built here); SHARED_SCENES: the folder holding sibenik/ and
# sponza_dabrovic/ (default ../shared/scenes). Writes OUT/device.txt, OUT/bench.log,
# OUT/results.csv, OUT/passes.csv, OUT/tables.md, OUT/speedup.png, OUT/error_*.png and
# OUT/run.txt (the command, the device and the wall time).
set -euo pipefail
cd "$(dirname "$0")/.."

short=0
if [ "${1:-}" = --short ]; then
    short=1
    shift
fi
out=${1:-gpu-tables}
scenes=${SHARED_SCENES:-../shared/scenes}
sibenik="$scenes/sibenik/sibenik.gltf"
dabrovic="$scenes/sponza_dabrovic/sponza_dabrovic.gltf"
for f in "$sibenik" "$dabrovic"; do
    if [ ! -f "$f" ]; then
        echo "error: $f not found: set SHARED_SCENES to the folder holding sibenik/ and sponza_dabrovic/" >&2
        exit 1
    fi
done
if [ -z "${SMLT:-}" ]; then
    cargo build --release --quiet --bin smlt
    SMLT="${CARGO_TARGET_DIR:-target}/release/smlt"
fi
if [ "$short" = 1 ]; then
    size=(--width 64 --height 36 --candidates 1024 --bootstrap 4096)
    seconds=1
    spp=16
else
    size=(--width 1920 --height 1080)
    seconds=${SECONDS_PER_METHOD:-5}
    spp=${REFERENCE_SPP:-256}
fi
mkdir -p "$out"
start=$(date +%s)
"$SMLT" devices >"$out/device.txt" 2>&1
"$SMLT" scene sponza-banner --from "$dabrovic" --out "$out/sponza_banner.gltf" >/dev/null
command=("$SMLT" bench --device vulkan
    --scenes "$sibenik:1,$out/sponza_banner.gltf:1,$out/sponza_banner.gltf:2"
    --methods naive,s2,s3,s4,s5,s6,rc2,rc4,rc8,rc16,rc32,rc64
    --seconds "$seconds" "${size[@]}" --reference-spp "$spp" --out "$out")
if ! "${command[@]}" >"$out/bench.log" 2>&1; then
    echo "error: the bench failed; its last lines (all of it in $out/bench.log):" >&2
    grep -v XDG_RUNTIME_DIR "$out/bench.log" | tail -5 >&2
    exit 1
fi
wall=$(($(date +%s) - start))
{
    echo "command: ${command[*]}"
    grep -m1 '^bench on' "$out/bench.log" || true
    echo "wall time: $wall s"
} >"$out/run.txt"
echo "wrote $out/tables.md, $out/passes.csv and $out/speedup.png in $wall s"
