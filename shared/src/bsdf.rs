//! Materials and their BSDFs — only what our scenes use: Lambertian diffuse, a normalised
//! Phong lobe, and emission (area lights are emissive triangles).
//!
//! Surfaces are two-sided for scattering: the BSDF works on the side that `wo` lies on, and
//! `wo` and `wi` on opposite sides give 0 (no transmission). Emission is one-sided, along the
//! triangle's geometric normal (its winding), see [`crate::light`].
//!
//! **Normalised Phong** (Lafortune and Willems 1994), exponent n, reflectance ρ:
//! `f = ρ (n + 2)/(2π) cosⁿα`, α the angle between `wi` and the mirror direction of `wo`,
//! sampled with density `(n + 1)/(2π) cosⁿα`. For exponents up to 1e5 the lobe is a fraction
//! of a degree wide, where `1 − cos α` is of the order of f32's resolution near 1; both
//! evaluation and sampling therefore work with `δ = 1 − cos α` computed without cancellation
//! (`|r − wi|²/2` and `−expm1`), and `cosⁿα = exp(n · ln(1 − δ))` with a series for ln(1 − δ).

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use core::f32::consts::PI;
use glam::{Vec2, Vec3};

/// A material (uploaded to the device as it is).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Material {
    /// Diffuse albedo (Lambert) or Phong reflectance, from glTF `baseColorFactor`.
    pub albedo: [f32; 3],
    /// Phong exponent; 0 means Lambertian.
    pub phong_exponent: f32,
    /// Emitted radiance (glTF `emissiveFactor` × `KHR_materials_emissive_strength`).
    pub emission: [f32; 3],
    /// Padding to 32 bytes.
    pub _pad: f32,
}

impl Material {
    /// Whether the material emits light.
    #[inline]
    pub fn is_emissive(&self) -> bool {
        self.emission[0] > 0.0 || self.emission[1] > 0.0 || self.emission[2] > 0.0
    }
}

/// A sampled direction with the BSDF value and the solid-angle density; `pdf == 0` means the
/// sample failed (the path ends).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BsdfSample {
    /// The sampled incident direction (unit).
    pub wi: Vec3,
    /// The BSDF value f(wo, wi).
    pub f: Vec3,
    /// Solid-angle density of `wi`.
    pub pdf: f32,
}

/// Two unit vectors completing `n` (unit) to an orthonormal basis (Duff et al. 2017).
#[inline]
pub fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3::new(b, sign + n.y * n.y * a, -n.y))
}

/// A cosine-distributed direction about `n` for `u` ∈ [0,1)², density `cosθ/π`.
#[inline]
pub fn cosine_hemisphere(n: Vec3, u: Vec2) -> Vec3 {
    let r = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    let z = (1.0 - u.x).max(0.0).sqrt();
    let (t, b) = orthonormal_basis(n);
    (t * (r * phi.cos()) + b * (r * phi.sin()) + n * z).normalize()
}

/// ln(1 − δ) for δ ∈ [0, 1], accurate for small δ.
#[inline]
fn ln_one_minus(delta: f32) -> f32 {
    if delta < 1e-3 {
        -delta * (1.0 + delta * (0.5 + delta / 3.0))
    } else {
        (1.0 - delta).ln()
    }
}

/// 1 − e^x for x ≤ 0, accurate for small |x|.
#[inline]
fn one_minus_exp(x: f32) -> f32 {
    if x > -1e-3 {
        -x * (1.0 + x * (0.5 + x / 6.0))
    } else {
        1.0 - x.exp()
    }
}

/// cosⁿα of the Phong lobe about mirror direction `r` for direction `wi` (both unit), 0 when
/// `wi` is more than 90° from `r`.
#[inline]
pub fn phong_lobe(exponent: f32, r: Vec3, wi: Vec3) -> f32 {
    if r.dot(wi) <= 0.0 {
        return 0.0;
    }
    let delta = ((r - wi).length_squared() * 0.5).min(1.0);
    (exponent * ln_one_minus(delta)).exp()
}

/// The side of the surface that `wo` is on: `n` or `−n`.
#[inline]
fn facing(n: Vec3, wo: Vec3) -> Vec3 {
    if n.dot(wo) >= 0.0 {
        n
    } else {
        -n
    }
}

/// The mirror direction of `wo` about `n`.
#[inline]
fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    2.0 * wo.dot(n) * n - wo
}

/// f(wo, wi) at a surface with geometric normal `n` (all unit; `wo` and `wi` point away).
#[inline]
pub fn bsdf_eval(m: &Material, n: Vec3, wo: Vec3, wi: Vec3) -> Vec3 {
    let ns = facing(n, wo);
    if ns.dot(wi) <= 0.0 || ns.dot(wo) <= 0.0 {
        return Vec3::ZERO;
    }
    let albedo = Vec3::from_array(m.albedo);
    if m.phong_exponent > 0.0 {
        let e = m.phong_exponent;
        albedo * ((e + 2.0) / (2.0 * PI) * phong_lobe(e, reflect(wo, ns), wi))
    } else {
        albedo / PI
    }
}

/// Solid-angle density with which [`bsdf_sample`] picks `wi` given `wo`.
#[inline]
pub fn bsdf_pdf(m: &Material, n: Vec3, wo: Vec3, wi: Vec3) -> f32 {
    let ns = facing(n, wo);
    let cos_i = ns.dot(wi);
    if cos_i <= 0.0 || ns.dot(wo) <= 0.0 {
        return 0.0;
    }
    if m.phong_exponent > 0.0 {
        let e = m.phong_exponent;
        (e + 1.0) / (2.0 * PI) * phong_lobe(e, reflect(wo, ns), wi)
    } else {
        cos_i / PI
    }
}

/// Samples `wi` for `wo` with `u` ∈ [0,1)².
#[inline]
pub fn bsdf_sample(m: &Material, n: Vec3, wo: Vec3, u: Vec2) -> BsdfSample {
    let ns = facing(n, wo);
    if ns.dot(wo) <= 0.0 {
        return BsdfSample::default();
    }
    let wi = if m.phong_exponent > 0.0 {
        // cos α = (1 − u)^(1/(n+1)), computed as exp(x) with 1 − cos α = −expm1(x).
        let x = (1.0 - u.x).ln() / (m.phong_exponent + 1.0);
        let cos_a = x.exp();
        let sin_a = (one_minus_exp(x) * (1.0 + cos_a)).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let r = reflect(wo, ns);
        let (t, b) = orthonormal_basis(r);
        (t * (sin_a * phi.cos()) + b * (sin_a * phi.sin()) + r * cos_a).normalize()
    } else {
        cosine_hemisphere(ns, u)
    };
    let pdf = bsdf_pdf(m, n, wo, wi);
    if !(pdf > 0.0) {
        return BsdfSample::default();
    }
    BsdfSample { wi, f: bsdf_eval(m, n, wo, wi), pdf }
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests;
