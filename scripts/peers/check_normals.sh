#!/usr/bin/env bash
# Mitsuba 3 against smlt on smooth shading normals (glTF's NORMAL, interpolated over each triangle
# as the shading normal): the `smooth` scene (scenes/smooth.gltf: a closed room lit by an emissive
# quad and a point light, low-poly spheres with smooth NORMALs, a Lambert one, a GGX metal one
# and a glass one, and a flat block).
#  1. The normals alone: at random points on each mesh with NORMALs, Mitsuba's shading normal
#     (si.sh_frame.n of the `ply` that mitsuba_peer.py writes, vertex normals, face_normals false)
#     against the loader's world-space corner normals interpolated here (numpy, barycentric, then
#     normalised), and its geometric normal (si.n) against the triangle's (p1 - p0) x (p2 - p0);
#     and, to show what the check would catch, the same mesh loaded flat (face_normals true).
#  2. The scene: smlt's path tracer (`smlt render --method pt`) in two halves of SPP/2 (seeds 1,
#     2) against two Mitsuba renders of SPP/2 each (seeds 1, 2): the halves' differences are each
#     renderer's noise, so every figure has its own interval: means (the whole image, each surface
#     by the pixels whose centre sees it; each smooth mesh also split into its grazing pixels, the
#     view within 17.5° of the shading normal's horizon (|cos| < 0.3), and the rest) with ± one
#     standard error of the mean difference and z = difference / error, RMSE against the RMSE the
#     two noises alone give (ratio 1 ± ~1/sqrt(pixels) where the renderers agree; the measure
#     that tells a Lambert sphere's facets apart, whose mean they hardly move); then a third
#     Mitsuba render (SPP/2) of the same scene with every mesh flat (face normals): smlt against
#     it, and Mitsuba's smooth - flat, per smooth mesh: the difference the check tells apart.
# smlt's BSDFs give 0 to a direction on which the geometric and the shading normal disagree (no
# light through a surface's back), Mitsuba's see the shading frame alone: near a coarse sphere's
# silhouette (the grazing pixels) and terminator small differences are expected; the figures show
# them as they are. Step 2 also counts the pixels whose centre's view lies on opposite sides of
# the two normals.
#   scripts/peers/check_normals.sh [SCENE.gltf] [OUT]   (default: scenes/smooth.gltf, /tmp/check-normals; SPP=4096)
# CPU_LOCK=FILE takes flock(1) on FILE around each render (a machine shared with builds).
# Needs smlt built (cargo build --release), the peers' Python packages (requirements.txt) and
# DRJIT_LIBLLVM_PATH (a libLLVM >= 16, for Mitsuba's llvm_ad_rgb variant and the BSDF plugins).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
scene="$(realpath "${1:-$root/scenes/smooth.gltf}")"
out="${2:-/tmp/check-normals}"
spp="${SPP:-4096}"
smlt="${CARGO_TARGET_DIR:-$root/target}/release/smlt"
size=(--width 160 --height 120 --max-depth 12)
: "${DRJIT_LIBLLVM_PATH:?set DRJIT_LIBLLVM_PATH to a libLLVM >= 16 (scripts/peers/README.md)}"
export DRJIT_LIBLLVM_PATH CPU_LOCK="${CPU_LOCK:-}"
locked() { if [ -n "$CPU_LOCK" ]; then flock "$CPU_LOCK" "$@"; else "$@"; fi; }
mkdir -p "$out"
cd "$out"
PYTHONPATH="$root/scripts/peers" python3 - "$scene" <<'PY'
import sys, tempfile
import mitsuba as mi
import numpy as np
mi.set_variant("llvm_ad_rgb")
import gltf_scene
from peer_common import write_ply

scene = gltf_scene.load(sys.argv[1])
if not scene.normals:
    raise SystemExit(f"{sys.argv[1]}: no mesh has NORMAL, nothing to check")
