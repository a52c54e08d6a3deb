# smlt_gltf's sample against its own eval and pdf: weight = eval / pdf and bs.pdf = pdf(wo) for
# every sampled direction, and the pdf integrates to at most 1 over the hemisphere.
import os
import sys
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../../scripts/peers"))
import mitsuba as mi
mi.set_variant("llvm_ad_rgb")
import drjit as dr
import numpy as np
import mitsuba_gltf
mitsuba_gltf.register()
n = 200000
rng = np.random.default_rng(3)
for props in [dict(base_color=[0.73, 0.73, 0.67], metallic=0.0, alpha=1.0, f0=[0.04]*3, f90=1.0),
              dict(base_color=[0.8, 0.2, 0.1], metallic=0.0, alpha=0.1, f0=[0.04]*3, f90=1.0),
              dict(base_color=[1.0, 0.78, 0.34], metallic=1.0, alpha=0.12, f0=[0.04]*3, f90=1.0),
              dict(base_color=[0.5, 0.5, 0.5], metallic=0.4, alpha=0.3, f0=[0.04]*3, f90=1.0),
              dict(base_color=[0.5, 0.5, 0.5], metallic=0.0, alpha=0.0, f0=[0.04]*3, f90=1.0),
              dict(base_color=[0.5, 0.5, 0.5], metallic=0.0, alpha=0.5, f0=[0.0]*3, f90=0.0)]:
    bsdf = mi.load_dict({"type": "smlt_gltf", **props})
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    z = rng.uniform(-1, 1, n); phi = rng.uniform(0, 2*np.pi, n); r = np.sqrt(1 - z*z)
    si.wi = mi.Vector3f(r*np.cos(phi), r*np.sin(phi), z)
    ctx = mi.BSDFContext()
    bs, w = bsdf.sample(ctx, si, mi.Float(rng.uniform(size=n)), mi.Point2f(rng.uniform(size=n), rng.uniform(size=n)))
    ok = bs.pdf > 0
    glossy = ok & ~mi.has_flag(bs.sampled_type, mi.BSDFFlags.Delta)
    e, p = bsdf.eval(ctx, si, bs.wo), bsdf.pdf(ctx, si, bs.wo)
    rel_pdf = dr.max(dr.select(glossy, dr.abs(p - bs.pdf) / bs.pdf, 0.0))
    rel_w = dr.max(dr.select(glossy, dr.max(dr.abs(e / p - w)) / dr.maximum(dr.max(w), 1e-6), 0.0))
    # the density's integral over the sphere (uniform directions)
    z2 = rng.uniform(-1, 1, n); phi2 = rng.uniform(0, 2*np.pi, n); r2 = np.sqrt(1 - z2*z2)
    wo = mi.Vector3f(r2*np.cos(phi2), r2*np.sin(phi2), z2)
    front = dr.zeros(mi.SurfaceInteraction3f, n); front.sh_frame = si.sh_frame
    front.wi = dr.normalize(mi.Vector3f(0.3, 0.1, 0.8))
    integral = dr.mean(bsdf.pdf(ctx, front, wo)) * 4 * np.pi
    print(f"{props['metallic']=} {props['alpha']=}: sampled {dr.count(ok)[0]/n:.3f} "
          f"max rel pdf diff {rel_pdf[0]:.2e} max rel weight diff {rel_w[0]:.2e} pdf integral {integral[0]:.3f}")
