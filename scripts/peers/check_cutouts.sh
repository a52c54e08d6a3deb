#!/usr/bin/env bash
# Mitsuba 3 against smlt on glTF's cut-outs (alphaMode): the `cutout` scene (scenes/cutout.gltf: a
# Lambertian room under a ceiling lamp, a perforated screen under the lamp — MASK over a NEAREST
# texture of square holes —, a leaf — MASK at alphaCutoff 0.4 over a bilinear disc of alpha —
# and a red pane whose coverage fades across it — BLEND, baseColorFactor's alpha 0.8 × a bilinear
# ramp 1, 2/3, 1/3, 0).
# Mitsuba's side is mitsuba_peer.py's: each cut-out's BSDF inside a `mask` whose opacity is glTF's
# (BLEND: the filtered alpha itself, which `mask` passes 1 − opacity of in expectation, as smlt's
# stochastic opacity does; MASK: glTF's alpha thresholded at alphaCutoff on a grid 32 × finer than
# a bilinear texture, as a NEAREST bitmap).
# smlt's path tracer (`smlt render --method pt`) in two halves of SPP/2 (seeds 1, 2) against two
# Mitsuba renders of SPP/2 each: the halves' differences are each renderer's noise, so every
# figure has its own interval: means (the whole image, each surface by the pixels whose centre's
# first hit is on it, cut-away parts included) ± one standard error of the mean difference, z,
# RMSE against the RMSE the two noises alone give. Then a control, Mitsuba with every cut-out
# made OPAQUE (SPP/2): smlt against it, the difference the check tells apart.
# Depth: smlt's pass through a cut-away point is no vertex; Mitsuba's `mask` counts one (its
# null transmission is a bounce), so Mitsuba runs twice smlt's depth (smlt 24: the light beyond
# 24 bounces in this room is ~1e-4 of the image).
#   scripts/peers/check_cutouts.sh [OUT]   (default: /tmp/check-cutouts; SPP=4096)
# CPU_LOCK=FILE takes flock(1) on FILE around each render (a machine shared with builds).
# Needs smlt built (cargo build --release), the peers' Python packages (requirements.txt) and
# DRJIT_LIBLLVM_PATH (a libLLVM >= 16, for Mitsuba's llvm_ad_rgb variant).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
scene="$root/scenes/cutout.gltf"
out="${1:-/tmp/check-cutouts}"
spp="${SPP:-4096}"
depth=24
smlt="${CARGO_TARGET_DIR:-$root/target}/release/smlt"
: "${DRJIT_LIBLLVM_PATH:?set DRJIT_LIBLLVM_PATH to a libLLVM >= 16 (scripts/peers/README.md)}"
export DRJIT_LIBLLVM_PATH CPU_LOCK="${CPU_LOCK:-}"
locked() { if [ -n "$CPU_LOCK" ]; then flock "$CPU_LOCK" "$@"; else "$@"; fi; }
mkdir -p "$out"
cd "$out"
for seed in 1 2; do
    locked "$smlt" render "$scene" --method pt --device cpu --mutations-per-pixel $((spp / 2)) --seed "$seed" \
        --width 160 --height 120 --max-depth "$depth" --out "smlt_$seed.exr" | { grep -E "paths/s|render time" || true; }
done
PYTHONPATH="$root/scripts/peers" python3 - "$scene" "$spp" "$depth" <<'PY'
import contextlib, fcntl, os, sys, tempfile, time
import drjit as dr
import mitsuba as mi
import numpy as np
mi.set_variant("llvm_ad_rgb")
import gltf_scene, mitsuba_peer
from peer_common import errors

path, spp, depth = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
w, h = 160, 120


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
cutouts = [m.name for m in scene.materials if m.alpha_mode != "OPAQUE"]
if not cutouts:
    raise SystemExit(f"{path}: no MASK or BLEND material, nothing to check")
s_halves = [mitsuba_peer.read_exr(mi, f"smlt_{seed}.exr") for seed in (1, 2)]
if s_halves[0].shape[:2] != (h, w):
    raise SystemExit(f"smlt's image is {s_halves[0].shape[1]}x{s_halves[0].shape[0]}, not {w}x{h}")
