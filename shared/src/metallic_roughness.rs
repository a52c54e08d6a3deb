//! glTF 2.0's metallic-roughness BRDF (the spec's Appendix B) with `KHR_materials_specular`,
//! in a local frame whose z axis is the surface normal on `wo`'s side (`wo.z` > 0):
//!
//! - `f = (1 − metallic) · dielectric + metallic · metal`;
//! - `dielectric = (1 − F_d) · base/π + F_d · S`, `F_d = f0 + (f90 − f0)(1 − wo·h)⁵` with
//!   `f0 = min(F0(ior) · specularColor, 1) · specular`, `f90 = specular` and
//!   `F0(ior) = ((ior − 1)/(ior + 1))²` (0.04 for glTF's default 1.5);
//! - `metal = F_m · S`, `F_m = base + (1 − base)(1 − wo·h)⁵`;
//! - `S = D(h) G(wo, wi) / (4 cos θ_o cos θ_i)`, GGX of α = roughness² with the
//!   height-correlated Smith G (`crate::microfacet`), h = normalize(wo + wi); anisotropic
//!   (`KHR_materials_anisotropy`) where the two roughnesses differ, the frame's x axis then the
//!   direction of the wider one.
//!
//! With `specular` = 0 and `metallic` = 0 the dielectric layer vanishes and `f = base/π`
//! exactly (Lambert), which is how scenes meant to be Lambertian say so. Where both α are below
//! [`SMOOTH_ALPHA`](crate::bsdf::SMOOTH_ALPHA) the specular lobe is a mirror (a delta), of
//! weight `(1 − metallic) F_d + metallic F_m` at h = n.
//!
//! Sampling chooses the specular lobe with [`specular_probability`] — its estimated weight at
//! `wo` against the diffuse lobe's, kept within [0.1, 0.9] where both scatter — then a visible
//! normal (Heitz 2018) or a cosine-weighted direction; [`pdf`] is the mixture's density, the
//! one that MIS and the multiplexed weights see. The BRDF is reciprocal (`wo·h = wi·h`).
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use core::f32::consts::PI;
use glam::{Vec2, Vec3};

use crate::color::luminance;
use crate::float::clamp;

/// The parameters of the BRDF at a surface point, from a material's factors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetallicRoughness {
    /// glTF's base colour: the diffuse albedo and the metal's normal-incidence reflectance.
    pub base: Vec3,
    /// glTF's metallicFactor, in [0, 1].
    pub metallic: f32,
    /// The GGX roughnesses (αx, αy) along the frame's x and y axes (roughnessFactor² on both,
    /// but where `KHR_materials_anisotropy` widens x: `crate::bsdf::Material::alphas`).
    pub alpha: Vec2,
    /// The dielectric layer's reflectance at normal incidence.
    pub f0: Vec3,
    /// The dielectric layer's reflectance at grazing incidence.
    pub f90: f32,
}

/// The reflectance at normal incidence of a dielectric of index `ior` in air.
#[inline]
pub fn f0_from_ior(ior: f32) -> f32 {
    let r = (ior - 1.0) / (ior + 1.0);
    r * r
}

/// Schlick's weight `(1 − c)⁵` for a cosine `c` in [0, 1].
#[inline]
pub fn schlick_weight(c: f32) -> f32 {
    let x = clamp(1.0 - c, 0.0, 1.0);
    let x2 = x * x;
    x2 * x2 * x
}

impl MetallicRoughness {
    /// The BRDF of glTF's factors: base colour, metallic, (αx, αy), ior, and
    /// `KHR_materials_specular`'s specularFactor and specularColorFactor.
    #[inline]
    pub fn new(
        base: Vec3,
        metallic: f32,
        alpha: Vec2,
        ior: f32,
        specular: f32,
        specular_color: Vec3,
    ) -> Self {
        let f0 = (specular_color * f0_from_ior(ior)).min(Vec3::ONE) * specular;
        MetallicRoughness { base, metallic, alpha, f0, f90: specular }
    }

    /// Whether the BRDF is exactly Lambertian (no metal, no dielectric layer).
    #[inline]
    pub fn is_lambertian(&self) -> bool {
        self.metallic == 0.0 && self.f90 == 0.0 && self.f0 == Vec3::ZERO
    }

    /// Whether the specular lobe is a mirror (a delta: both α below the smooth limit).
    #[inline]
    pub fn is_smooth(&self) -> bool {
        self.alpha.max_element() < crate::bsdf::SMOOTH_ALPHA
    }

    /// Whether the specular lobe is a mirror with weight.
    #[inline]
    pub fn has_mirror(&self) -> bool {
        self.is_smooth() && !self.is_lambertian()
    }

    /// The dielectric layer's Fresnel factor `F_d` at cosine `c` between wo and h.
    #[inline]
    pub fn dielectric_fresnel(&self, c: f32) -> Vec3 {
        self.f0 + (Vec3::splat(self.f90) - self.f0) * schlick_weight(c)
    }

