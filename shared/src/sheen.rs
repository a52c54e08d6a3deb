//! glTF's sheen (`KHR_materials_sheen`): a layer of micro-fibres over the glTF BRDF (and the
//! dielectric beneath it), below the clear coat, combined with the extension's albedo scaling:
//!
//! - `f = c · f_sheen(wo, wi) + f_base(wo, wi) · s(wo, wi)`, c the sheen colour;
//! - `f_sheen = D(h) · V(wo, wi)`, h = normalize(wo + wi), with the "Charlie" distribution of
//!   Conty and Kulla (2017), `D(h) = (2 + 1/α) sin(θ_h)^(1/α) / (2π)`, α = r², r the sheen
//!   roughness, and their visibility `V = 1 / ((1 + Λ(cos θ_o) + Λ(cos θ_i)) 4 cos θ_o cos θ_i)`,
//!   Λ their fitted shadowing ([`lambda`]);
//! - `s = min(1 − max(c) E(cos θ_o), 1 − max(c) E(cos θ_i))`, E the directional albedo of
//!   `f_sheen` ([`albedo`]), from a table of its quadrature (`sheen/albedo.rs`, generated and
//!   checked by this module's tests), interpolated bilinearly in (√cos θ, r).
//!
//! These are the extension's implementation notes, which it leaves to the renderer; smlt's
//! choices where they are silent:
//! - **r is kept in [0.07, 1]**, as Khronos' sample viewer keeps it: the fit of Λ is for α
//!   in [0, 1], and below 0.07 the lobe is narrower than the table resolves.
//! - **E exceeds 1 near grazing** for small r (up to 2.9 at r = 0.07 and cos θ = 0.002; below 1
//!   at every angle for r ≥ 0.3): Λ is a fit, and this lobe is not energy-conserving there, so
//!   `s` is kept at 0 or more; a white sheen of roughness below 0.3 seen at grazing angles
//!   reflects more than it receives, as it does in every renderer of this model.
//! - **No Fresnel factor** (F = 1, which the notes allow).
//! - **Sampling**: the layer with [`probability`], its share of the energy at `wo` (c · E, at
//!   most [`MAX_PROBABILITY`]), uniformly over the hemisphere ([`sample`]); Conty and Kulla
//!   sample it so too: the lobe peaks at grazing half vectors, where a cosine or a visible
//!   normal would rarely go.
//!
//! Directions are local, z the shading normal on `wo`'s side; the layer is a reflection only.
//! On a transmission (the dielectric beneath) `s` takes the cosines' magnitudes.
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use core::f32::consts::PI;
use glam::{Vec2, Vec3};

use crate::float::clamp;
use spirv_std::arch::IndexUnchecked;

mod albedo;

/// The smallest sheen roughness r modelled (smaller ones are taken as it; the module doc).
pub const MIN_ROUGHNESS: f32 = 0.07;

/// The largest probability of sampling the layer: the base keeps at least a tenth.
pub const MAX_PROBABILITY: f32 = 0.9;

/// The distribution's α for the sheen roughness `roughness`: r², r kept in [0.07, 1].
#[inline]
pub fn alpha(roughness: f32) -> f32 {
    let r = clamp(roughness, MIN_ROUGHNESS, 1.0);
    r * r
}

/// The Charlie distribution `D` of micro-fibre normals at cosine `cos_h` from the normal,
/// roughness `alpha` (normalised: ∫ D cos θ_h dω_h = 1 over the hemisphere).
#[inline]
pub fn charlie_d(alpha: f32, cos_h: f32) -> f32 {
    let sin2 = (1.0 - cos_h * cos_h).max(0.0);
    (2.0 + 1.0 / alpha) * sin2.powf(0.5 / alpha) / (2.0 * PI)
}

/// Conty and Kulla's fitted exponent `L(x)` of the shadowing, its five coefficients mixed
/// between their fits at α = 0 and α = 1 by (1 − α)².
#[inline]
fn fitted_l(x: f32, alpha: f32) -> f32 {
    let t = (1.0 - alpha) * (1.0 - alpha);
    let mix = |at_one: f32, at_zero: f32| at_one + (at_zero - at_one) * t;
    let a = mix(21.5473, 25.3245);
    let b = mix(3.82987, 3.32435);
    let c = mix(0.19823, 0.16801);
    let d = mix(-1.97760, -1.27393);
    let e = mix(-4.32054, -4.85967);
    a / (1.0 + b * x.powf(c)) + d * x + e
}