with tempfile.TemporaryDirectory() as folder:
    ms = mi.load_dict(mitsuba_peer.scene_dict(mi, scene, 1, w, h, 2 * depth, folder))
    start = time.time()
    halves = [render(ms, seed) for seed in (1, 2)]
    took = time.time() - start
    # which surface each pixel's centre meets first (a cut-away part included)
    sensor = ms.sensors()[0]
    idx = dr.arange(mi.UInt32, w * h)
    pos = mi.Point2f((mi.Float(idx % w) + 0.5) / w, (mi.Float(idx // w) + 0.5) / h)
    ray, _ = sensor.sample_ray(0.0, 0.5, pos, mi.Point2f(0.5))
    si = ms.ray_intersect(ray)
    seen = {s.id(): np.array(si.shape == mi.ShapePtr(s)).reshape(h, w) for s in ms.shapes()}
    # the control: every cut-out opaque
    opaque = gltf_scene.load(path)
    for m in opaque.materials:
        m.alpha_mode = "OPAQUE"
    os.mkdir(f"{folder}/opaque")
    mo = mi.load_dict(mitsuba_peer.scene_dict(mi, opaque, 1, w, h, 2 * depth, f"{folder}/opaque"))
    control = render(mo, 3)
ref = (s_halves[0] + s_halves[1]) / 2
img = (halves[0] + halves[1]) / 2
mi.Bitmap(img.astype(np.float32)).write("mitsuba_cutout.exr")
mi.Bitmap(control.astype(np.float32)).write("mitsuba_opaque.exr")
ds, dm = (s_halves[0] - s_halves[1]) / 2, (halves[0] - halves[1]) / 2
noise_s, noise_m = float(np.sqrt((ds ** 2).mean())), float(np.sqrt((dm ** 2).mean()))
print(f"cut-outs: {', '.join(cutouts)}")
print(f"Mitsuba: 2 x {spp // 2} spp in {took:.0f} s (llvm_ad_rgb, max_depth {2 * depth + 1}), noise (RMSE)"
      f" {noise_m:.2e}; smlt's (2 x {spp // 2} spp, max depth {depth}) {noise_s:.2e}")


def compare(name, mask, a=img, k=1.0):
    """Means and RMSE over the pixels of `mask` of image `a` (its noise k times the variance of
    Mitsuba's SPP mean: 2 for one SPP/2 render) against smlt's: the mean difference with its
    standard error (from the channel means of the noise samples: pixels are independent,
    channels are not) and the RMSE with the one the noises alone give (ratio 1 ± about
    1/sqrt(pixels) where the two agree)."""
    n = int(mask.sum())
    if n == 0:
        return
    x, y = ref[mask].mean(), a[mask].mean()
    se = np.sqrt((ds[mask].mean(1) ** 2).sum() + k * (dm[mask].mean(1) ** 2).sum()) / n
    expected = float(np.sqrt((ds[mask] ** 2).mean() + k * (dm[mask] ** 2).mean()))
    r = float(np.sqrt(((a[mask] - ref[mask]) ** 2).mean()))
    print(f"  {name:20s} {n:5d} px: {x:.5f} vs {y:.5f} ({100 * (y / x - 1):+.3f} % ± {100 * se / x:.3f} %,"
          f" z {(y - x) / se:+6.1f}), RMSE {r:.2e} (noise {expected:.2e}, ratio {r / expected:.2f} ± {1 / np.sqrt(n):.2f})")


rmse = errors(img, ref)[0]
print(f"RMSE {rmse:.2e} against the noises' {np.hypot(noise_s, noise_m):.2e} (ratio {rmse / np.hypot(noise_s, noise_m):.3f});"
      f" mirrored {errors(img[:, ::-1], ref)[0]:.2e}")
material = lambda key: int(key.removeprefix("mesh"))  # noqa: E731
everything = np.ones((h, w), dtype=bool)
print("smlt vs Mitsuba:")
compare("image", everything)
for key, mask in seen.items():
    compare(scene.materials[material(key)].name, mask)
print(f"smlt vs Mitsuba with every cut-out opaque ({spp // 2} spp):")
compare("image", everything, control, k=2.0)
for key, mask in seen.items():
    compare(scene.materials[material(key)].name, mask, control, k=2.0)
PY
