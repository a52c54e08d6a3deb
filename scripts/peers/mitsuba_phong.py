"""smlt's normalised Phong BSDF (shared/src/bsdf.rs) as a Mitsuba 3 Python plugin, `smlt_phong`.

Normalised Phong (Lafortune and Willems 1994), exponent n, reflectance rho:

    f = rho (n + 2)/(2 pi) cos^n(alpha),  sampled with density  (n + 1)/(2 pi) cos^n(alpha),

alpha the angle between the light direction and the mirror direction of the view direction
(the lobe is 0 beyond 90 degrees from the mirror direction). As in smlt the surface scatters on
both sides: it works on the side the view direction lies on, gives 0 when the two directions lie
on opposite sides (or either lies in the surface), and a sampled direction below that side is a
failed sample (pdf 0, weight 0).

Mitsuba's names against smlt's: Mitsuba's `si.wi` (local frame, toward the previous vertex, the
camera side) is smlt's `wo`; Mitsuba's `wo` (toward the light) is smlt's `wi`. Mitsuba's `eval`
includes the cosine factor of its `wo`, and `sample` returns the weight f cos / pdf, here
rho (n + 2)/(n + 1) cos theta. The mirror direction in the local frame, (-x, -y, z), is the
same for either side.

Exponents up to 1e5 make the lobe a fraction of a degree wide, where 1 - cos(alpha) is near the
resolution of float32 near 1, so evaluation and sampling work, as smlt does, with
delta = 1 - cos(alpha) computed without cancellation: delta = |r - w|^2 / 2 for evaluation,
cos^n(alpha) = exp(n ln(1 - delta)) with a series for ln(1 - delta) at small delta, and for
sampling cos(alpha) = exp(x), x = ln(1 - u)/(n + 1), with 1 - cos(alpha) = -expm1(x) by a series
at small |x|.

Usage: `import mitsuba_phong; mitsuba_phong.register()` after `mi.set_variant(...)` (the class
derives from that variant's `mi.BSDF`; take a JIT variant such as `llvm_ad_rgb`, Python plugins
are slow under scalar ones), then `{"type": "smlt_phong", "reflectance": [r, g, b],
"exponent": n}`.
"""

import math

import drjit as dr
import mitsuba as mi

NAME = "smlt_phong"


def ln_one_minus(delta):
    """ln(1 - delta) for delta in [0, 1], accurate for small delta (smlt's `ln_one_minus`)."""
    series = -delta * (1.0 + delta * (0.5 + delta * (1.0 / 3.0)))
    return dr.select(delta < 1e-3, series, dr.log(1.0 - delta))


def one_minus_exp(x):
    """1 - e^x for x <= 0, accurate for small |x| (smlt's `one_minus_exp`)."""
    series = -x * (1.0 + x * (0.5 + x * (1.0 / 6.0)))
    return dr.select(x > -1e-3, series, 1.0 - dr.exp(x))


def phong_lobe(exponent, r, w):
    """cos^n(alpha) of the lobe about the mirror direction `r` for the direction `w` (both unit),
    0 when `w` is more than 90 degrees from `r` (smlt's `phong_lobe`)."""
    delta = dr.minimum(dr.squared_norm(r - w) * 0.5, 1.0)
    return dr.select(dr.dot(r, w) > 0.0, dr.exp(exponent * ln_one_minus(delta)), 0.0)


class SmltPhong(mi.BSDF):
    """smlt's two-sided normalised Phong reflection; properties `reflectance` (an RGB triple)
    and `exponent` (> 0)."""

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.exponent = float(props["exponent"])
        if not self.exponent > 0.0:
            raise ValueError(f"{NAME}: the exponent must be positive, not {self.exponent}")
        rho = props["reflectance"]
        self.reflectance = mi.Color3f(float(rho[0]), float(rho[1]), float(rho[2]))
        # Constants of the lobe: f = f_scale cos^n, pdf = pdf_scale cos^n, f / pdf = weight_scale.
        n = self.exponent
        self.f_scale = (n + 2.0) / (2.0 * math.pi)
        self.pdf_scale = (n + 1.0) / (2.0 * math.pi)
        self.weight_scale = (n + 2.0) / (n + 1.0)
        flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide
        self.m_components = [flags]
        self.m_flags = flags

    def _cosines(self, ctx, si, wo, active):
        """cos theta of `si.wi` and of `wo` on the side `si.wi` lies on (smlt's `facing`: the
        front when si.wi.z >= 0), and where both are positive (and the lobe is enabled)."""
        side = dr.select(si.wi.z >= 0.0, 1.0, -1.0)
        cos_i = side * si.wi.z
        cos_o = side * wo.z
        enabled = mi.Bool(ctx.is_enabled(mi.BSDFFlags.GlossyReflection, 0))
        return cos_o, active & enabled & (cos_i > 0.0) & (cos_o > 0.0)

    def _lobe(self, si, wo):
        """cos^n(alpha) of `wo` about the mirror direction of `si.wi`."""
        return phong_lobe(self.exponent, mi.reflect(si.wi), wo)

    def eval(self, ctx, si, wo, active=True):
        cos_o, valid = self._cosines(ctx, si, wo, active)
        value = self.reflectance * (self.f_scale * self._lobe(si, wo) * cos_o)
        return dr.select(valid, value, 0.0)

    def pdf(self, ctx, si, wo, active=True):
        _, valid = self._cosines(ctx, si, wo, active)
        return dr.select(valid, self.pdf_scale * self._lobe(si, wo), 0.0)

    def eval_pdf(self, ctx, si, wo, active=True):
        cos_o, valid = self._cosines(ctx, si, wo, active)
        lobe = self._lobe(si, wo)
        value = self.reflectance * (self.f_scale * lobe * cos_o)
        return dr.select(valid, value, 0.0), dr.select(valid, self.pdf_scale * lobe, 0.0)

    def sample(self, ctx, si, sample1, sample2, active=True):
        # cos(alpha) = (1 - u)^(1/(n + 1)) = exp(x); sin(alpha)^2 = (1 - cos)(1 + cos).
        x = dr.log(1.0 - sample2.x) / (self.exponent + 1.0)
        cos_a = dr.exp(x)
        sin_a = dr.sqrt(dr.maximum(one_minus_exp(x) * (1.0 + cos_a), 0.0))
        sin_phi, cos_phi = dr.sincos(2.0 * math.pi * sample2.y)
        r = mi.reflect(si.wi)
        wo = dr.normalize(mi.Frame3f(r).to_world(mi.Vector3f(sin_a * cos_phi, sin_a * sin_phi, cos_a)))
        cos_o, valid = self._cosines(ctx, si, wo, active)
        pdf = self.pdf_scale * self._lobe(si, wo)
        valid = valid & (pdf > 0.0)  # smlt: a sample whose density is not positive fails

        bs = mi.BSDFSample3f()
        bs.wo = wo
        bs.pdf = dr.select(valid, pdf, 0.0)
        bs.eta = 1.0
        bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
        bs.sampled_component = mi.UInt32(0)
        weight = self.reflectance * (self.weight_scale * cos_o)
        return bs, dr.select(valid, weight, 0.0)

    def to_string(self):
        return f"SmltPhong[reflectance={self.reflectance}, exponent={self.exponent}]"


def register():
    """Registers the plugin as `smlt_phong` (call after mi.set_variant)."""
    mi.register_bsdf(NAME, lambda props: SmltPhong(props))
