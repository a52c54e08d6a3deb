"""glTF's sheen (KHR_materials_sheen) as a Mitsuba 3 Python plugin, `smlt_sheen`, written from
the extension's implementation notes, not from smlt's code: a layer of micro-fibres over a
nested BSDF `base`,

    f = color f_sheen + f_base s,   s = min(1 - max(color) E(|N.V|), 1 - max(color) E(|N.L|)),
    f_sheen = D V,   D = (2 + 1/a) sin(theta_h)^(1/a) / (2 pi),   a = roughness^2,
    V = 1 / ((1 + Lambda(N.V) + Lambda(N.L)) 4 N.V N.L),
    Lambda(c) = exp(L(c)) for c < 0.5, exp(2 L(0.5) - L(1 - c)) otherwise,
    L(x) = A / (1 + B x^C) + D x + E, its coefficients mixed by (1 - a)^2 between the
    extension's two fits,

E(c) the directional albedo of f_sheen, computed here at construction by a quadrature of this
file's own f_sheen (numpy, 512 cosines on a square-root spacing, interpolated linearly). As in
smlt (the extension leaves these open): the roughness is kept in [0.07, 1] and s at 0 or more.
Two-sided, as smlt's surfaces are.

Sampling is this plugin's own: the layer with probability 1/4 by cosine-weighted directions,
else the base's own sampling. Usage: `import mitsuba_sheen; mitsuba_sheen.register()` after
`mi.set_variant(...)` (a JIT variant such as `llvm_ad_rgb`), then `{"type": "smlt_sheen",
"color": [r, g, b], "roughness": r, "base": {...any BSDF...}}`.
"""

import math

import drjit as dr
import mitsuba as mi
import numpy as np

NAME = "smlt_sheen"
P_LAYER = 0.25
CURVE = 512


def fitted_l(x, a, xp=np):
    t = (1.0 - a) ** 2
    mix = lambda one, zero: one * (1.0 - t) + zero * t  # noqa: E731
    big_a, b, c = mix(21.5473, 25.3245), mix(3.82987, 3.32435), mix(0.19823, 0.16801)
    d, e = mix(-1.97760, -1.27393), mix(-4.32054, -4.85967)
    return big_a / (1.0 + b * xp.power(x, c)) + d * x + e


def lambda_sheen(c, a, xp=np):
    c = xp.abs(c) if xp is np else dr.abs(c)
    low = (xp.exp if xp is np else dr.exp)(fitted_l(c, a, xp))
    high = (xp.exp if xp is np else dr.exp)(2.0 * fitted_l(0.5, a, xp) - fitted_l(1.0 - c, a, xp))
    return xp.where(c < 0.5, low, high) if xp is np else dr.select(c < 0.5, low, high)


def albedo_curve(a):
    """E at cosines (i / (CURVE - 1))^2 (the first 1e-4) by a midpoint quadrature in (cos^2, phi)."""
    n_t, n_phi = 600, 300
    t = (np.arange(n_t) + 0.5) / n_t
    c = t * t
    phi = (np.arange(n_phi) + 0.5) / n_phi * np.pi
    cc, pp = np.meshgrid(c, phi, indexing="ij")
    ss = np.sqrt(1.0 - cc * cc)
    wi = np.stack([ss * np.cos(pp), ss * np.sin(pp), cc], -1)
    weight = (2.0 * t / n_t)[:, None] * (2.0 * np.pi / n_phi)
    out = []
    for x in np.linspace(0.0, 1.0, CURVE):
        mu = max(x * x, 1e-4)
        wo = np.array([math.sqrt(1.0 - mu * mu), 0.0, mu])
        h = wi + wo
        h /= np.linalg.norm(h, axis=-1, keepdims=True)
        d = (2.0 + 1.0 / a) * np.power(np.clip(1.0 - h[..., 2] ** 2, 0.0, 1.0), 0.5 / a) / (2.0 * np.pi)
        f_cos = d / ((1.0 + lambda_sheen(mu, a) + lambda_sheen(cc, a)) * 4.0 * mu)
        out.append(float((f_cos * weight).sum()))
    return out


