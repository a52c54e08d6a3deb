"""How far Mitsuba 3's paths go in the scene `mitsuba_peer.py` builds: camera rays of a 128x72
view, 16 a pixel, then one BSDF sample after another (`bsdf.sample`, as its `path` integrator
takes them), printing per segment the share of paths cast, hitting, and sampling a direction.
    python3 first_bounce.py SCENE.gltf VIEW   (DRJIT_LIBLLVM_PATH set, as for the peer)
"""
import os, sys, tempfile
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../scripts/peers"))
import mitsuba as mi
mi.set_variant("llvm_ad_rgb")
import drjit as dr
import gltf_scene, mitsuba_gltf, mitsuba_phong
from mitsuba_peer import scene_dict
mitsuba_phong.register(); mitsuba_gltf.register()
scene_path, view = sys.argv[1], int(sys.argv[2])
with tempfile.TemporaryDirectory() as folder:
    scene = mi.load_dict(scene_dict(mi, gltf_scene.load(scene_path), view, 128, 72, 10, folder))
sensor = scene.sensors()[0]
sampler = mi.load_dict({"type": "independent"})
n = 128 * 72 * 16
sampler.seed(1, n)
idx = dr.arange(mi.UInt32, n)
px = mi.Vector2f(mi.Float(idx % 128), mi.Float((idx // 128) % 72))
pos = (px + sampler.next_2d()) / mi.Vector2f(128, 72)
ray, _ = sensor.sample_ray(0.0, 0.5, pos, mi.Point2f(0.5))
active = dr.full(mi.Bool, True, n)
ctx = mi.BSDFContext()
for depth in range(1, 7):
    si = scene.ray_intersect(ray, active)
    valid = si.is_valid() & active
    bsdf = si.bsdf(ray)
    bs, w = bsdf.sample(ctx, si, sampler.next_1d(), sampler.next_2d(), valid)
    ok = valid & (dr.max(w) > 0)
    wo = si.to_world(bs.wo)
    emit = valid & (si.emitter(scene) != None)
    print(f"segment {depth}: cast {dr.count(active)[0]/n:.3f} hit {dr.count(valid)[0]/n:.3f} "
          f"bsdf sample ok {dr.count(ok)[0]/n:.3f} emitter {dr.count(emit)[0]/n:.3f}")
    ray = si.spawn_ray(wo)
    active = ok
