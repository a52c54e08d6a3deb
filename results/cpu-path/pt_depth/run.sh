#!/usr/bin/env bash
# smlt's pt against Mitsuba 3's path by max depth, paths/s on Sibenik (128×72, 6 s a render,
# interleaved, REPEATS turns): where the gap between them opens. Writes depth.csv.
#   results/cpu-path/pt_depth/run.sh SMLT PYTHON REFERENCE.exr
# (the reference only gives the peer its size and error columns; paths/s do not depend on it)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
smlt=$1 py=$2 reference=$3
scene=${SCENE:-/work/shared/scenes/sibenik/sibenik.gltf}
peer=$here/../../../scripts/peers/mitsuba_peer.py
(lscpu | grep 'Model name'; date -u) >"$here/machine.txt"
echo "repeat,max_depth,smlt_paths_per_s,mitsuba_paths_per_s" >"$here/depth.csv"
for repeat in $(seq 1 "${REPEATS:-2}"); do
    for d in 1 2 4 10; do
        s=$("$smlt" render "$scene" --method pt --device cpu --time 6 --width 128 --height 72 --max-depth "$d" \
            --out /tmp/pt_depth.exr 2>&1 | awk '/^paths\/s/ {print $2 * 1e6}')
        "$py" "$peer" "$scene" --view 1 --width 128 --height 72 --max-depth "$d" --seconds 6 --repeats 1 \
            --reference "$reference" --label sibenik --out /tmp/pt_depth_mitsuba.csv >/dev/null 2>&1
        m=$(tail -1 /tmp/pt_depth_mitsuba.csv | cut -d, -f8)
        echo "$repeat,$d,$s,$m" >>"$here/depth.csv"
    done
done
