"""Mitsuba 3's own ray casting on smlt's rays: the records of `cargo run --release -p smlt-bench
--example pt_rays -- SCENE VIEW RAYS.f32` (pt's rays, the bench's ceiling log), cast as one batch
per kind through the scene `mitsuba_peer.py` builds, `ray_intersect_preliminary` for the
closest-hit rays and `ray_test` for the occlusion rays, each timed after a warm-up (the JIT's
compilation), and the share that hit. A measurement for docs/results.md, not a test.

    python3 scripts/peers/mitsuba_rays.py SCENE.gltf VIEW RAYS.f32 [--variant llvm_ad_rgb] [--repeats 10]
"""

import argparse
import os
import sys
import tempfile
import time

import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("view", type=int)
    ap.add_argument("rays")
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--repeats", type=int, default=10, help="copies of the log in one batch")
    a = ap.parse_args()
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import mitsuba as mi

    mi.set_variant(a.variant)
    import drjit as dr
    import gltf_scene
    import mitsuba_gltf
    import mitsuba_phong
    from mitsuba_peer import scene_dict

    mitsuba_phong.register()
    mitsuba_gltf.register()
    with tempfile.TemporaryDirectory() as folder:
        scene = mi.load_dict(scene_dict(mi, gltf_scene.load(a.scene), a.view, 128, 72, 10, folder))
    records = np.fromfile(a.rays, dtype="<f4").reshape(-1, 9)
    for kind, name in [(1, "closest-hit"), (2, "occlusion")]:
        q = np.tile(records[records[:, 8] == kind], (a.repeats, 1))
        rates = []
        for attempt in range(4):
            ray = mi.Ray3f(mi.Point3f(q[:, 0], q[:, 1], q[:, 2]), mi.Vector3f(q[:, 4], q[:, 5], q[:, 6]))
            # A new maxt each attempt, so that no result is reused.
            ray.maxt = mi.Float(np.minimum(q[:, 7], 3e38) * (1 - 1e-7 * attempt))
            dr.eval(ray)
            dr.sync_thread()
            start = time.perf_counter()
            found = scene.ray_intersect_preliminary(ray).is_valid() if kind == 1 else scene.ray_test(ray)
            count = dr.count(found)
            dr.eval(count)
            dr.sync_thread()
            rates.append(len(q) / (time.perf_counter() - start))
            share = count[0] / len(q)
        # The first attempt compiles the kernel.
        print(f"{name}: {len(q)} rays, {max(rates[1:]) / 1e6:.2f} M rays/s at best of {len(rates) - 1}, "
              f"{share:.3f} hit ({a.variant})")


if __name__ == "__main__":
    main()
