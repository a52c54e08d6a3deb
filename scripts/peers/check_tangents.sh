#!/usr/bin/env bash
# The tangent frame of glTF's normalTexture on a curved mesh, smlt against Blender and Cycles.
# The scene of tangent_scene.py: a smooth UV sphere with a normal texture of 35-degree tilts,
# half of it mapped mirror-wise (TANGENT w = -1 there), written by Blender's own glTF exporter
# with TANGENT (Blender's MikkTSpace) and without.
#  1. Cycles' Normal pass of the file through Blender's own importer (cycles_normals.py: its
#     Normal Map node over the MikkTSpace tangents Blender computes; the same image with or
#     without TANGENT, which the importer does not read);
#  2. smlt's shading normal at each pixel's first hit, at the pixel's centre (cargo's
#     `shading_normals` example): from the file's TANGENT; from MikkTSpace's tangents, which smlt
#     computes where a file has none (bevy_mikktspace); and in each triangle's own frame (dp/du,
#     -dp/dv; --triangle-frames), what smlt did before it read tangents;
#  3. the angle between each of smlt's normals and Cycles' over the sphere's pixels (a wrong
#     bitangent sign on the mirrored half, or a green channel read the other way, would turn
#     the texels' y: up to 70 degrees off), and between smlt's two vertex-tangent images.
# Cycles' pass is a mean over a pixel's samples (within 0.005 px of its centre), so where a
# pixel's centre lies on a texel's edge the pass mixes two texels' normals (its length below 1):
# those few pixels differ from any renderer's single normal by up to the texels' difference.
# Then, where scripts/fetch-flight-helmet.sh has fetched Khronos' FlightHelmet (every mesh has
# TANGENT), smlt's normals at 400 x 600 from MikkTSpace's tangents (the file with its TANGENTs
# left out) and from each triangle's frame, against its normals from the file's TANGENT.
#   scripts/peers/check_tangents.sh [OUT]   (default /tmp/check-tangents; SPP=16;
#   FLIGHT_HELMET=~/.cache/smlt/flight-helmet/FlightHelmet.gltf)
# Needs the example built (cargo build --release --example shading_normals) and the peers' Python
# packages (requirements.txt: bpy, OpenEXR, numpy).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
out="${1:-/tmp/check-tangents}"
spp="${SPP:-16}"
normals="${CARGO_TARGET_DIR:-$root/target}/release/examples/shading_normals"
size=(--width 160 --height 120)
mkdir -p "$out"
cd "$out"
python3 "$root/scripts/peers/tangent_scene.py" . | tail -3
python3 "$root/scripts/peers/cycles_normals.py" tangents.gltf "${size[@]}" --spp "$spp" --out cycles.exr | tail -1
"$normals" tangents.gltf "${size[@]}" --out smlt_tangent.exr >/dev/null
"$normals" no_tangents.gltf "${size[@]}" --out smlt_mikktspace.exr >/dev/null
"$normals" no_tangents.gltf "${size[@]}" --out smlt_triangle_frames.exr --triangle-frames >/dev/null
helmet="${FLIGHT_HELMET:-$HOME/.cache/smlt/flight-helmet/FlightHelmet.gltf}"
if [ -f "$helmet" ]; then
    mkdir -p helmet
    for f in "$(dirname "$helmet")"/*; do ln -sf "$f" helmet/; done
    python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))
for m in d['meshes']:
    for p in m['primitives']:
        p['attributes'].pop('TANGENT', None)
json.dump(d, open('helmet/no_tangents.gltf', 'w'))" "$helmet"
    helmet_size=(--width 400 --height 600)
    "$normals" "$helmet" "${helmet_size[@]}" --out helmet_tangent.exr >/dev/null
    "$normals" helmet/no_tangents.gltf "${helmet_size[@]}" --out helmet_mikktspace.exr >/dev/null
    "$normals" "$helmet" "${helmet_size[@]}" --out helmet_triangle_frames.exr --triangle-frames >/dev/null
fi
python3 - <<'PY'
import os
import numpy as np
import OpenEXR, Imath


def read(path):
    f = OpenEXR.InputFile(path)
    w = f.header()["dataWindow"]
    width, height = w.max.x - w.min.x + 1, w.max.y - w.min.y + 1
    return np.stack([np.frombuffer(f.channel(c, Imath.PixelType(Imath.PixelType.FLOAT)), dtype=np.float32)
                     .reshape(height, width) for c in "RGB"], axis=-1)


def angles(a, b):
    a = a / np.linalg.norm(a, axis=-1, keepdims=True)
    b = b / np.linalg.norm(b, axis=-1, keepdims=True)
    return np.degrees(np.arccos(np.clip((a * b).sum(-1), -1.0, 1.0)))


cycles = read("cycles.exr")
smlt = {name: read(f"smlt_{name}.exr") for name in ("tangent", "mikktspace", "triangle_frames")}
on_sphere = np.linalg.norm(cycles, axis=-1) > 0.5
masks = {name: np.linalg.norm(img, axis=-1) > 0.5 for name, img in smlt.items()}
print(f"{on_sphere.sum()} pixels on the sphere; smlt's hit mask differs from Cycles' at "
      + ", ".join(f"{(m != on_sphere).sum()} ({n})" for n, m in masks.items()))
print("| smlt's normal | against | pixels | mean angle | median | 99th percentile | pixels over 1 degree |")
print("|---|---|---|---|---|---|---|")
labels = {"tangent": "the file's TANGENT", "mikktspace": "MikkTSpace (smlt's, no TANGENT)",
          "triangle_frames": "each triangle's frame (dp/du)"}
for name, img in smlt.items():
    both = on_sphere & masks[name]
    a = angles(img[both], cycles[both])
    print(f"| {labels[name]} | Cycles | {both.sum()} | {a.mean():.4f} | {np.median(a):.4f} | "
          f"{np.percentile(a, 99):.3f} | {(a > 1).sum()} |")
both = masks["tangent"] & masks["mikktspace"]
a = angles(smlt["mikktspace"][both], smlt["tangent"][both])
print(f"| MikkTSpace (smlt's) | the file's TANGENT (Blender's) | {both.sum()} | {a.mean():.4f} | "
      f"{np.median(a):.4f} | {np.percentile(a, 99):.3f} | {(a > 1).sum()} |")
mixed = on_sphere & (np.linalg.norm(cycles, axis=-1) < 0.999)
print(f"Cycles' pass is below unit length (a pixel mixing texels) at {mixed.sum()} pixels")
if os.path.exists("helmet_tangent.exr"):
    print()
    print("FlightHelmet, 400 x 600: smlt's normals against its normals from the file's TANGENT")
    print("| smlt's normal | pixels | mean angle | median | 99th percentile | pixels over 5 degrees |")
    print("|---|---|---|---|---|---|")
    file = read("helmet_tangent.exr")
    for name in ("mikktspace", "triangle_frames"):
        img = read(f"helmet_{name}.exr")
        both = (np.linalg.norm(file, axis=-1) > 0.5) & (np.linalg.norm(img, axis=-1) > 0.5)
        a = angles(img[both], file[both])
        print(f"| {labels[name]} | {both.sum()} | {a.mean():.3f} | {np.median(a):.3f} | "
              f"{np.percentile(a, 99):.2f} | {(a > 5).sum()} ({100 * (a > 5).mean():.1f} %) |")
PY
