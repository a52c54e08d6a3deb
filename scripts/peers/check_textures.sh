#!/usr/bin/env bash
# Mitsuba 3 against smlt on glTF's textures: the `textured` scene (scenes/textured.gltf: a NEAREST
# checker floor, a bilinear MIRRORED_REPEAT × CLAMP_TO_EDGE banded back wall through a
# KHR_texture_transform, a bilinear striped side wall under a base colour factor, an
# emissiveTexture lamp), the figures docs/results.md quotes.
#  1. The lookups alone: at random points on each textured surface, Mitsuba's `bitmap` as
#     mitsuba_peer.py builds it (through Mitsuba's `ply` texture coordinates, the baked wrap
#     modes, `to_uv`, Mitsuba's sRGB decoding and filters) against gltf_scene.sample (numpy,
#     written from the glTF spec) × the factor; and, to show what the check would catch, the
#     same with v flipped and with the transform's rotation turned the other way.
#  2. The scene: smlt's reference against two Mitsuba renders of SPP/2 each (their mean, and
#     their difference for Mitsuba's noise): means, per-surface means (pixels whose centre sees
#     the surface), RMSE against the noise of the two renders together (smlt's own estimate of
#     its noise, spread over the surfaces as Mitsuba's); and a third Mitsuba render (SPP/2) with
#     KHR_texture_transform's rotation turned the other way, the back wall's difference it makes.
#   scripts/peers/check_textures.sh [OUT]   (default: /tmp/check-textures; SPP=16384)
# Needs smlt built (cargo build --release), the peers' Python packages (requirements.txt) and
# DRJIT_LIBLLVM_PATH (a libLLVM >= 16, for Mitsuba's llvm_ad_rgb variant).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
out="${1:-/tmp/check-textures}"
spp="${SPP:-16384}"
smlt="${CARGO_TARGET_DIR:-$root/target}/release/smlt"
size=(--width 160 --height 120 --max-depth 12)
: "${DRJIT_LIBLLVM_PATH:?set DRJIT_LIBLLVM_PATH to a libLLVM >= 16 (scripts/peers/README.md)}"
export DRJIT_LIBLLVM_PATH
mkdir -p "$out"
cd "$out"
scene="$root/scenes/textured.gltf"
PYTHONPATH="$root/scripts/peers" python3 - "$scene" <<'PY'
import sys, tempfile
import drjit as dr
import mitsuba as mi
import numpy as np
mi.set_variant("llvm_ad_rgb")
import gltf_scene, mitsuba_peer
from peer_common import write_ply

scene = gltf_scene.load(sys.argv[1])
example = gltf_scene.load(sys.argv[1], rotation="listing")
rng = np.random.default_rng(7)
rgb = lambda c: (lambda a: a.T if a.shape[0] == 3 and a.ndim == 2 else a)(np.array(c))  # noqa: E731 (n, 3)
print("lookups (20000 points a texture; / the factor): max |Mitsuba - spec| | v flipped | rotation the other way")
with tempfile.TemporaryDirectory() as folder:
    for m, mat in enumerate(scene.materials):
        if not mat.textures:
            continue
        tris, uv = scene.triangles[m], scene.texcoords[m][:, :, :, mat.textures[0].tex_coord]
        # the mesh and its bitmaps as the converter builds them
        mesh_uv, reflectance, radiance = mitsuba_peer.mesh_textures(mi, mat, uv, folder)
        path = f"{folder}/mesh{m}.ply"
        write_ply(path, tris, mesh_uv)
        ms = mi.load_dict({"type": "scene", "s": {"type": "ply", "filename": path, "face_normals": True}})
        for slot, bitmap in (("base_color_texture", reflectance), ("emissive_texture", radiance)):
            tex = getattr(mat, slot)
            if tex is None:
                continue
            factor = np.array(mat.albedo if slot == "base_color_texture" else mat.emission)
            # random points: a triangle by area, uniform barycentrics
            area = np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]), axis=1)
            k = rng.choice(len(tris), 20000, p=area / area.sum())
            r1, r2 = rng.random(20000), rng.random(20000)
            s = np.sqrt(r1)
            b = np.stack([1 - s, s * (1 - r2), s * r2], axis=1)[:, :, None]
            p, st = (tris[k] * b).sum(1), (uv[k] * b).sum(1)
            n = np.cross(tris[k, 1] - tris[k, 0], tris[k, 2] - tris[k, 0])
            n /= np.linalg.norm(n, axis=1)[:, None]
            # Mitsuba: the mesh alone, hit from along its normal; its bitmap at the hit
            o = p + 1e-2 * n
            si = ms.ray_intersect(mi.Ray3f(mi.Point3f(*o.T.astype(np.float32)), mi.Vector3f(*(-n).T.astype(np.float32))))
            bitmap = mi.load_dict(bitmap)
            got = rgb(bitmap.eval(si))
            si.uv = mi.Point2f(si.uv.x, 1 - si.uv.y)
            flipped = rgb(bitmap.eval(si))
            # the spec: 8-bit texels (Mitsuba's PNG reader, no conversion), IEC 61966-2-1 decoding here
            raw = mitsuba_peer.decode(mi, tex, folder, srgb=False)
            texels = gltf_scene.srgb_to_linear(np.round(raw * 255) / 255)
            want = gltf_scene.sample(texels, tex, tex.coordinates(st)) * factor
            other = getattr(example.materials[m], slot)
            turned = gltf_scene.sample(texels, other, other.coordinates(st)) * factor
            hits = np.array(si.is_valid())
            d = np.abs(got - want).max(axis=1) / factor.max()
            print(f"  {mat.name} {slot.split('_texture')[0]}: {d.max():.2e} ({hits.mean() * 100:.1f} % hit;"
                  f" {(d > 1e-4).mean() * 100:.2f} % over 1e-4) | {np.abs(flipped - want).max() / factor.max():.3f}"
                  f" | {np.abs(turned - want).max() / factor.max():.3f}, mean {want.mean():.4f} -> {turned.mean():.4f}")
