#!/usr/bin/env bash
# One run of every method on the default scene; prints method, million candidates/s, million
# steps/s and the acceptance rate. SMLT: the binary; T: seconds per method; OUTDIR: images.
set -o pipefail
S=${SMLT:-smlt}; T=${T:-10}; OUTDIR=${OUTDIR:-out}
mkdir -p "$OUTDIR"
for m in naive s2 s3 s4 s5 s6 rc2 rc4 rc8 rc16 rc32 rc64; do
  if ! out=$($S render --width 256 --height 256 --time "$T" --method $m --out "$OUTDIR/methods_$m.exr" 2>"$OUTDIR/methods_$m.log"); then
    echo "$m failed: $(grep -v XDG_RUNTIME_DIR "$OUTDIR/methods_$m.log" | tail -1)" >&2
    exit 1
  fi
  echo "$out" | awk -v m=$m '/^mutations\/s/ {c=$2} /^chain steps\/s/ {s=$3} /^acceptance/ {a=$3} END {printf "%s %s %s %s\n", m, c, s, a}'
done
