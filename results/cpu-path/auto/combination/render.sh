#!/usr/bin/env bash
# The renders of the combination experiment (README.md): `pt` and `naive` at 4 s and 8 s, seeds
# 1–3, and pilot-length renders (0.25 s, seeds 11–16, two halves each per render seed), on the
# three views where auto trails the best single method. Run from an empty folder:
#   SMLT=target/release/smlt VIEWS=/tmp/autobench results/cpu-path/auto/combination/render.sh
# VIEWS holds sunblind.gltf, slit.gltf and sponza_banner.gltf (written by `smlt scene`, as the
# auto bench's) and their references ref_VIEW.exr.
set -euo pipefail
: "${SMLT:?the smlt binary}" "${VIEWS:?the folder of the views and references}"
r() { # view scene camera method seed seconds out
    "$SMLT" render "$2" --view "$3" --method "$4" --seed "$5" --time "$6" --device cpu --width 128 \
        --height 72 --max-depth 10 --out "$7" >/dev/null 2>&1
}
for v in "sunblind sunblind.gltf 1" "slit slit.gltf 1" "banner2 sponza_banner.gltf 2"; do
    read -r name file camera <<<"$v"
    for seed in 1 2 3; do
        for m in pt naive; do
            for t in 4 8; do r "$name" "$VIEWS/$file" "$camera" "$m" "$seed" "$t" "${name}_${m}_${seed}_${t}.exr"; done
        done
    done
    for seed in 11 12 13 14 15 16; do
        for m in pt naive; do r "$name" "$VIEWS/$file" "$camera" "$m" "$seed" 0.25 "p_${name}_${m}_${seed}.exr"; done
    done
done
