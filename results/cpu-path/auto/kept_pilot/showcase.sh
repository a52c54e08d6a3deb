#!/usr/bin/env bash
# (Run at 5f205fd after run.sh; SMLT built at 5f205fd, OLD at a022f10.)
# The lamps' showcase with auto keeping its pilot (128×96, so the pilot is at the render's
# size): scripts/showcase.sh with this commit's smlt (its bench of auto, pt, naive, s3 and
# path-naive, then Mitsuba 3 where the peers' packages are installed; the README's picture cut
# to 1 s), then on each view the previous commit's auto on the same reference, 3 runs of 8 s.
#   SMLT=… OLD=… results/cpu-path/auto/kept_pilot/showcase.sh [OUT]   (default: /tmp/showcase)
set -euo pipefail
HERE=$(dirname "$(readlink -f "$0")")
ROOT=$HERE/../../../..
OUT=${1:-/tmp/showcase}
SMLT=${SMLT:?this commit\'s smlt}
OLD=${OLD:?the previous commit\'s smlt}
SMLT=$SMLT PICTURE_SECONDS=1 "$ROOT/scripts/showcase.sh" "$OUT"
cd "$OUT"
for view in lamp sky; do
    env=()
    [ "$view" = sky ] && env=(--environment sky.hdr --environment-strength 0.1 --environment-rotation 40)
    "$OLD" bench --device cpu --scenes caustic --methods auto --seconds 8 --repeats 3 --width 128 --height 96 \
        --max-depth 12 "${env[@]}" --reference "$view/reference.exr" --out "old_$view" | tail -1
    mkdir -p "$HERE/showcase/$view"
    cp "$view"/{results.csv,auto.csv} "$HERE/showcase/$view/"
    cp "$view/tables.md" "$HERE/showcase/$view/bench_tables.md"
    [ -f "$view/all/tables.md" ] && cp "$view/all/tables.md" "$HERE/showcase/$view/all_tables.md"
    cp "old_$view/results.csv" "$HERE/showcase/$view/old_auto_results.csv"
    cp "old_$view/auto.csv" "$HERE/showcase/$view/old_auto.csv"
    cp "old_$view/tables.md" "$HERE/showcase/$view/old_bench_tables.md"
done
cp run.txt "$HERE/showcase/run.txt"
