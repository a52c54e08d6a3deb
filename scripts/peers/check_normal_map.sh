#!/usr/bin/env bash
# glTF's normalTexture in smlt against the spec's arithmetic, Cycles (Blender's own glTF
# importer: its Normal Map node in tangent space, MikkTSpace tangents) and Mitsuba 3 (its
# `normalmap` BSDF over `diffuse`, the frame from dp/du). The scene of normal_map_scene.py: a
# Lambertian floor lit only by a sun, so that each pixel's radiance is albedo/pi x E x cos, cos
# between the bent normal and the sun, the same for every sample inside a band; its normal
# texture has four bands: flat, leaning +x, +y and -y by TILT degrees.
#  1. smlt's path tracer (`smlt reference`), smlt's multiplexed estimator (`--method naive`,
#     whose light subpaths scatter off the bent normals through Veach's adjoint; NAIVE_MPP
#     mutations a pixel), Cycles (`cycles_peer.py --converged SPP`) and Mitsuba (`llvm_ad_rgb`
#     where DRJIT_LIBLLVM_PATH is set, else `scalar_rgb`), SPP samples a pixel;
#  2. each band's mean over a window at its centre, over the flat band's, against the spec's
#     value: the cosine with the sun of the texel's normal (8-bit, (2 c - 1) normalised) in the
#     frame x = +x (dp/du), y = -z (up in the image: decreasing v), z = +y, over the flat one's;
#     and that value times Conty and Kulla's bump shadowing term (Ray Tracing Gems, 2019, ch.
#     12: 2 / (1 + sqrt(1 + a2 tan2 i)), a2 = min(tan2 d / 8, 1), d the bent normal's angle to
#     the geometric one, i the light's), which Cycles and Mitsuba multiply a bent normal's
#     light by against the bump terminator and which glTF does not define.
# A swapped or flipped axis would swap the +y and -y bands (1.28 against 0.45 at 30 degrees).
#   scripts/peers/check_normal_map.sh [OUT]   (default /tmp/check-normal-map; SPP=64, TILT=30,
#   NAIVE_MPP=8192)
# Needs smlt built (cargo build --release) and the peers' Python packages (requirements.txt: bpy,
# mitsuba, OpenEXR, numpy).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
out="${1:-/tmp/check-normal-map}"
spp="${SPP:-64}"
naive_mpp="${NAIVE_MPP:-8192}"
tilt="${TILT:-30}"
smlt="${CARGO_TARGET_DIR:-$root/target}/release/smlt"
size=(--width 160 --height 100 --max-depth 10)
mkdir -p "$out"
cd "$out"
python3 "$root/scripts/peers/normal_map_scene.py" . --tilt "$tilt"
"$smlt" reference normal_map.gltf "${size[@]}" --spp "$spp" --device cpu --out pt.exr >/dev/null
"$smlt" render normal_map.gltf "${size[@]}" --method naive --mutations-per-pixel "$naive_mpp" --device cpu \
    --out naive.exr >/dev/null
python3 "$root/scripts/peers/cycles_peer.py" normal_map.gltf --view 1 "${size[@]}" --reference pt.exr \
    --converged "$spp" --save cycles.exr 2>/dev/null | tail -1
python3 - "$tilt" "$spp" <<'PY'
import math, os, sys
import numpy as np
import OpenEXR, Imath
import mitsuba as mi

mi.set_variant("llvm_ad_rgb" if os.environ.get("DRJIT_LIBLLVM_PATH") else "scalar_rgb")
sun = math.radians(40.0)
# The same floor: Mitsuba's rectangle turned to face +y has u along +x and dp/du = +x.
mitsuba = mi.load_dict({
    "type": "scene",
    "integrator": {"type": "path", "max_depth": 11},
    "sensor": {"type": "perspective", "fov": math.degrees(0.9), "fov_axis": "y",
               "to_world": mi.ScalarTransform4f().look_at(origin=[0, 2.2, 0], target=[0, 0, 0], up=[0, 0, -1]),
               "film": {"type": "hdrfilm", "width": 160, "height": 100, "rfilter": {"type": "box"}},
               "sampler": {"type": "independent", "sample_count": int(sys.argv[2])}},
    "floor": {"type": "rectangle", "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90),
              "bsdf": {"type": "normalmap",
                       "normalmap": {"type": "bitmap", "filename": "normal_map.png", "raw": True,
                                     "filter_type": "nearest"},
                       "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.8] * 3}}}},
    "sun": {"type": "directional", "direction": [0, -math.cos(sun), math.sin(sun)],
            "irradiance": {"type": "rgb", "value": [1, 1, 1]}},
})
mi.Bitmap(mi.render(mitsuba)).write("mitsuba.exr")

def luminance(path):
    f = OpenEXR.InputFile(path)
    w = f.header()["dataWindow"]
    width, height = w.max.x - w.min.x + 1, w.max.y - w.min.y + 1
    c = [np.frombuffer(f.channel(k, Imath.PixelType(Imath.PixelType.FLOAT)), dtype=np.float32)
         .reshape(height, width) for k in "RGB"]
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]

tilt = math.radians(float(sys.argv[1]))
s, c = math.sin(tilt), math.cos(tilt)
texel = lambda n: [round((x + 1) / 2 * 255) / 255 * 2 - 1 for x in n]  # noqa: E731 (8-bit, decoded)
bands = [(0, 0, 1), (s, 0, c), (0, s, c), (0, -s, c)]
towards_sun = np.array([0.0, math.cos(sun), -math.sin(sun)])
def bent(n):
    t = texel(n)
    world = np.array([t[0], t[2], -t[1]])  # x = +x, z (the normal) = +y, y (up in the image) = -z
    return world / np.linalg.norm(world)
def conty_kulla(n):
    tan2 = lambda cos: (1 - cos * cos) / (cos * cos)  # noqa: E731
    a2 = min(tan2(float(n[1])) / 8, 1.0)
    return 2 / (1 + math.sqrt(1 + a2 * tan2(float(towards_sun[1]))))
spec = [max(0.0, float(bent(n) @ towards_sun)) for n in bands]  # no light from below the bent normal
shadowed = [x * conty_kulla(bent(n)) for x, n in zip(spec, bands)]
images = {name: luminance(f"{name}.exr") for name in ("pt", "naive", "cycles", "mitsuba")}
height, width = images["pt"].shape
half_width = 2.2 * 1.6 * math.tan(0.45)  # the floor's half-width seen at the camera's distance
def band(image, k):
    x = -0.75 + 0.5 * k
    px = int(width / 2 + x / half_width * width / 2)
    return float(image[height // 2 - 20:height // 2 + 20, px - 4:px + 4].mean())
names = ["flat", "+x", "+y", "-y"]
print(f"band / flat band, tilt {math.degrees(tilt):.0f} degrees (a 40x8-pixel window at each band's centre)")
print("| band | spec | spec x Conty-Kulla | smlt pt | smlt naive | Cycles | Mitsuba 3 |")
print("|---|---|---|---|---|---|---|")
for k, name in enumerate(names):
    r = {n: band(img, k) / band(img, 0) for n, img in images.items()}
    print(f"| {name} | {spec[k] / spec[0]:.4f} | {shadowed[k] / shadowed[0]:.4f} | {r['pt']:.4f} | "
          f"{r['naive']:.4f} | {r['cycles']:.4f} | {r['mitsuba']:.4f} |")
PY
