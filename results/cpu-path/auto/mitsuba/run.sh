#!/usr/bin/env bash
# Mitsuba 3's path tracer on the auto bench's seven views, 3 runs of 8 s, same references.
set -uo pipefail
cd /tmp/autobench
P=/work/main/scripts/peers/mitsuba_peer.py
SC=/work/shared/scenes
m() { # name scene view label
  python3 $P "$2" --view "$3" --width 128 --height 72 --max-depth 10 --seconds 8 --repeats 3 \
     --reference "ref_$1.exr" --label "$4" --out "mitsuba/$1.csv" > "mitsuba/$1.log" 2>&1
  echo "$1 $(tail -1 mitsuba/$1.csv | cut -d, -f8,11)"
}
mkdir -p mitsuba
lscpu | grep 'Model name' > mitsuba/machine.txt
m sibenik $SC/sibenik/sibenik.gltf 1 sibenik
m sponza $SC/sponza_dabrovic/sponza_dabrovic.gltf 1 sponza_dabrovic
m banner2 /tmp/autobench/sponza_banner.gltf 2 sponza_banner
m sunblind /tmp/autobench/sunblind.gltf 1 sunblind
m slit /tmp/autobench/slit.gltf 1 slit
m atrium1 /tmp/autobench/atrium.gltf 1 atrium
m atrium2 /tmp/autobench/atrium.gltf 2 atrium
echo MITSUBA_DONE
