"""A rough thin wall of glass (glTF's KHR_materials_transmission without KHR_materials_volume:
light passes without bending) as a Mitsuba 3 Python plugin, `smlt_thin`, written from the
extension's text, not from smlt's code. Its transmission lobe is its reflection lobe "sampled
along the line of sight through the surface": the light direction mirrored in the plane,

    reflection:   f = F(V.H) D(H) G2(V, L) / (4 |N.V| |N.L|),                  H = norm(V + L),
    transmission: f = tint (1 - F(V.H)) D(H) G2(V, L') / (4 |N.V| |N.L|),     H = norm(V + L'),

L' = L mirrored in the surface's plane, D GGX of alpha, G2 the height-correlated Smith term
1 / (1 + Lambda(V) + Lambda(L')), Lambda(w) = (sqrt(1 + alpha^2 tan^2 theta) - 1) / 2, and F the
unpolarised Fresnel reflectance of index `ior` (Mitsuba's `mi.fresnel`; smlt's dielectrics
take the exact factor, as Mitsuba's do, not the core BRDF's Schlick approximation). Two-sided;
no 1/eta^2 (the light leaves the wall into the medium it came from).

Sampling is this plugin's own: a visible normal by Mitsuba's GGX sampler, the reflection about
it (failing below the plane), kept with probability F and otherwise mirrored through the plane. Mitsuba's `si.wi` is
smlt's `wo` (towards the camera). Usage: `import mitsuba_thin; mitsuba_thin.register()` after
`mi.set_variant(...)` (a JIT variant such as `llvm_ad_rgb`), then `{"type": "smlt_thin",
"alpha": a, "ior": 1.5, "tint": [r, g, b]}`.
"""

import drjit as dr
import mitsuba as mi

NAME = "smlt_thin"


def mirrored(w):
    return mi.Vector3f(w.x, w.y, -w.z)


class SmltThin(mi.BSDF):
    """A rough thin glass wall: GGX `alpha`, index `ior`, transmission `tint`."""

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.alpha = float(props["alpha"])
        self.ior = float(props["ior"])
        self.tint = mi.Color3f(*(float(c) for c in props["tint"]))
        self.ggx = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, self.alpha, True)
        sides = mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide
        self.m_components = [mi.BSDFFlags.GlossyReflection | sides, mi.BSDFFlags.GlossyTransmission | sides]
        self.m_flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.GlossyTransmission | sides

    def _lambda(self, w):
        tan2 = (w.x * w.x + w.y * w.y) / (w.z * w.z)
        return (dr.sqrt(1.0 + self.alpha * self.alpha * tan2) - 1.0) * 0.5

    def _terms(self, v, l):
        """(f without the tint, the density, whether it transmits) for v above the plane."""
        passes = l.z < 0.0
        lr = dr.select(passes, mirrored(l), l)
        h = dr.normalize(v + lr)
        c = dr.dot(v, h)
        d = self.ggx.eval(h)
        g2 = 1.0 / (1.0 + self._lambda(v) + self._lambda(lr))
        f_r = mi.fresnel(c, self.ior)[0]
        share = dr.select(passes, 1.0 - f_r, f_r)
        f = share * d * g2 / (4.0 * v.z * lr.z)
        pdf = share * self.ggx.pdf(v, h) / (4.0 * c)
        valid = (v.z > 0.0) & (lr.z > 0.0) & (c > 0.0) & (dr.dot(lr, h) > 0.0)
        return dr.select(valid, f, 0.0), dr.select(valid, pdf, 0.0), passes

    def _side(self, si, wo):
        side = dr.select(si.wi.z >= 0.0, 1.0, -1.0)
        return mi.Vector3f(si.wi.x, si.wi.y, side * si.wi.z), mi.Vector3f(wo.x, wo.y, side * wo.z)

    def eval(self, ctx, si, wo, active=True):
        v, l = self._side(si, wo)
        f, _, passes = self._terms(v, l)
        value = dr.select(passes, self.tint * f, mi.Color3f(f))
        return dr.select(active, value * dr.abs(l.z), 0.0)

    def pdf(self, ctx, si, wo, active=True):
        v, l = self._side(si, wo)
        _, pdf, _ = self._terms(v, l)
        return dr.select(active, pdf, 0.0)

    def eval_pdf(self, ctx, si, wo, active=True):
        return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

    def sample(self, ctx, si, sample1, sample2, active=True):
        side = dr.select(si.wi.z >= 0.0, 1.0, -1.0)
        v = mi.Vector3f(si.wi.x, si.wi.y, side * si.wi.z)
        m, _ = self.ggx.sample(v, sample2)
        r = mi.reflect(v, m)
        passes = sample1 >= mi.fresnel(dr.dot(v, m), self.ior)[0]
        l = dr.select(passes, mirrored(r), r)
        f, pdf, _ = self._terms(v, l)
        # A reflection below the plane is no sample of either lobe (its mirror image would be
        # the other lobe's direction, at another density).
        valid = active & (pdf > 0.0) & (r.z > 0.0)
        bs = mi.BSDFSample3f()
        bs.wo = mi.Vector3f(l.x, l.y, side * l.z)
        bs.eta = 1.0
        bs.pdf = dr.select(valid, pdf, 0.0)
        bs.sampled_type = dr.select(passes, mi.UInt32(+mi.BSDFFlags.GlossyTransmission),
                                    mi.UInt32(+mi.BSDFFlags.GlossyReflection))
        bs.sampled_component = dr.select(passes, mi.UInt32(1), mi.UInt32(0))
        value = dr.select(passes, self.tint * f, mi.Color3f(f)) * dr.abs(l.z) / dr.maximum(pdf, 1e-30)
        return bs, dr.select(valid, value, 0.0)

    def to_string(self):
        return f"SmltThin[alpha={self.alpha}, ior={self.ior}, tint={self.tint}]"


def register():
    """Registers the plugin as `smlt_thin` (call after mi.set_variant)."""
    mi.register_bsdf(NAME, lambda props: SmltThin(props))


