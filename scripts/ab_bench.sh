#!/usr/bin/env bash
# The bench of two smlt binaries, alternating scene by scene (A then B on each scene, so that a
# machine's drift falls on both): each writes OUT/A/<scene>/ and OUT/B/<scene>/ (results.csv,
# tables.md, passes.csv, plots). Copy the cached references (reference_<scene>_v<view>.exr and
# .json) into every OUT/A|B/<scene>/ first, or each run renders its own.
# A measurement, not a test: quote the ratios of one run, and the machine (lscpu).
#
#   scripts/ab_bench.sh OLD_SMLT 'OLD_METHODS' NEW_SMLT 'NEW_METHODS' OUT SCENE[:VIEW]...
#   scripts/ab_bench.sh /tmp/smlt-old pt,path-naive target/release/smlt pt,path-naive,path-s3 /tmp/ab \
#       ../shared/scenes/sibenik/sibenik.gltf sponza_banner.gltf:2
set -euo pipefail
if [ $# -lt 6 ]; then
    echo "usage: $0 OLD_SMLT OLD_METHODS NEW_SMLT NEW_METHODS OUT SCENE[:VIEW]..." >&2
    exit 2
fi
a=$1 a_methods=$2 b=$3 b_methods=$4 out=$5
shift 5
for scene in "$@"; do
    name=$(basename "${scene%%:*}" .gltf)
    for which in A B; do
        bin=$a methods=$a_methods
        [ "$which" = B ] && bin=$b methods=$b_methods
        mkdir -p "$out/$which/$name"
        "$bin" bench --device cpu --scenes "$scene" --methods "$methods" --seconds 8 --repeats 3 \
            --width 128 --height 72 --reference-spp 2048 --out "$out/$which/$name" \
            >"$out/$which-$name.log" 2>&1
    done
done