PY
"$smlt" reference "$scene" --device cpu --spp "$spp" "${size[@]}" --out ref_textured.exr | { grep -E "noise|time|cached" || true; }
PYTHONPATH="$root/scripts/peers" python3 - "$scene" "$spp" "${size[@]}" <<'PY'
import sys, tempfile, time
import drjit as dr
import mitsuba as mi
import numpy as np
mi.set_variant("llvm_ad_rgb")
import gltf_scene, mitsuba_peer
from peer_common import errors

import json
path, spp = sys.argv[1], int(sys.argv[2])
w, h, depth = int(sys.argv[4]), int(sys.argv[6]), int(sys.argv[8])
noise_s = json.load(open("ref_textured.exr.json"))["noise_rmse"]  # smlt's estimate of its RMSE
scene = gltf_scene.load(path)
ref = mitsuba_peer.read_exr(mi, "ref_textured.exr")
with tempfile.TemporaryDirectory() as folder:
    d = mitsuba_peer.scene_dict(mi, scene, 1, w, h, depth, folder)
    ms = mi.load_dict(d)
    start = time.time()
    halves = [np.array(ms.integrator().render(ms, seed=seed, spp=spp // 2)) for seed in (1, 2)]
    took = time.time() - start
    # which surface each pixel's centre sees
    sensor = ms.sensors()[0]
    idx = dr.arange(mi.UInt32, w * h)
    pos = mi.Point2f((mi.Float(idx % w) + 0.5) / w, (mi.Float(idx // w) + 0.5) / h)
    ray, _ = sensor.sample_ray(0.0, 0.5, pos, mi.Point2f(0.5))
    si = ms.ray_intersect(ray)
    seen = {s.id(): np.array(si.shape == mi.ShapePtr(s)).reshape(h, w) for s in ms.shapes()}
    # KHR_texture_transform's rotation read the other way (gltf_scene.py): what the check tells apart
    dt = mitsuba_peer.scene_dict(mi, gltf_scene.load(path, rotation="listing"), 1, w, h, depth, folder)
    mt = mi.load_dict(dt)
    turned = np.array(mt.integrator().render(mt, seed=3, spp=spp // 2))
img = (halves[0] + halves[1]) / 2
mi.Bitmap(img.astype(np.float32)).write("mitsuba_textured.exr")
diff = halves[0] - halves[1]  # (h, w, 3): Mitsuba's noise at SPP is |diff| / 2
noise_m = float(np.sqrt((diff ** 2).mean())) / 2
scale = np.hypot(1.0, noise_s / noise_m)  # smlt's noise taken as Mitsuba's times the ratio of the two
rmse = errors(img, ref)[0]
print(f"Mitsuba: {spp} spp in {took:.0f} s (llvm_ad_rgb), noise (RMSE) {noise_m:.2e}; smlt's {noise_s:.2e}")


def compare(name, mask, a=img):
    """Means and RMSE over the pixels of `mask`, with the noise expected of the two renders'
    difference (its RMSE, and the standard error of the mean difference)."""
    expected = float(np.sqrt((diff[mask] ** 2).mean())) / 2 * scale
    x, y = ref[mask].mean(), a[mask].mean()
    r = float(np.sqrt(((a[mask] - ref[mask]) ** 2).mean()))
    print(f"  {name:22s} {mask.sum():5d} px: smlt {x:.5f}, Mitsuba {y:.5f} ({100 * (y / x - 1):+.3f} %"
          f" ± {100 * expected / np.sqrt(mask.sum()) / x:.3f} %), RMSE {r:.2e} (noise {expected:.2e})")


print(f"RMSE {rmse:.2e} against the noise's {noise_m * scale:.2e} (ratio {rmse / noise_m / scale:.3f}); mirrored"
      f" {errors(img[:, ::-1], ref)[0]:.2e}, upside down {errors(img[::-1], ref)[0]:.2e}")
everything = np.ones((h, w), dtype=bool)
compare("image", everything)
lamp = [k for k in seen if scene.materials[int(k.removeprefix("mesh"))].emissive_texture]
compare("image but the lamp", ~np.any([seen[k] for k in lamp], axis=0))
for key, mask in seen.items():
    if mask.any():
        compare(scene.materials[int(key.removeprefix("mesh"))].name, mask)
wall = [k for k in seen if scene.materials[int(k.removeprefix("mesh"))].name == "banded wall"]
if wall:
    print(f"with the rotation turned the other way ({spp // 2} spp):")
    compare("banded wall", seen[wall[0]], turned)
PY
