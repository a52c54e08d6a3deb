#!/usr/bin/env bash
# (Run at 2f0190b; SMLT built at 2f0190b, OLD at a022f10.)
# auto keeping the chosen method's pilot where it rendered the render's pixels: every method of
# the auto bench on its seven views (3 runs of 8 s each, 128×72, so the pilot is at the
# render's size), and on each view right after it the previous commit's auto (the same choice,
# its pilot discarded) on the same reference, so that both autos are measured in one session
# against the same single methods. Run from the folder holding the references (ref_VIEW.exr,
# `smlt reference SCENE --view V --spp N --width 128 --height 72 --max-depth 10 --seed 1001
# --device cpu`, N as in docs/results.md) and sponza_banner.gltf (`smlt scene sponza-banner`);
# SMLT (this commit) and OLD (the previous) from the environment. Tables: table.py.
set -uo pipefail
HERE=$(dirname "$(readlink -f "$0")")
ROOT=$HERE/../../../..
SC=${SC:-/work/shared/scenes}
SMLT=${SMLT:-smlt}
OLD=${OLD:?the previous commit\'s smlt}
views=(
    "sibenik $SC/sibenik/sibenik.gltf 1"
    "sponza $SC/sponza_dabrovic/sponza_dabrovic.gltf 1"
    "banner2 sponza_banner.gltf 2"
    "sunblind $ROOT/scenes/sunblind.gltf 1"
    "slit $ROOT/scenes/slit.gltf 1"
    "atrium1 $ROOT/scenes/atrium.gltf 1"
    "atrium2 $ROOT/scenes/atrium.gltf 2"
)
lscpu | grep 'Model name' > "$HERE/machine.txt"
for v in "${views[@]}"; do
    read -r name scene view <<<"$v"
    "$SMLT" bench --device cpu --scenes "$scene:$view" --methods auto,pt,naive,path-naive,s3 --seconds 8 \
        --repeats 3 --width 128 --height 72 --max-depth 10 --reference "ref_$name.exr" --out "kept_$name" |
        tail -1
    "$OLD" bench --device cpu --scenes "$scene:$view" --methods auto --seconds 8 \
        --repeats 3 --width 128 --height 72 --max-depth 10 --reference "ref_$name.exr" --out "kold_$name" |
        tail -1
    mkdir -p "$HERE/$name"
    cp "kept_$name"/{results.csv,auto.csv} "$HERE/$name/"
    cp "kept_$name/tables.md" "$HERE/$name/bench_tables.md"
    cp "kold_$name/results.csv" "$HERE/$name/old_auto_results.csv"
    cp "kold_$name/auto.csv" "$HERE/$name/old_auto.csv"
    cp "kold_$name/tables.md" "$HERE/$name/old_bench_tables.md"
done
