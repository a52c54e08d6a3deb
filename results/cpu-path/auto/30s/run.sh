#!/usr/bin/env bash
# Auto at 30 s on two views where it trailed at 8 s and on Sibenik, where its pilot's share capped
# it: references of 65 536 (`slit`) and 32 768 (banner v2, Sibenik) samples a pixel, then `auto`,
# `pt` and `naive` in one bench a view, 3 runs of 30 s. Run from an empty folder:
#   SMLT=target/release/smlt VIEWS=/tmp/autobench SHARED_SCENES=../shared/scenes \
#       results/cpu-path/auto/30s/run.sh
# VIEWS holds slit.gltf and sponza_banner.gltf (the auto bench's views).
set -euo pipefail
: "${SMLT:?the smlt binary}" "${VIEWS:?the folder of the views}" "${SHARED_SCENES:?the folder of sibenik/}"
"$SMLT" reference "$VIEWS/slit.gltf" --view 1 --spp 65536 --width 128 --height 72 --max-depth 10 \
    --seed 1001 --device cpu --out ref_slit.exr
"$SMLT" reference "$VIEWS/sponza_banner.gltf" --view 2 --spp 32768 --width 128 --height 72 \
    --max-depth 10 --seed 1001 --device cpu --out ref_banner2.exr
sibenik="$SHARED_SCENES/sibenik/sibenik.gltf"
"$SMLT" reference "$sibenik" --view 1 --spp 32768 --width 128 --height 72 --max-depth 10 \
    --seed 1001 --device cpu --out ref_sibenik.exr
for v in "slit $VIEWS/slit.gltf:1" "banner2 $VIEWS/sponza_banner.gltf:2" "sibenik $sibenik:1"; do
    read -r name scene <<<"$v"
    "$SMLT" bench --device cpu --scenes "$scene" --methods auto,pt,naive --seconds 30 --repeats 3 \
        --width 128 --height 72 --max-depth 10 --reference "ref_$name.exr" --out "bench_$name"
done
