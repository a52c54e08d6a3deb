#!/usr/bin/env bash
# Blender's Cycles (CPU path tracer, through Blender's own glTF importer) on four of the auto bench's
# seven views, 3 runs of 8 s, the bench's references (docs/results.md, "--method auto at equal time"):
# first each view once at many samples against the reference (a peer's numbers count only where
# that agrees), then the timed runs, then each view's tables beside the bench's and Mitsuba's rows.
# Run from the folder holding the references and generated scenes (/tmp/autobench in the session).
set -uo pipefail
P=$(dirname "$(readlink -f "$0")")/../../../../scripts/peers/cycles_peer.py
HERE=$(dirname "$(readlink -f "$0")")
SC=${SC:-/work/shared/scenes}
SMLT=${SMLT:-smlt}
PY=${PY:-python3}
views=(
    "sibenik $SC/sibenik/sibenik.gltf 1 sibenik"
    "sponza $SC/sponza_dabrovic/sponza_dabrovic.gltf 1 sponza_dabrovic"
    "sunblind sunblind.gltf 1 sunblind"
    "slit slit.gltf 1 slit"
)
# Not the banner view nor the atrium's two: their banners are smlt's Phong lobe, which Cycles has
# no closure for (cycles_peer.py refuses them; Blender's importer would read them as Lambert).
mkdir -p cycles
lscpu | grep 'Model name' > cycles/machine.txt
for v in "${views[@]}"; do
    read -r name scene view label <<<"$v"
    "$PY" "$P" "$scene" --view "$view" --width 128 --height 72 --max-depth 10 --reference "ref_$name.exr" \
        --converged 1024 --label "$label" 2>&1 | grep " spp in " | tee -a cycles/converged.txt
done
for v in "${views[@]}"; do
    read -r name scene view label <<<"$v"
    "$PY" "$P" "$scene" --view "$view" --width 128 --height 72 --max-depth 10 --seconds 8 --repeats 3 \
        --reference "ref_$name.exr" --label "$label" --out "cycles/$name.csv" > "cycles/$name.log" 2>&1
    echo "$name $(tail -1 "cycles/$name.csv" | cut -d, -f8,11)"
done
# Each view's tables: the bench's rows, Mitsuba's (../mitsuba/) and Cycles'.
for v in "${views[@]}"; do
    read -r name _ <<<"$v"
    (cat "$HERE/../$name/results.csv"; tail -n +2 "$HERE/../mitsuba/$name.csv"; tail -n +2 "cycles/$name.csv") \
        > "cycles/all_$name.csv"
    "$SMLT" plot "cycles/all_$name.csv" --out "cycles/plot_$name" > /dev/null
    cp "cycles/plot_$name/tables.md" "cycles/tables_$name.md"
done
echo CYCLES_DONE