class SmltSheen(mi.BSDF):
    """A sheen of colour `color` and roughness `roughness` over the BSDF `base`."""

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.base = props["base"]
        self.color = mi.Color3f(*(float(c) for c in props["color"]))
        self.color_max = max(float(c) for c in props["color"])
        r = min(max(float(props["roughness"]), 0.07), 1.0)
        self.a = r * r
        self.curve = mi.Float(albedo_curve(self.a))
        sides = mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide
        self.m_components = [self.base.flags(), mi.BSDFFlags.GlossyReflection | sides]
        self.m_flags = self.base.flags() | mi.BSDFFlags.GlossyReflection | sides

    def _albedo(self, c):
        x = dr.clip(dr.sqrt(dr.abs(c)), 0.0, 1.0) * (CURVE - 1)
        i = dr.minimum(mi.UInt32(x), CURVE - 2)
        f = x - mi.Float(i)
        e0, e1 = dr.gather(mi.Float, self.curve, i), dr.gather(mi.Float, self.curve, i + 1)
        return e0 + (e1 - e0) * f

    def _local(self, si, wo):
        side = dr.select(si.wi.z >= 0.0, 1.0, -1.0)
        return mi.Vector3f(si.wi.x, si.wi.y, side * si.wi.z), mi.Vector3f(wo.x, wo.y, side * wo.z)

    def _scaling(self, v, l):
        e = dr.maximum(self._albedo(v.z), self._albedo(l.z))
        return dr.maximum(1.0 - self.color_max * e, 0.0)

    def _layer(self, v, l):
        """f_sheen for both directions above the surface."""
        h = dr.normalize(v + l)
        d = (2.0 + 1.0 / self.a) * dr.power(dr.clip(1.0 - h.z * h.z, 0.0, 1.0), 0.5 / self.a) / (2.0 * math.pi)
        vis = 1.0 / ((1.0 + lambda_sheen(v.z, self.a, dr) + lambda_sheen(l.z, self.a, dr)) * 4.0 * v.z * l.z)
        return d * vis

    def eval(self, ctx, si, wo, active=True):
        v, l = self._local(si, wo)
        above = active & (v.z > 0.0) & (l.z > 0.0)
        layer = dr.select(above, self.color * self._layer(v, l) * l.z, 0.0)
        return self.base.eval(ctx, si, wo, active) * self._scaling(v, l) + layer

    def pdf(self, ctx, si, wo, active=True):
        v, l = self._local(si, wo)
        above = active & (v.z > 0.0) & (l.z > 0.0)
        layer = dr.select(above, l.z / math.pi, 0.0)
        return (1.0 - P_LAYER) * self.base.pdf(ctx, si, wo, active) + P_LAYER * layer

    def eval_pdf(self, ctx, si, wo, active=True):
        return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

    def sample(self, ctx, si, sample1, sample2, active=True):
        side = dr.select(si.wi.z >= 0.0, 1.0, -1.0)
        v = mi.Vector3f(si.wi.x, si.wi.y, side * si.wi.z)
        layer = sample1 < P_LAYER
        bs_base, weight_base = self.base.sample(ctx, si, (sample1 - P_LAYER) / (1.0 - P_LAYER), sample2, active)
        base_delta = mi.has_flag(bs_base.sampled_type, mi.BSDFFlags.Delta)
        l_layer = mi.warp.square_to_cosine_hemisphere(sample2)
        bs = mi.BSDFSample3f()
        bs.eta = dr.select(layer, 1.0, bs_base.eta)
        bs.wo = dr.select(layer, mi.Vector3f(l_layer.x, l_layer.y, side * l_layer.z), bs_base.wo)
        bs.sampled_component = dr.select(layer, mi.UInt32(1), mi.UInt32(0))
        bs.sampled_type = dr.select(layer, mi.UInt32(+mi.BSDFFlags.GlossyReflection), bs_base.sampled_type)
        valid = active & (v.z > 0.0) & dr.select(layer, l_layer.z > 0.0, bs_base.pdf > 0.0)
        f, pdf = self.eval_pdf(ctx, si, bs.wo, valid)
        mixture = f / dr.maximum(pdf, 1e-30)
        # A delta of the base: its weight, scaled, over the base's share of the choice.
        _, l = self._local(si, bs.wo)
        delta = base_delta & ~layer
        weight = dr.select(delta, weight_base * self._scaling(v, l) / (1.0 - P_LAYER), mixture)
        bs.pdf = dr.select(delta, bs_base.pdf * (1.0 - P_LAYER), pdf)
        valid = valid & (bs.pdf > 0.0)
        bs.pdf = dr.select(valid, bs.pdf, 0.0)
        return bs, dr.select(valid, weight, 0.0)

    def to_string(self):
        return f"SmltSheen[color={self.color}, a={self.a}, base={self.base}]"


def register():
    """Registers the plugin as `smlt_sheen` (call after mi.set_variant)."""
    mi.register_bsdf(NAME, lambda props: SmltSheen(props))
