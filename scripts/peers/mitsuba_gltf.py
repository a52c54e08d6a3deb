"""glTF 2.0's metallic-roughness BRDF (the spec's Appendix B, with KHR_materials_specular) as a
Mitsuba 3 Python plugin, `smlt_gltf`, written from the spec, not from smlt's code:

    f = (1 - metallic) [(1 - F_d) base / pi + F_d V D] + metallic F_m V D,
    F_d = f0 + (f90 - f0) (1 - |V.H|)^5,   F_m = base + (1 - base) (1 - |V.H|)^5,
    V = 0.5 / (N.L sqrt(N.V^2 (1 - a^2) + a^2) + N.V sqrt(N.L^2 (1 - a^2) + a^2)),
    D = a^2 / (pi ((N.H)^2 (a^2 - 1) + 1)^2),   a = roughness^2,

with f0 = min(((ior - 1)/(ior + 1))^2 specularColor, 1) specular and f90 = specular. Where a is
below 1e-3 (smlt's smooth limit) the specular lobe is a mirror: a delta of weight
(1 - metallic) F_d + metallic F_m at H = N. The surface scatters on both sides, as smlt's do.

KHR_materials_anisotropy (optional properties `alpha_t`, `alpha_b` and `direction`, a world
vector: the direction of alpha_t, which the caller takes from the mesh's tangent frame): V and D
become the extension's V_GGX_anisotropic and D_GGX_anisotropic,

    V = 0.5 / (N.L |(at T.V, ab B.V, N.V)| + N.V |(at T.L, ab B.L, N.L)|),
    D = a2 w2^2 / pi,  w2 = a2 / |(ab T.H, at B.H, a2 N.H)|^2,  a2 = at ab,

with T the direction made orthogonal to N and B = N x T, and the visible normals are sampled by
Mitsuba's anisotropic GGX in that frame.

Sampling is this plugin's own, not smlt's: the specular lobe by Mitsuba's GGX visible-normal
sampler, else the cosine-weighted diffuse lobe, chosen as Mitsuba's `roughplastic` weighs its
two lobes: the specular one with probability s / (s + d), where s is the mean over rgb of its
Fresnel weight (1 - metallic) F_d + metallic F_m at cos(N, V) and d that of the diffuse lobe's
(1 - metallic)(1 - F_d) base (so 1 for a metal, 0 without a layer). An even choice wasted a
sample on a rough dielectric (Sibenik's, Sponza's): 18 % of them left the hemisphere and ended
the path, against 4-5 % of smlt's, so that Mitsuba's paths ran shorter than smlt's.

Mitsuba's `si.wi` is smlt's `wo` (toward the camera), Mitsuba's `wo` smlt's `wi`; `eval`
includes the cosine, `sample` returns f cos / pdf. Usage: `import mitsuba_gltf;
mitsuba_gltf.register()` after `mi.set_variant(...)` (a JIT variant such as `llvm_ad_rgb`), then
`{"type": "smlt_gltf", "base_color": [r, g, b], "metallic": m, "alpha": a, "f0": [r, g, b],
"f90": s}`.
"""

import math

import drjit as dr
import mitsuba as mi

NAME = "smlt_gltf"
SMOOTH_ALPHA = 1e-3


def schlick(c):
    x = dr.clip(1.0 - c, 0.0, 1.0)
    return x * x * x * x * x


