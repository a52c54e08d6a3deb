#!/usr/bin/env bash
# The auto bench again after the packed pixel's bits (shared::layout::PIXEL_BITS_FLIP), which
# made the Metropolis methods 1.04-1.23x faster on the CPU backend: every method of the auto
# bench on its seven views (3 runs of 8 s each), then Mitsuba 3's and Cycles' timed runs on the
# same references in the same session, then each view's tables with all rows (VIEW/tables.md)
# and the docs' table (table.md). Run from the folder holding the auto bench's references
# (ref_VIEW.exr) and generated scenes (`smlt scene sponza-banner|sunblind|slit|atrium`), as
# /tmp/autobench in the session; SMLT, PY (Python with mitsuba and bpy) from the environment.
set -uo pipefail
HERE=$(dirname "$(readlink -f "$0")")
PEERS=$HERE/../../../../scripts/peers
SC=${SC:-/work/shared/scenes}
SMLT=${SMLT:-smlt}
PY=${PY:-python3}
views=(
    "sibenik $SC/sibenik/sibenik.gltf 1 sibenik"
    "sponza $SC/sponza_dabrovic/sponza_dabrovic.gltf 1 sponza_dabrovic"
    "banner2 sponza_banner.gltf 2 sponza_banner"
    "sunblind sunblind.gltf 1 sunblind"
    "slit slit.gltf 1 slit"
    "atrium1 atrium.gltf 1 atrium"
    "atrium2 atrium.gltf 2 atrium"
)
lscpu | grep 'Model name' > "$HERE/machine.txt"
mkdir -p "$HERE/mitsuba" "$HERE/cycles"
for v in "${views[@]}"; do
    read -r name scene view _ <<<"$v"
    "$SMLT" bench --device cpu --scenes "$scene:$view" --methods auto,pt,naive,path-naive,s3 --seconds 8 \
        --repeats 3 --width 128 --height 72 --max-depth 10 --reference "ref_$name.exr" --out "bench_$name" |
        tail -1
    mkdir -p "$HERE/$name"
    cp "bench_$name"/{results.csv,passes.csv,auto.csv} "$HERE/$name/"
    cp "bench_$name/tables.md" "$HERE/$name/bench_tables.md"
done
for v in "${views[@]}"; do
    read -r name scene view label <<<"$v"
    "$PY" "$PEERS/mitsuba_peer.py" "$scene" --view "$view" --width 128 --height 72 --max-depth 10 \
        --seconds 8 --repeats 3 --reference "ref_$name.exr" --label "$label" --out "$HERE/mitsuba/$name.csv" \
        > /dev/null 2>&1
done
# Cycles: not the banner view nor the atrium's two (smlt's Phong lobe, which it has no closure for).
for v in "${views[@]:0:2}" "${views[@]:3:2}"; do
    read -r name scene view label <<<"$v"
    "$PY" "$PEERS/cycles_peer.py" "$scene" --view "$view" --width 128 --height 72 --max-depth 10 \
        --seconds 8 --repeats 3 --reference "ref_$name.exr" --label "$label" --out "$HERE/cycles/$name.csv" \
        > /dev/null 2>&1
done
for v in "${views[@]}"; do
    read -r name _ <<<"$v"
    {
        cat "$HERE/$name/results.csv"
        tail -n +2 "$HERE/mitsuba/$name.csv"
        [ -f "$HERE/cycles/$name.csv" ] && tail -n +2 "$HERE/cycles/$name.csv"
    } > "$HERE/$name/all.csv"
    "$SMLT" plot "$HERE/$name/all.csv" --out "plot_$name" > /dev/null
    cp "plot_$name/tables.md" "$HERE/$name/tables.md"
done
python3 "$HERE/table.py" "$HERE" > "$HERE/table.md"