rng = np.random.default_rng(7)
vec = lambda v: (lambda a: a.T if a.shape[0] == 3 else a)(np.array(v))  # noqa: E731 (n, 3)
print("normals (20000 points a mesh): max |Mitsuba - loader| shading, geometric | flat: shading - loader's (max, mean)")
with tempfile.TemporaryDirectory() as folder:
    for m, normals in scene.normals.items():
        tris = scene.triangles[m]
        path = f"{folder}/mesh{m}.ply"
        write_ply(path, tris, None, normals)  # as mitsuba_peer.scene_dict writes it (uv aside)
        smooth = mi.load_dict({"type": "scene", "s": {"type": "ply", "filename": path, "face_normals": False}})
        flat = mi.load_dict({"type": "scene", "s": {"type": "ply", "filename": path, "face_normals": True}})
        # random points: a triangle by area, uniform barycentrics
        area = np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]), axis=1)
        k = rng.choice(len(tris), 20000, p=area / area.sum())
        r1, r2 = rng.random(20000), rng.random(20000)
        s = np.sqrt(r1)
        b = np.stack([1 - s, s * (1 - r2), s * r2], axis=1)[:, :, None]
        p = (tris[k] * b).sum(1)
        want = (normals[k] * b).sum(1)
        want /= np.linalg.norm(want, axis=1)[:, None]
        g = gltf_scene.geometric_normals(tris)[k]
        # hit from along the geometric normal, from the front and from the back
        worst, hits = np.zeros(2), []
        for side in (1.0, -1.0):
            o = p + side * 1e-2 * g
            ray = mi.Ray3f(mi.Point3f(*o.T.astype(np.float32)), mi.Vector3f(*(-side * g).T.astype(np.float32)))
            si = smooth.ray_intersect(ray)
            hits.append(np.array(si.is_valid()).mean())
            worst = np.maximum(worst, [np.abs(vec(si.sh_frame.n) - want).max(), np.abs(vec(si.n) - g).max()])
        off = np.linalg.norm(vec(flat.ray_intersect(ray).sh_frame.n) - want, axis=1)
        print(f"  {scene.materials[m].name}: {worst[0]:.1e}, {worst[1]:.1e} ({100 * min(hits):.1f} % hit)"
              f" | {off.max():.3f}, {off.mean():.3f}; shading · geometric >= {(normals * gltf_scene.geometric_normals(tris)[:, None]).sum(-1).min():.3f}")
PY
for seed in 1 2; do
    locked "$smlt" render "$scene" --method pt --device cpu --mutations-per-pixel $((spp / 2)) --seed "$seed" \
        "${size[@]}" --out "smlt_$seed.exr" | { grep -E "paths/s|render time" || true; }
done
PYTHONPATH="$root/scripts/peers" python3 - "$scene" "$spp" "${size[@]}" <<'PY'
import contextlib, fcntl, os, sys, tempfile, time
import drjit as dr
import mitsuba as mi
import numpy as np
mi.set_variant("llvm_ad_rgb")
import gltf_scene, mitsuba_gltf, mitsuba_peer, mitsuba_phong
from peer_common import errors
mitsuba_gltf.register()
mitsuba_phong.register()

path, spp = sys.argv[1], int(sys.argv[2])
w, h, depth = int(sys.argv[4]), int(sys.argv[6]), int(sys.argv[8])


@contextlib.contextmanager
def cpu():
    """CPU_LOCK's flock around a render, where set."""
    if not os.environ.get("CPU_LOCK"):
        yield
        return
    with open(os.environ["CPU_LOCK"], "a") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)


