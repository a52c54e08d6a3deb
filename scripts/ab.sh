#!/usr/bin/env bash
# Candidates/s (paths/s for pt) of two smlt binaries on the same renders, interleaved (A, B, A, B, … for every
# case, so that a machine's drift falls on both), as CSV on stdout: case,binary,repeat,M/s.
# A measurement, not a test: quote the ratio B/A measured in one run, and the machine (lscpu).
#
#   scripts/ab.sh OLD_SMLT NEW_SMLT REPEATS 'label|render args' ['label|render args' …]
#   scripts/ab.sh /tmp/old/smlt target/release/smlt 2 \
#       'sibenik-cpu2|../shared/scenes/sibenik/sibenik.gltf --device cpu --time 10 --width 128 --height 72'
set -euo pipefail
if [ $# -lt 4 ]; then
    echo "usage: $0 OLD_SMLT NEW_SMLT REPEATS 'label|render args'..." >&2
    exit 2
fi
a=$1 b=$2 repeats=$3
shift 3
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "case,binary,repeat,mutations_per_s"
for case in "$@"; do
    label=${case%%|*}
    read -r -a args <<<"${case#*|}"
    for repeat in $(seq 1 "$repeats"); do
        for which in A B; do
            bin=$a
            [ "$which" = B ] && bin=$b
            rate=$("$bin" render "${args[@]}" --out "$out/ab.exr" 2>/dev/null |
                awk '/^(mutations|paths)\/s/ {print $2}')
            echo "$label,$which,$repeat,${rate:-failed}"
        done
    done
done
