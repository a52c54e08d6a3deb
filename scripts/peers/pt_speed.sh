#!/usr/bin/env bash
# smlt's path tracer against Mitsuba 3's `path`, paths/s on the same cores in one interleaved
# run: for each view, REPEATS turns of `smlt bench --methods pt` (whose passes.csv holds the
# path tracer's bare-ray ceiling) and then `mitsuba_peer.py`, each SECONDS long; then OUT/table.md
# with both rates, their ratio and pt's fraction of its ray ceiling (means over the turns).
#   scripts/peers/pt_speed.sh OUT SCENE.gltf:VIEW:REFERENCE.exr ...
# Size 128×72, max depth 10, as the bench of docs/results.md. Needs smlt built (cargo build
# --release) and the peers' packages (requirements.txt); DRJIT_LIBLLVM_PATH for Mitsuba's
# `llvm_ad_rgb` variant, which the peer takes when it is set (else `scalar_rgb`, whose Python
# glTF BRDF plugin is slow).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
smlt="${SMLT:-${CARGO_TARGET_DIR:-$root/target}/release/smlt}"
seconds="${SECONDS_PER_RUN:-8}"
repeats="${REPEATS:-3}"
out="$1"
shift
size=(--width 128 --height 72 --max-depth 10)
mkdir -p "$out"
for spec in "$@"; do
    IFS=: read -r scene view reference <<<"$spec"
    label="$(basename "$scene" .gltf)_v$view"
    for r in $(seq 1 "$repeats"); do
        "$smlt" bench --device cpu --scenes "$scene:$view" --methods pt --seconds "$seconds" --repeats 1 \
            "${size[@]}" --reference "$reference" --out "$out/$label/smlt_$r" >/dev/null
        python3 "$root/scripts/peers/mitsuba_peer.py" "$scene" --view "$view" "${size[@]}" --seconds "$seconds" \
            --repeats 1 --reference "$reference" --label "$label" --out "$out/$label/mitsuba_$r.csv" >/dev/null
        echo "$label turn $r done"
    done
done
python3 - "$out" <<'PY'
import csv, glob, os, statistics, sys
out = sys.argv[1]
rows = ["| view | smlt `pt` M paths/s | Mitsuba 3 `path` M paths/s | Mitsuba / smlt | pt's rays a path "
        "| bare M rays/s | ceiling M paths/s | pt of its ceiling |", "|---|---|---|---|---|---|---|---|"]
for folder in sorted(glob.glob(os.path.join(out, "*_v*"))):
    smlt, mitsuba, ceiling = [], [], []
    for run in sorted(glob.glob(os.path.join(folder, "smlt_*"))):
        with open(os.path.join(run, "results.csv")) as f:
            smlt.append(float(list(csv.DictReader(f))[-1]["mutations_per_s"]))
        with open(os.path.join(run, "passes.csv")) as f:
            p = list(csv.DictReader(f))[0]
            ceiling.append((float(p["rays_per_candidate"]), float(p["bare_rays_per_s"]),
                            float(p["ceiling_mutations_per_s"]), float(p["ceiling_fraction"])))
    for path in sorted(glob.glob(os.path.join(folder, "mitsuba_*.csv"))):
        with open(path) as f:
            mitsuba.append(float(list(csv.DictReader(f))[-1]["mutations_per_s"]))
    s, m = statistics.mean(smlt), statistics.mean(mitsuba)
    c = [statistics.mean(x[i] for x in ceiling) for i in range(4)]
    span = lambda xs: f"{statistics.mean(xs) / 1e6:.2f} ({min(xs) / 1e6:.2f}–{max(xs) / 1e6:.2f})"
    rows.append(f"| {os.path.basename(folder)} | {span(smlt)} | {span(mitsuba)} | {m / s:.2f}× | {c[0]:.2f} "
                f"| {c[1] / 1e6:.2f} | {c[2] / 1e6:.2f} | {100 * c[3]:.0f} % |")
table = "\n".join(rows) + "\n"
open(os.path.join(out, "table.md"), "w").write(table)
print(table)
PY