    /// The metal's Fresnel factor `F_m` at cosine `c` between wo and h.
    #[inline]
    pub fn metal_fresnel(&self, c: f32) -> Vec3 {
        self.base + (Vec3::ONE - self.base) * schlick_weight(c)
    }

    /// The specular lobe's Fresnel weight `(1 − metallic) F_d + metallic F_m` at cosine `c`.
    #[inline]
    pub fn specular_fresnel(&self, c: f32) -> Vec3 {
        self.dielectric_fresnel(c) * (1.0 - self.metallic) + self.metal_fresnel(c) * self.metallic
    }

    /// The diffuse lobe's weight `(1 − metallic)(1 − F_d) base` at cosine `c`.
    #[inline]
    pub fn diffuse_weight(&self, c: f32) -> Vec3 {
        (Vec3::ONE - self.dielectric_fresnel(c)) * self.base * (1.0 - self.metallic)
    }
}

/// The probability of sampling the specular lobe for wo at cosine `cos_o` from the normal: its
/// Fresnel weight against the diffuse lobe's (by luminance), within [0.1, 0.9] where both
/// scatter; 0 without a specular lobe, 1 without a diffuse one.
#[inline]
pub fn specular_probability(b: &MetallicRoughness, cos_o: f32) -> f32 {
    let s = luminance(b.specular_fresnel(cos_o));
    let d = luminance(b.diffuse_weight(cos_o));
    if !(s > 0.0) {
        0.0
    } else if !(d > 0.0) {
        1.0
    } else {
        clamp(s / (s + d), 0.1, 0.9)
    }
}

/// f(wo, wi) (local, both on the normal's side; else 0), without the mirror of a smooth
/// specular lobe, which only [`sample`] produces.
// Calls on the device, not copies at every call site.
#[cfg_attr(target_arch = "spirv", inline(never))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn eval(b: &MetallicRoughness, wo: Vec3, wi: Vec3) -> Vec3 {
    if !(wo.z > 0.0 && wi.z > 0.0) {
        return Vec3::ZERO;
    }
    if b.is_lambertian() {
        return b.base / PI;
    }
    let h = wo + wi;
    let c = if h.length_squared() > 0.0 { clamp(wo.dot(h.normalize()), 0.0, 1.0) } else { 0.0 };
    let diffuse = b.diffuse_weight(c) / PI;
    if b.is_smooth() {
        return diffuse;
    }
    diffuse + b.specular_fresnel(c) * crate::microfacet::reflection(b.alpha, wo, wi)
}

/// The solid-angle density with which [`sample`] picks `wi` given `wo` (local), without the
/// mirror's discrete probability.
#[cfg_attr(target_arch = "spirv", inline(never))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn pdf(b: &MetallicRoughness, wo: Vec3, wi: Vec3) -> f32 {
    if !(wo.z > 0.0 && wi.z > 0.0) {
        return 0.0;
    }
    let p = specular_probability(b, wo.z);
    let diffuse = (1.0 - p) * wi.z / PI;
    if p == 0.0 || b.is_smooth() {
        return diffuse;
    }
    diffuse + p * crate::microfacet::reflection_pdf(b.alpha, wo, wi)
}

/// A direction sampled by [`sample`] (local).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalSample {
    /// The sampled direction.
    pub wi: Vec3,
    /// For the mirror, the share of light it reflects (its Fresnel weight; with `pdf`, its
    /// discrete probability, the sample's weight is `f / pdf`); otherwise [`eval`] and [`pdf`]
    /// give the value and density.
    pub f: Vec3,
    /// See `f`.
    pub pdf: f32,
    /// Whether `wi` is the mirror's (a delta).
    pub delta: bool,
    /// Whether there is a sample (false: a reflection below the surface).
    pub found: bool,
}

/// Samples `wi` for `wo` (local, `wo.z` > 0) with `u` ∈ [0,1)²: the specular lobe with
/// [`specular_probability`], else the cosine-weighted diffuse lobe.
#[inline]
pub fn sample(b: &MetallicRoughness, wo: Vec3, u: Vec2) -> LocalSample {
    let p = specular_probability(b, wo.z);
    let none = LocalSample { wi: Vec3::Z, f: Vec3::ZERO, pdf: 0.0, delta: false, found: false };
    if u.x < p {
        let v = Vec2::new((u.x / p).min(1.0 - f32::EPSILON), u.y);
        if b.is_smooth() {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            return LocalSample { wi, f: b.specular_fresnel(wo.z), pdf: p, delta: true, found: true };
        }
        let Some(wi) = crate::microfacet::sample_reflection(b.alpha, wo, v) else {
            return none;
        };
        return LocalSample { wi, f: Vec3::ZERO, pdf: 0.0, delta: false, found: true };
    }
    let v = Vec2::new(((u.x - p) / (1.0 - p)).min(1.0 - f32::EPSILON), u.y);
    let r = v.x.sqrt();
    let phi = 2.0 * PI * v.y;
    let wi = Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - v.x).max(0.0).sqrt());
    if !(wi.z > 0.0) {
        return none;
    }
    LocalSample { wi: wi.normalize(), f: Vec3::ZERO, pdf: 0.0, delta: false, found: true }
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests;
