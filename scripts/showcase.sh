#!/usr/bin/env bash
# The showcase: a spot lamp's caustic through a glass ball (the `caustic` scene), where a path
# tracer fails outright, measured at equal time on the CPU backend — `--method auto` (its pilot's
# time counted), smlt's path tracer, the multiplexed estimator (naive, s3), the path estimator,
# Mitsuba 3's and Cycles' path tracers — against
# a bidirectional reference; then the same view under a sky (`--environment`, the sky of
# scripts/peers/check_environment.sh) beside its lamps. Writes OUT/lamp and OUT/sky (each the
# bench's results.csv, tables.md and images, and all/ with Mitsuba's and Cycles' rows appended), OUT/caustic.png
# (the README's picture) and OUT/run.txt.
#   scripts/showcase.sh [OUT]   (default: /tmp/showcase)
# Needs smlt built (cargo build --release); Mitsuba's and Cycles' rows need the peers' Python
# packages (scripts/peers/requirements.txt: mitsuba, bpy) and each is left out without its own.
#
# The reference is the multiplexed estimator's (naive) long render: no path tracer renders the
# spot's caustic, so a path-traced reference would be wrong where it matters. It is checked two
# ways: its two halves (seeds 1 and 2) agree with each other to the noise the script prints,
# and with the spot removed, smlt's path tracer agrees with Mitsuba's (check_glass.sh).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:-/tmp/showcase}"
smlt="${SMLT:-${CARGO_TARGET_DIR:-$root/target}/release/smlt}"
seconds="${SECONDS_PER_METHOD:-8}"
repeats="${REPEATS:-3}"
reference_mpp="${REFERENCE_MPP:-16384}"
picture_seconds="${PICTURE_SECONDS:-60}"
size=(--width 128 --height 96 --max-depth 12)
mkdir -p "$out"
cd "$out"
start=$(date +%s)
"$smlt" scene caustic --out caustic.gltf >/dev/null
python3 - <<'PY'
# The sky of check_environment.sh, at 512×256.
import struct, zlib, math
w, h = 512, 256
rows = []
for j in range(h):
    v = (j + 0.5) / h
    for i in range(w):
        u = (i + 0.5) / w
        if v < 0.5:
            t = min(v * 2, 1)
            rgb = [(1 - t) * a + t * b for a, b in zip([0.25, 0.45, 1.0], [0.8, 0.85, 0.9])]
        else:
            rgb = [0.12, 0.1, 0.08]
        d2 = ((u - 0.3) * w) ** 2 + ((v - (0.5 - 25 / 180)) * h) ** 2
        sun = 400.0 * math.exp(-d2 / (2 * 4.0 ** 2))
        rows.append([c + sun * k for c, k in zip(rgb, [1.0, 0.9, 0.75])])
# Radiance HDR (RGBE, flat scanlines): what `--environment` reads besides OpenEXR.
def rgbe(c):
    m = max(c)
    if m < 1e-32:
        return bytes(4)
    e = math.frexp(m)[1]
    return bytes([int(x / 2 ** e * 256) for x in c] + [e + 128])
with open("sky.hdr", "wb") as f:
    f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n" + f"-Y {h} +X {w}\n".encode())
    f.write(b"".join(rgbe(c) for c in rows))
PY
views=(lamp sky)
for view in "${views[@]}"; do
    env=()
    [ "$view" = sky ] && env=(--environment sky.hdr --environment-strength 0.1 --environment-rotation 40)
    mkdir -p "$view"
    # The reference in two independent halves, and their mean.
    for seed in 1 2; do
        "$smlt" render caustic --device cpu --method naive --mutations-per-pixel "$reference_mpp" --seed "$seed" \
            "${size[@]}" "${env[@]}" --out "$view/reference_$seed.exr" | grep -E "render time" || true
    done
    python3 - "$view" <<'PY'
import sys
import numpy as np
import OpenEXR, Imath
view = sys.argv[1]
def read(path):
    f = OpenEXR.InputFile(path)
    dw = f.header()["dataWindow"]
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    return np.stack([np.frombuffer(f.channel(c, Imath.PixelType(Imath.PixelType.FLOAT)), np.float32).reshape(h, w)
                     for c in "RGB"], -1), (w, h)
(a, (w, h)), (b, _) = read(f"{view}/reference_1.exr"), read(f"{view}/reference_2.exr")
mean = (a + b) / 2
header = OpenEXR.Header(w, h)
OpenEXR.OutputFile(f"{view}/reference.exr", header).writePixels({c: mean[..., i].astype(np.float32).tobytes()
                                                                for i, c in enumerate("RGB")})
# The mean's RMSE is half the halves' difference's.
print(f"{view}: reference halves' means {a.mean():.5f}, {b.mean():.5f}; reference noise RMSE "
      f"{np.sqrt(((a - b) ** 2).mean()) / 2:.3e}")
PY
    "$smlt" bench --device cpu --scenes caustic --methods auto,pt,naive,s3,path-naive --seconds "$seconds" \
        --repeats "$repeats" "${size[@]}" "${env[@]}" --reference "$view/reference.exr" --out "$view" | tail -2
    peer_env=()
    [ "$view" = sky ] && peer_env=(--environment sky.hdr --environment-strength 0.1 --environment-rotation 40)
    rm -f "$view/peers.csv"
    if python3 -c "import mitsuba" 2>/dev/null; then
        python3 "$root/scripts/peers/mitsuba_peer.py" caustic.gltf "${size[@]}" --reference "$view/reference.exr" \
            --seconds "$seconds" --repeats "$repeats" --label caustic "${peer_env[@]}" --out "$view/peers.csv" | tail -1
    fi
    # Cycles through Blender's own glTF importer (bpy); the Blender log lines are dropped.
    if python3 -c "import bpy" 2>/dev/null; then
        python3 "$root/scripts/peers/cycles_peer.py" caustic.gltf "${size[@]}" --reference "$view/reference.exr" \
            --seconds "$seconds" --repeats "$repeats" --label caustic "${peer_env[@]}" --out "$view/peers.csv" \
            | grep "^caustic," | tail -1
    fi
    if [ -f "$view/peers.csv" ]; then
        (cat "$view/results.csv"; tail -n +2 "$view/peers.csv") > "$view/all.csv"
        "$smlt" plot "$view/all.csv" --out "$view/all" >/dev/null
    fi
done
# The README's picture: the multiplexed estimator for 60 s at 384×288.
"$smlt" render caustic --device cpu --method naive --time "$picture_seconds" --width 384 --height 288 --max-depth 12 \
    --out caustic.exr | grep -E "render time|wrote" || true
{
    echo "scripts/showcase.sh $out: $(( $(date +%s) - start )) s"
    lscpu | grep -E "Model name|^CPU\(s\)"
} > run.txt
cat run.txt
