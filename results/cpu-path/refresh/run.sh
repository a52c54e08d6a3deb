#!/bin/bash
# Alternates the two binaries scene by scene: old (f6c196e) pt,path-naive; new (1e0afae) pt,path-naive,path-s3.
cd /tmp/bench19
SC=(/work/shared/scenes/sibenik/sibenik.gltf /work/shared/scenes/sponza_dabrovic/sponza_dabrovic.gltf sponza_banner.gltf:2 sunblind.gltf slit.gltf)
for s in "${SC[@]}"; do
  for b in old new; do
    if [ $b = old ]; then bin=/tmp/smlt-f6c; m=pt,path-naive; else bin=/tmp/smlt-1e0; m=pt,path-naive,path-s3; fi
    name=$(basename ${s%%:*} .gltf)
    $bin bench --device cpu --scenes $s --methods $m --seconds 8 --repeats 3 --width 128 --height 72 --reference-spp 2048 --out /tmp/b5/$b/$name > /tmp/b5/$b-$name.log 2>&1
    cp /tmp/b5/$b/reference_* /tmp/b5/$b/$name/ 2>/dev/null
  done
done
echo ALLDONE