def render(ms, seed):
    with cpu():
        return np.array(ms.integrator().render(ms, seed=seed, spp=spp // 2))


scene = gltf_scene.load(path)
s_halves = [mitsuba_peer.read_exr(mi, f"smlt_{seed}.exr") for seed in (1, 2)]
if s_halves[0].shape[:2] != (h, w):
    raise SystemExit(f"smlt's image is {s_halves[0].shape[1]}x{s_halves[0].shape[0]}, not {w}x{h}")
with tempfile.TemporaryDirectory() as folder:
    d = mitsuba_peer.scene_dict(mi, scene, 1, w, h, depth, folder)
    ms = mi.load_dict(d)
    start = time.time()
    halves = [render(ms, seed) for seed in (1, 2)]
    took = time.time() - start
    # which surface each pixel's centre sees, and how the view meets its normals there
    sensor = ms.sensors()[0]
    idx = dr.arange(mi.UInt32, w * h)
    pos = mi.Point2f((mi.Float(idx % w) + 0.5) / w, (mi.Float(idx // w) + 0.5) / h)
    ray, _ = sensor.sample_ray(0.0, 0.5, pos, mi.Point2f(0.5))
    si = ms.ray_intersect(ray)
    seen = {s.id(): np.array(si.shape == mi.ShapePtr(s)).reshape(h, w) for s in ms.shapes()}
    view = -np.array(ray.d)
    cos_s = (view * np.array(si.sh_frame.n)).sum(0).reshape(h, w)
    cos_g = (view * np.array(si.n)).sum(0).reshape(h, w)
    # the same scene flat: every mesh with face normals, as without NORMAL
    flat_scene = gltf_scene.load(path)
    flat_scene.normals = {}
    os.mkdir(f"{folder}/flat")
    mf = mi.load_dict(mitsuba_peer.scene_dict(mi, flat_scene, 1, w, h, depth, f"{folder}/flat"))
    flat = render(mf, 3)
ref = (s_halves[0] + s_halves[1]) / 2
img = (halves[0] + halves[1]) / 2
mi.Bitmap(img.astype(np.float32)).write("mitsuba_smooth.exr")
mi.Bitmap(flat.astype(np.float32)).write("mitsuba_flat.exr")
# each renderer's noise: half its two halves' difference has the variance of its mean's error
ds, dm = (s_halves[0] - s_halves[1]) / 2, (halves[0] - halves[1]) / 2
noise_s, noise_m = float(np.sqrt((ds ** 2).mean())), float(np.sqrt((dm ** 2).mean()))
print(f"Mitsuba: 2 x {spp // 2} spp in {took:.0f} s (llvm_ad_rgb), noise (RMSE) {noise_m:.2e}; smlt's (2 x {spp // 2} spp)"
      f" {noise_s:.2e}")


def compare(name, mask, a=img, k=1.0, against=ref, d_ref=ds):
    """Means and RMSE over the pixels of `mask` of image `a` (Mitsuba's noise k times the
    variance of its SPP mean: 2 for one SPP/2 render) against `against` (noise d_ref): the mean
    difference with its standard error (from the channel means of the noise samples: pixels are
    independent, channels are not) and the RMSE with the one the noises alone give, their ratio
    ± about 1/sqrt(pixels) (the ratio's own noise where the two agree: that of the squared
    differences' mean and of the noises' estimate, each ~1/sqrt(2 n) for n Gaussian pixels)."""
    n = int(mask.sum())
    if n == 0:
        return
    x, y = against[mask].mean(), a[mask].mean()
    se = np.sqrt((d_ref[mask].mean(1) ** 2).sum() + k * (dm[mask].mean(1) ** 2).sum()) / n
    expected = float(np.sqrt((d_ref[mask] ** 2).mean() + k * (dm[mask] ** 2).mean()))
    r = float(np.sqrt(((a[mask] - against[mask]) ** 2).mean()))
    print(f"  {name:26s} {n:5d} px: {x:.5f} vs {y:.5f} ({100 * (y / x - 1):+.3f} % ± {100 * se / x:.3f} %,"
          f" z {(y - x) / se:+6.1f}), RMSE {r:.2e} (noise {expected:.2e}, ratio {r / expected:.2f} ± {1 / np.sqrt(n):.2f})")


rmse = errors(img, ref)[0]
expected = np.hypot(noise_s, noise_m)
print(f"RMSE {rmse:.2e} against the noises' {expected:.2e} (ratio {rmse / expected:.3f}); mirrored"
      f" {errors(img[:, ::-1], ref)[0]:.2e}, upside down {errors(img[::-1], ref)[0]:.2e}")
print("smlt vs Mitsuba (smooth):")
compare("image", np.ones((h, w), dtype=bool))
material = lambda key: int(key.removeprefix("mesh"))  # noqa: E731
smooth = [k for k in seen if material(k) in scene.normals]
for key, mask in seen.items():
    compare(scene.materials[material(key)].name, mask)
for key in smooth:
    mask, name = seen[key], scene.materials[material(key)].name
    grazing = mask & (np.abs(cos_s) < 0.3)
    compare(f"{name}, grazing", grazing)
    compare(f"{name}, the rest", mask & ~grazing)
    split = mask & (np.sign(cos_s) != np.sign(cos_g))
    print(f"    {name}: {int(split.sum())} px whose centre's view lies on opposite sides of the two normals")
print(f"smlt vs Mitsuba with every mesh flat ({spp // 2} spp):")
for key in smooth:
    compare(scene.materials[material(key)].name, seen[key], flat, k=2.0)
print(f"Mitsuba smooth vs flat (the difference the check tells apart):")
for key in smooth:
    compare(scene.materials[material(key)].name, seen[key], flat, k=2.0, against=img, d_ref=dm)
PY