/// The shadowing `Λ` of a direction at cosine `cos` from the normal: `exp(L(cos))` below 0.5,
/// `exp(2 L(0.5) − L(1 − cos))` above (its fit is made at grazing angles and mirrored).
#[inline]
pub fn lambda(alpha: f32, cos: f32) -> f32 {
    let c = cos.abs();
    if c < 0.5 {
        fitted_l(c, alpha).exp()
    } else {
        (2.0 * fitted_l(0.5, alpha) - fitted_l(1.0 - c, alpha)).exp()
    }
}

/// `f_sheen(wo, wi) = D(h) V(wo, wi)` (local, both above the surface; else 0) of a white sheen
/// of roughness `alpha` ([`alpha`]).
#[inline]
pub fn eval(alpha: f32, wo: Vec3, wi: Vec3) -> f32 {
    if !(wo.z > 0.0 && wi.z > 0.0) {
        return 0.0;
    }
    let h = (wo + wi).normalize();
    let visibility = 1.0 / ((1.0 + lambda(alpha, wo.z) + lambda(alpha, wi.z)) * (4.0 * wo.z * wi.z));
    charlie_d(alpha, h.z) * visibility
}

/// E: the directional albedo `∫ f_sheen(wo, wi) cos θ_i dω_i` of a white sheen of roughness
/// `roughness` (r, not α) seen at cosine `cos` (magnitude taken), from the table.
// One call on the device (its table is a constant, read through a local copy: rust-gpu has no
// globals), no panic path.
#[cfg_attr(target_arch = "spirv", inline(never))]
#[cfg_attr(not(target_arch = "spirv"), inline)]
pub fn albedo(roughness: f32, cos: f32) -> f32 {
    let n = albedo::SIZE as f32 - 1.0;
    let x = clamp(cos.abs().sqrt(), 0.0, 1.0) * n;
    let y = (clamp(roughness, MIN_ROUGHNESS, 1.0) - MIN_ROUGHNESS) / (1.0 - MIN_ROUGHNESS) * n;
    let (i, j) = ((x as usize).min(albedo::SIZE - 2), (y as usize).min(albedo::SIZE - 2));
    let (fx, fy) = (x - i as f32, y - j as f32);
    let table = albedo::TABLE;
    // SAFETY: i, j ≤ SIZE − 1, so the index is below SIZE².
    let at = |i: usize, j: usize| unsafe { *table.index_unchecked(j * albedo::SIZE + i) };
    let low = at(i, j) + (at(i + 1, j) - at(i, j)) * fx;
    let high = at(i, j + 1) + (at(i + 1, j + 1) - at(i, j + 1)) * fx;
    low + (high - low) * fy
}

/// The base's albedo scaling `s = min(1 − m E(cos_o), 1 − m E(cos_i))`, m the sheen colour's
/// largest channel, kept at 0 or more (the module doc).
#[inline]
pub fn albedo_scaling(color_max: f32, roughness: f32, cos_o: f32, cos_i: f32) -> f32 {
    let e = albedo(roughness, cos_o).max(albedo(roughness, cos_i));
    (1.0 - color_max * e).max(0.0)
}

/// The probability of sampling the layer for `wo` at cosine `cos_o`: its share `m E(cos_o)`
/// of the energy, at most [`MAX_PROBABILITY`].
#[inline]
pub fn probability(color_max: f32, roughness: f32, cos_o: f32) -> f32 {
    clamp(color_max * albedo(roughness, cos_o), 0.0, MAX_PROBABILITY)
}

/// The density of [`sample`]: uniform over the hemisphere.
pub const PDF: f32 = 0.5 / PI;

/// A direction uniform over the upper hemisphere (local) for `u` ∈ [0,1)², density [`PDF`].
#[inline]
pub fn sample(u: Vec2) -> Vec3 {
    let z = 1.0 - u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests;
