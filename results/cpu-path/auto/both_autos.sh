#!/usr/bin/env bash
# Two autos on the auto bench's seven views, measured in one session against the same single
# methods: per view SMLT's bench of auto, pt, naive, path-naive and s3 (3 runs of 8 s each,
# 128×72, max depth 10), then right after it OLD's auto on the same reference. Each view's
# results go to DIR/VIEW (results.csv, auto.csv, bench_tables.md and OLD's old_auto_results.csv,
# old_auto.csv, old_bench_tables.md); both_autos_table.py prints their table.
#   SMLT=… OLD=… both_autos.sh DIR NEW_PREFIX OLD_PREFIX
# Run from the folder holding the references (ref_VIEW.exr, `smlt reference SCENE --view V --spp
# N --width 128 --height 72 --max-depth 10 --seed 1001 --device cpu`, N as in docs/results.md)
# and sponza_banner.gltf (`smlt scene sponza-banner`); the benches' own folders are
# NEW_PREFIX_VIEW and OLD_PREFIX_VIEW there.
set -uo pipefail
HERE=$(dirname "$(readlink -f "$0")")
ROOT=$HERE/../../..
SC=${SC:-/work/shared/scenes}
SMLT=${SMLT:-smlt}
OLD=${OLD:?the previous commit\'s smlt}
DIR=$1
NEW_PREFIX=$2
OLD_PREFIX=$3
views=(
    "sibenik $SC/sibenik/sibenik.gltf 1"
    "sponza $SC/sponza_dabrovic/sponza_dabrovic.gltf 1"
    "banner2 sponza_banner.gltf 2"
    "sunblind $ROOT/scenes/sunblind.gltf 1"
    "slit $ROOT/scenes/slit.gltf 1"
    "atrium1 $ROOT/scenes/atrium.gltf 1"
    "atrium2 $ROOT/scenes/atrium.gltf 2"
)
lscpu | grep 'Model name' > "$DIR/machine.txt"
for v in "${views[@]}"; do
    read -r name scene view <<<"$v"
    new="${NEW_PREFIX}_$name"
    old="${OLD_PREFIX}_$name"
    "$SMLT" bench --device cpu --scenes "$scene:$view" --methods auto,pt,naive,path-naive,s3 --seconds 8 \
        --repeats 3 --width 128 --height 72 --max-depth 10 --reference "ref_$name.exr" --out "$new" |
        tail -1
    "$OLD" bench --device cpu --scenes "$scene:$view" --methods auto --seconds 8 \
        --repeats 3 --width 128 --height 72 --max-depth 10 --reference "ref_$name.exr" --out "$old" |
        tail -1
    mkdir -p "$DIR/$name"
    cp "$new"/{results.csv,auto.csv} "$DIR/$name/"
    cp "$new/tables.md" "$DIR/$name/bench_tables.md"
    cp "$old/results.csv" "$DIR/$name/old_auto_results.csv"
    cp "$old/auto.csv" "$DIR/$name/old_auto.csv"
    cp "$old/tables.md" "$DIR/$name/old_bench_tables.md"
done
