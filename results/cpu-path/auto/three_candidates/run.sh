#!/usr/bin/env bash
# (Run at e33e1a0, reverted by 06e9264; SMLT built at e33e1a0, OLD at a022f10.)
# auto with the chains over the path tracer's estimate (`path-naive`) as a third candidate,
# weighed only where the path tracer's pilot met no fireflies: every method of the auto bench on
# its seven views (3 runs of 8 s each), and on each view right after it the previous commit's
# auto (two candidates, `pt` and `naive`) on the same reference, so that both autos are
# measured in one session against the same single methods. Run from the folder holding the
# references (ref_VIEW.exr, `smlt reference SCENE --view V --spp N --width 128 --height 72
# --max-depth 10 --seed 1001 --device cpu`, N as in docs/results.md) and sponza_banner.gltf
# (`smlt scene sponza-banner`); SMLT (this commit) and OLD (the previous) from the environment.
set -uo pipefail
HERE=$(dirname "$(readlink -f "$0")")
ROOT=$HERE/../../../..
SC=${SC:-/work/shared/scenes}
SMLT=${SMLT:-smlt}
OLD=${OLD:?the previous commit\'s smlt}
views=(
    "sunblind $ROOT/scenes/sunblind.gltf 1"
    "atrium1 $ROOT/scenes/atrium.gltf 1"
    "sibenik $SC/sibenik/sibenik.gltf 1"
    "slit $ROOT/scenes/slit.gltf 1"
    "banner2 sponza_banner.gltf 2"
    "atrium2 $ROOT/scenes/atrium.gltf 2"
    "sponza $SC/sponza_dabrovic/sponza_dabrovic.gltf 1"
)
lscpu | grep 'Model name' > "$HERE/machine.txt"
for v in "${views[@]}"; do
    read -r name scene view <<<"$v"
    "$SMLT" bench --device cpu --scenes "$scene:$view" --methods auto,pt,naive,path-naive,s3 --seconds 8 \
        --repeats 3 --width 128 --height 72 --max-depth 10 --reference "ref_$name.exr" --out "bench_$name" |
        tail -1
    "$OLD" bench --device cpu --scenes "$scene:$view" --methods auto --seconds 8 \
        --repeats 3 --width 128 --height 72 --max-depth 10 --reference "ref_$name.exr" --out "old_$name" |
        tail -1
    mkdir -p "$HERE/$name"
    cp "bench_$name"/{results.csv,auto.csv} "$HERE/$name/"
    cp "bench_$name/tables.md" "$HERE/$name/bench_tables.md"
    cp "old_$name/results.csv" "$HERE/$name/old_auto_results.csv"
    cp "old_$name/auto.csv" "$HERE/$name/old_auto.csv"
    cp "old_$name/tables.md" "$HERE/$name/old_bench_tables.md"
done
