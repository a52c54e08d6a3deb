#!/usr/bin/env bash
# naive with the per-pixel importance (side 1) against 3×3 blocks (side 3) at 128×72, one bench each, interleaved by view.
cd /tmp/autobench
SC=/work/shared/scenes
for v in "sibenik $SC/sibenik/sibenik.gltf:1" "sunblind sunblind.gltf:1" "atrium1 atrium.gltf:1" "banner2 sponza_banner.gltf:2"; do
  read n sv <<<"$v"
  for side in 1 3; do
    SMLT_SIDE=$side /tmp/smlt_sideenv bench --device cpu --scenes "$sv" --methods naive --seconds 8 --repeats 3 --width 128 --height 72 --max-depth 10 --reference ref_$n.exr --out /tmp/side/${n}_$side > /dev/null 2>&1
    echo "$n side $side: $(grep -A6 '^### Efficiency' /tmp/side/${n}_$side/tables.md | grep '^| naive')"
  done
done
echo SIDEDONE
