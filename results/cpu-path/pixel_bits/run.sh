#!/usr/bin/env bash
# The packed pixel's bits (shared::layout::PIXEL_BITS_FLIP): the commit before it (OLD) against
# it (NEW), interleaved, 3 pairs of 6 s per case, from /tmp/autobench (the auto bench's generated
# scenes: `smlt scene sponza_banner|sunblind|atrium --out X.gltf`). Writes ab.csv and ratios.md.
#   results/cpu-path/pixel_bits/run.sh OLD_SMLT NEW_SMLT
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
old=$1 new=$2
SC=${SC:-/work/shared/scenes}
C="--device cpu --time 6 --width 128 --height 72 --max-depth 10"
cd /tmp/autobench
(lscpu | grep 'Model name'; date -u) >"$here/machine.txt"
"$here/../../../scripts/ab.sh" "$old" "$new" 3 \
    "sibenik-naive|$SC/sibenik/sibenik.gltf --method naive $C" \
    "sibenik-s3|$SC/sibenik/sibenik.gltf --method s3 $C" \
    "sponza-naive|$SC/sponza_dabrovic/sponza_dabrovic.gltf --method naive $C" \
    "banner2-naive|sponza_banner.gltf --view 2 --method naive $C" \
    "sunblind-path-naive|sunblind.gltf --method path-naive $C" \
    "atrium1-naive|atrium.gltf --method naive $C" \
    "lamps-naive|lamps --method naive $C" \
    "lamps-rc4|lamps --method rc4 $C" \
    "sibenik-pt|$SC/sibenik/sibenik.gltf --method pt $C" >"$here/ab.csv"
python3 - "$here" <<'P' >"$here/ratios.md"
import csv, collections, statistics as st, sys
d = collections.defaultdict(lambda: {'A': [], 'B': []})
for r in csv.DictReader(open(sys.argv[1] + '/ab.csv')):
    d[r['case']][r['binary']].append(float(r['mutations_per_s']))
print("| case | old (M/s) | new (M/s) | new / old, per pair |")
print("|---|---|---|---|")
for k, v in d.items():
    pr = [b / a for a, b in zip(v['A'], v['B'])]
    print(f"| {k} | {st.mean(v['A']):.3f} | {st.mean(v['B']):.3f} | {st.mean(pr):.2f} ({', '.join(f'{x:.2f}' for x in pr)}) |")
P
