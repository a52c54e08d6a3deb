#!/usr/bin/env bash
# The pilot's Metropolis configuration against the render's, on `sunblind` (128×72, max depth
# 10, CPU backend): a pilot of an 8 s render runs an eighth of the render's chains (512, one
# candidate each an iteration) from an eighth of its bootstrap samples (8192), so that each
# chain starts as a render's would (auto::pilot_settings); a render runs 4096 from 65 536.
# 1. Error per mutation: 4 seeds of each at 35 mutations a pixel (a pilot half's, about 0.2 s)
#    and at 350 (a tenth of an 8 s render's), their relMSE against REF (relmse.py: each
#    image's, and the estimate from pairs of seeds as auto's halves estimate it).
# 2. Mutations per second: 100 mutations a pixel, the two configurations alternating, 3 pairs.
#   SMLT=… run.sh REF OUT    (writes OUT/*.exr; prints what results.txt holds)
set -euo pipefail
HERE=$(dirname "$(readlink -f "$0")")
SMLT=${SMLT:-smlt}
REF=$(readlink -f "$1")
OUT=$2
SCENE=$HERE/../../../../scenes/sunblind.gltf
mkdir -p "$OUT"
cd "$OUT"
size=(--device cpu --width 128 --height 72 --max-depth 10)
pilot=(--bootstrap 8192 --candidates 512)
lscpu | grep 'Model name'
for method in naive path-naive; do
    for mpp in 35 350; do
        for seed in 1 2 3 4; do
            "$SMLT" render "$SCENE" --method "$method" "${size[@]}" --mutations-per-pixel "$mpp" --seed "$seed" \
                "${pilot[@]}" --out "${method}_pilot${mpp}_$seed.exr" >/dev/null
            "$SMLT" render "$SCENE" --method "$method" "${size[@]}" --mutations-per-pixel "$mpp" --seed "$seed" \
                --out "${method}_render${mpp}_$seed.exr" >/dev/null
        done
    done
    python3 "$HERE/relmse.py" "$REF" "${method}_pilot35" "${method}_render35" "${method}_pilot350" "${method}_render350"
    for pair in 1 2 3; do
        for cfg in pilot render; do
            args=()
            [ "$cfg" = pilot ] && args=("${pilot[@]}")
            echo "$method $cfg pair $pair: $("$SMLT" render "$SCENE" --method "$method" "${size[@]}" \
                --mutations-per-pixel 100 --seed 9 "${args[@]}" --out speed.exr 2>/dev/null |
                grep -E '^mutations/s')"
        done
    done
done