class SmltGltf(mi.BSDF):
    """glTF's two-sided metallic-roughness BRDF; properties `base_color`, `metallic`, `alpha`,
    `f0` (the dielectric layer's normal reflectance, rgb) and `f90`."""

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        rgb = lambda key: mi.Color3f(*(float(c) for c in props[key]))  # noqa: E731
        self.base = rgb("base_color")
        self.metallic = float(props["metallic"])
        self.alpha = float(props["alpha"])
        self.f0 = rgb("f0")
        self.f90 = float(props["f90"])
        self.smooth = self.alpha < SMOOTH_ALPHA
        self.has_layer = self.metallic > 0.0 or self.f90 > 0.0 or max(float(c) for c in props["f0"]) > 0.0
        lobe = mi.BSDFFlags.DeltaReflection if self.smooth else mi.BSDFFlags.GlossyReflection
        sides = mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide
        self.m_components = [mi.BSDFFlags.DiffuseReflection | sides, lobe | sides]
        self.m_flags = mi.BSDFFlags.DiffuseReflection | lobe | sides
        self.anisotropic = props.has_property("direction")
        if self.anisotropic:
            self.alpha_t, self.alpha_b = float(props["alpha_t"]), float(props["alpha_b"])
            self.direction = mi.Vector3f(*(float(c) for c in props["direction"]))
            self.smooth = False
            self.ggx = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, self.alpha_t, self.alpha_b, True)
        else:
            self.ggx = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, max(self.alpha, SMOOTH_ALPHA), True)

    def _turn(self, si):
        """(cos, sin) of the anisotropy's direction in Mitsuba's local frame at `si` (1, 0 when
        isotropic): local vectors turned by it have x along T and y along B."""
        if not self.anisotropic:
            return mi.Float(1.0), mi.Float(0.0)
        d = si.to_local(self.direction)
        r = dr.sqrt(d.x * d.x + d.y * d.y)
        return d.x / r, d.y / r

    def _local(self, si, wo):
        """The two directions on the side `si.wi` lies on (z flipped when it is the back), in
        the frame of the anisotropy's direction."""
        side = dr.select(si.wi.z >= 0.0, 1.0, -1.0)
        c, s = self._turn(si)
        v = mi.Vector3f(c * si.wi.x + s * si.wi.y, -s * si.wi.x + c * si.wi.y, side * si.wi.z)
        l = mi.Vector3f(c * wo.x + s * wo.y, -s * wo.x + c * wo.y, side * wo.z)
        return v, l

    def _fresnel(self, c):
        w = schlick(c)
        f_d = self.f0 + (mi.Color3f(self.f90) - self.f0) * w
        f_m = self.base + (mi.Color3f(1.0) - self.base) * w
        return f_d, f_m

    def _f(self, v, l):
        """f (without the mirror) for both directions above the surface."""
        h = dr.normalize(v + l)
        f_d, f_m = self._fresnel(dr.abs(dr.dot(v, h)))
        n_v, n_l, n_h = v.z, l.z, h.z
        if self.anisotropic:
            at, ab = self.alpha_t, self.alpha_b
            a2 = at * ab
            vis = 0.5 / (n_l * dr.norm(mi.Vector3f(at * v.x, ab * v.y, n_v))
                         + n_v * dr.norm(mi.Vector3f(at * l.x, ab * l.y, n_l)))
            w2 = a2 / dr.squared_norm(mi.Vector3f(ab * h.x, at * h.y, a2 * n_h))
            d = a2 * w2 * w2 / math.pi
        else:
            a2 = self.alpha * self.alpha
            vis = 0.5 / (n_l * dr.sqrt(n_v * n_v * (1.0 - a2) + a2) + n_v * dr.sqrt(n_l * n_l * (1.0 - a2) + a2))
            d = a2 / (math.pi * dr.square(n_h * n_h * (a2 - 1.0) + 1.0))
        spec = 0.0 if self.smooth else vis * d
        dielectric = (mi.Color3f(1.0) - f_d) * self.base / math.pi + f_d * spec
        return dielectric * (1.0 - self.metallic) + f_m * (spec * self.metallic)

    def _p_specular(self, v):
        """The probability of sampling the specular lobe for `v`: its Fresnel weight against
        the diffuse lobe's, each the mean over rgb."""
        if not self.has_layer:
            return mi.Float(0.0)
        f_d, f_m = self._fresnel(v.z)
        s = dr.mean(f_d * (1.0 - self.metallic) + f_m * self.metallic)
        d = dr.mean((mi.Color3f(1.0) - f_d) * self.base * (1.0 - self.metallic))
        return dr.select(s + d > 0.0, s / (s + d), 0.5)

    def _pdf(self, v, l):
        p_specular = self._p_specular(v)
        cosine = (1.0 - p_specular) * l.z / math.pi
        if self.smooth or not self.has_layer:
            return cosine
        h = dr.normalize(v + l)
        return cosine + p_specular * self.ggx.pdf(v, h) / (4.0 * dr.dot(v, h))

    def eval(self, ctx, si, wo, active=True):
        v, l = self._local(si, wo)
        valid = active & (v.z > 0.0) & (l.z > 0.0)
        return dr.select(valid, self._f(v, l) * l.z, 0.0)

    def pdf(self, ctx, si, wo, active=True):
        v, l = self._local(si, wo)
        valid = active & (v.z > 0.0) & (l.z > 0.0)
        return dr.select(valid, self._pdf(v, l), 0.0)

    def eval_pdf(self, ctx, si, wo, active=True):
        return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

    def sample(self, ctx, si, sample1, sample2, active=True):
        side = dr.select(si.wi.z >= 0.0, 1.0, -1.0)
        c, s = self._turn(si)
        v = mi.Vector3f(c * si.wi.x + s * si.wi.y, -s * si.wi.x + c * si.wi.y, side * si.wi.z)
        p_specular = self._p_specular(v)
        specular = sample1 < p_specular
        if self.smooth:
            m = mi.Normal3f(0.0, 0.0, 1.0)
        else:
            m, _ = self.ggx.sample(v, sample2)
        l_spec = mi.reflect(v, m)
        l_diff = mi.warp.square_to_cosine_hemisphere(sample2)
        l = dr.select(specular, l_spec, l_diff)
        valid = active & (v.z > 0.0) & (l.z > 0.0)
        bs = mi.BSDFSample3f()
        bs.wo = mi.Vector3f(c * l.x - s * l.y, s * l.x + c * l.y, side * l.z)
        bs.eta = 1.0
        if self.smooth:
            f_d, f_m = self._fresnel(v.z)
            mirror = f_d * (1.0 - self.metallic) + f_m * self.metallic
            pdf = dr.select(specular, p_specular, self._pdf(v, l))
            weight = dr.select(specular, mirror / p_specular, self._f(v, l) * l.z / pdf)
            bs.sampled_type = dr.select(specular, mi.UInt32(+mi.BSDFFlags.DeltaReflection),
                                        mi.UInt32(+mi.BSDFFlags.DiffuseReflection))
        else:
            pdf = self._pdf(v, l)
            weight = self._f(v, l) * l.z / pdf
            bs.sampled_type = dr.select(specular, mi.UInt32(+mi.BSDFFlags.GlossyReflection),
                                        mi.UInt32(+mi.BSDFFlags.DiffuseReflection))
        bs.sampled_component = dr.select(specular, mi.UInt32(1), mi.UInt32(0))
        valid = valid & (pdf > 0.0)
        bs.pdf = dr.select(valid, pdf, 0.0)
        return bs, dr.select(valid, weight, 0.0)

    def to_string(self):
        return f"SmltGltf[base={self.base}, metallic={self.metallic}, alpha={self.alpha}, f0={self.f0}, f90={self.f90}]"


def register():
    """Registers the plugin as `smlt_gltf` (call after mi.set_variant)."""
    mi.register_bsdf(NAME, lambda props: SmltGltf(props))
