"""glTF's clear coat (KHR_materials_clearcoat) as a Mitsuba 3 Python plugin, `smlt_coat`, written
from the extension's text, not from smlt's code: a specular layer over a nested BSDF `base`,

    f = (1 - w) f_base + w f_layer,   w = clearcoat (0.04 + 0.96 (1 - |V.N|)^5),
    f_layer = V_GGX D_GGX  (the core BRDF's specular term without its Fresnel factor),
    V_GGX = 0.5 / (N.L sqrt(N.V^2 (1 - a^2) + a^2) + N.V sqrt(N.L^2 (1 - a^2) + a^2)),
    D_GGX = a^2 / (pi ((N.H)^2 (a^2 - 1) + 1)^2),   a = clearcoatRoughness^2,

V the viewer (Mitsuba's `si.wi`: its path tracer carries radiance from the camera). Where a is
below 1e-3 (smlt's smooth limit) the layer is a mirror: a delta of weight w. Two-sided, as
smlt's surfaces are; the coat's normal is the shading frame's.

Sampling is this plugin's own: the layer with probability 1/2 (a rough one by Mitsuba's GGX
visible-normal sampler), else the base's own sampling. Usage: `import mitsuba_coat;
mitsuba_coat.register()` after `mi.set_variant(...)` (a JIT variant such as `llvm_ad_rgb`), then
`{"type": "smlt_coat", "clearcoat": c, "alpha": a, "base": {...any BSDF...}}`.
"""

import math

import drjit as dr
import mitsuba as mi

NAME = "smlt_coat"
SMOOTH_ALPHA = 1e-3
P_LAYER = 0.5


class SmltCoat(mi.BSDF):
    """A clear coat of intensity `clearcoat` and GGX roughness `alpha` over the BSDF `base`."""

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.base = props["base"]
        self.clearcoat = float(props["clearcoat"])
        self.alpha = float(props["alpha"])
        self.smooth = self.alpha < SMOOTH_ALPHA
        lobe = mi.BSDFFlags.DeltaReflection if self.smooth else mi.BSDFFlags.GlossyReflection
        sides = mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide
        self.m_components = [self.base.flags(), lobe | sides]
        self.m_flags = self.base.flags() | lobe | sides
        self.ggx = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, max(self.alpha, SMOOTH_ALPHA), True)

    @staticmethod
    def _local(si, wo):
        """V and L turned to V's side (both sides scatter, as smlt's surfaces do)."""
        side = dr.select(si.wi.z >= 0.0, 1.0, -1.0)
        return mi.Vector3f(si.wi.x, si.wi.y, side * si.wi.z), mi.Vector3f(wo.x, wo.y, side * wo.z)

    def _weight(self, v):
        x = dr.clip(1.0 - dr.abs(v.z), 0.0, 1.0)
        return self.clearcoat * (0.04 + 0.96 * x * x * x * x * x)

    def _layer(self, v, l):
        """f_layer for both directions above the surface (0 for a smooth layer)."""
        if self.smooth:
            return mi.Float(0.0)
        h = dr.normalize(v + l)
        a2 = self.alpha * self.alpha
        n_v, n_l, n_h = v.z, l.z, h.z
        vis = 0.5 / (n_l * dr.sqrt(n_v * n_v * (1.0 - a2) + a2) + n_v * dr.sqrt(n_l * n_l * (1.0 - a2) + a2))
        d = a2 / (math.pi * dr.square(n_h * n_h * (a2 - 1.0) + 1.0))
        return vis * d

    def _layer_pdf(self, v, l):
        if self.smooth:
            return mi.Float(0.0)
        h = dr.normalize(v + l)
        return self.ggx.pdf(v, h) / (4.0 * dr.dot(v, h))

    def eval(self, ctx, si, wo, active=True):
        v, l = self._local(si, wo)
        w = self._weight(v)
        above = active & (v.z > 0.0) & (l.z > 0.0)
        layer = dr.select(above, w * self._layer(v, l) * l.z, 0.0)
        return self.base.eval(ctx, si, wo, active) * (1.0 - w) + layer

    def pdf(self, ctx, si, wo, active=True):
        v, l = self._local(si, wo)
        above = active & (v.z > 0.0) & (l.z > 0.0)
        layer = dr.select(above, self._layer_pdf(v, l), 0.0)
        return (1.0 - P_LAYER) * self.base.pdf(ctx, si, wo, active) + P_LAYER * layer

    def eval_pdf(self, ctx, si, wo, active=True):
        return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

    def sample(self, ctx, si, sample1, sample2, active=True):
        side = dr.select(si.wi.z >= 0.0, 1.0, -1.0)
        v = mi.Vector3f(si.wi.x, si.wi.y, side * si.wi.z)
        w = self._weight(v)
        layer = sample1 < P_LAYER
        # The base's own sample, from the rest of sample1.
        bs_base, weight_base = self.base.sample(ctx, si, (sample1 - P_LAYER) / (1.0 - P_LAYER), sample2, active)
        base_delta = mi.has_flag(bs_base.sampled_type, mi.BSDFFlags.Delta)
        # The layer's direction.
        m = mi.Normal3f(0.0, 0.0, 1.0) if self.smooth else self.ggx.sample(v, sample2)[0]
        l_layer = mi.reflect(v, m)
        wo_layer = mi.Vector3f(l_layer.x, l_layer.y, side * l_layer.z)
        bs = mi.BSDFSample3f()
        bs.eta = dr.select(layer, 1.0, bs_base.eta)
        bs.wo = dr.select(layer, wo_layer, bs_base.wo)
        bs.sampled_component = dr.select(layer, mi.UInt32(1), mi.UInt32(0))
        if self.smooth:
            layer_type = mi.UInt32(+mi.BSDFFlags.DeltaReflection)
        else:
            layer_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
        bs.sampled_type = dr.select(layer, layer_type, bs_base.sampled_type)
        valid = active & (v.z > 0.0) & dr.select(layer, l_layer.z > 0.0, bs_base.pdf > 0.0)
        # A delta's weight: its share over its probability; any other direction: the whole
        # mixture's f cos over its density.
        f, pdf = self.eval_pdf(ctx, si, bs.wo, valid)
        mixture = f / dr.maximum(pdf, 1e-30)
        if self.smooth:
            weight = dr.select(layer, w / P_LAYER, dr.select(base_delta, weight_base * (1.0 - w) / (1.0 - P_LAYER), mixture))
            bs.pdf = dr.select(layer, P_LAYER, dr.select(base_delta, bs_base.pdf * (1.0 - P_LAYER), pdf))
        else:
            weight = dr.select(base_delta & ~layer, weight_base * (1.0 - w) / (1.0 - P_LAYER), mixture)
            bs.pdf = dr.select(base_delta & ~layer, bs_base.pdf * (1.0 - P_LAYER), pdf)
        valid = valid & (bs.pdf > 0.0)
        bs.pdf = dr.select(valid, bs.pdf, 0.0)
        return bs, dr.select(valid, weight, 0.0)

    def to_string(self):
        return f"SmltCoat[clearcoat={self.clearcoat}, alpha={self.alpha}, base={self.base}]"


def register():
    """Registers the plugin as `smlt_coat` (call after mi.set_variant)."""
    mi.register_bsdf(NAME, lambda props: SmltCoat(props))
