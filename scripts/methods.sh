#!/usr/bin/env bash
# One run of every method on the default scene; prints method, million candidates/s, million steps/s.
S=${SMLT:-smlt}; T=${T:-10}; OUTDIR=${OUTDIR:-out}
for m in naive s2 s3 s4 s5 s6 rc2 rc4 rc8 rc16 rc32 rc64; do
  $S render --width 256 --height 256 --time $T --method $m --out $OUTDIR/methods_$m.exr 2>/dev/null \
    | awk -v m=$m '/^mutations\/s/ {c=$2} /^chain steps\/s/ {s=$3} /^acceptance/ {a=$3} END {printf "%s %s %s %s\n", m, c, s, a}'
done
