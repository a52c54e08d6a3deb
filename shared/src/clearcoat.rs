//! glTF's clear coat (`KHR_materials_clearcoat`): a smooth or GGX-rough specular layer of
//! index 1.5 over the whole material, mixed as the extension's `fresnel_coat`:
//!
//! - `f = (1 − w) f_base + w f_coat`, with the layer's weight `w = clearcoat · F_c(|V·n|)`;
//! - `F_c(c) = 0.04 + (1 − 0.04)(1 − c)⁵` (Schlick's, F0 of index 1.5);
//! - `f_coat = D(h) G(wo, wi) / (4 cos θ_o cos θ_i)`, GGX of α = clearcoatRoughness² with the
//!   height-correlated Smith G (`crate::microfacet`), the specular term of the core BRDF without
//!   its Fresnel factor; below [`SMOOTH_ALPHA`](crate::bsdf::SMOOTH_ALPHA) a mirror (a delta)
//!   of weight `w`.
//!
//! **V** is the viewer's direction, as the extension writes it: the spec takes the Fresnel
//! factor at `N·V` rather than at the micro-normal, so that the two layers' weights sum to one
//! (its "Discussion"), which makes the coated material non-reciprocal. Radiance transport (the
//! path tracer, a camera subpath) has the viewer on `wo`'s side; importance transport (a light
//! subpath) takes the adjoint, whose viewer is on `wi`'s side ([`viewer_cosine`]).
//!
//! **Sampling** chooses the layer with [`probability`], its weight at `wo` (at most 0.9, so that
//! the base is sampled at grazing angles too): the layer's mirror then has weight 1, and the
//! base's samples keep the base's own weights.
//!
//! **The coat's normal** (`crate::normals::Normals::coat`) is the interpolated vertex normal,
//! bent by clearcoatNormalTexture only: the base's normal texture leaves the coat smooth, as
//! the extension says. Its layer is evaluated and sampled in its own frame (directions here
//! are local: z is the coat's normal on `wo`'s side), while the callers multiply every lobe by
//! the shading normal's cosine (`crate::normals::scattering_cosine`), so the layer's f carries
//! [`frame_correction`]. The viewer's cosine is the coat normal's.
use glam::{Vec2, Vec3};

use crate::metallic_roughness::{f0_from_ior, schlick_weight};

/// The coat's index of refraction (the extension's, fixed).
pub const COAT_IOR: f32 = 1.5;

/// The largest probability of sampling the layer: the base keeps at least a tenth.
pub const MAX_PROBABILITY: f32 = 0.9;

/// `F_c(c)`: the coat's Schlick Fresnel factor at cosine `c` (either side) from its normal.
#[inline]
pub fn coat_fresnel(c: f32) -> f32 {
    let f0 = f0_from_ior(COAT_IOR);
    f0 + (1.0 - f0) * schlick_weight(c.abs())
}

/// The layer's weight `w = clearcoat · F_c(|V·n|)` for the viewer at cosine `cos_v`.
#[inline]
pub fn layer_weight(clearcoat: f32, cos_v: f32) -> f32 {
    clearcoat * coat_fresnel(cos_v)
}

/// The viewer's cosine: `wo`'s in radiance transport, `wi`'s in importance transport (the
/// module doc), from the unit normal `n`.
#[inline]
pub fn viewer_cosine(n: Vec3, wo: Vec3, wi: Vec3, radiance: bool) -> f32 {
    if radiance {
        n.dot(wo)
    } else {
        n.dot(wi)
    }
}

/// The factor `|nc·l| / |ns·l|` that turns the shading normal `ns`'s cosine, which the
/// callers multiply every lobe by, into the coat normal `nc`'s for the layer; `l` is the
/// direction light comes from (`wi` in radiance transport, `wo` in importance transport, where
/// the callers' cosine is Veach's adjoint `|ns·wo| |ng·wi| / |ng·wo|`, which becomes the
/// adjoint about the coat's normal). 1 where the two normals are one; 0 where `l` lies in the
/// shading normal's plane.
#[inline]
pub fn frame_correction(nc: Vec3, ns: Vec3, l: Vec3) -> f32 {
    let cos_s = ns.dot(l).abs();
    if cos_s > 0.0 {
        nc.dot(l).abs() / cos_s
    } else {
        0.0
    }
}

/// The probability of sampling the layer for `wo` at cosine `cos_o`: its weight there, at most
/// [`MAX_PROBABILITY`].
#[inline]
pub fn probability(clearcoat: f32, cos_o: f32) -> f32 {
    layer_weight(clearcoat, cos_o).min(MAX_PROBABILITY)
}

/// `f_coat(wo, wi)` (local, both above the surface; else 0) of the rough layer, without its
/// weight (`crate::microfacet::reflection`); 0 for a smooth one, whose mirror only [`sample`]
/// produces.
#[inline]
pub fn eval(alpha: f32, wo: Vec3, wi: Vec3) -> f32 {
    if !(wo.z > 0.0 && wi.z > 0.0) || alpha < crate::bsdf::SMOOTH_ALPHA {
        return 0.0;
    }
    crate::microfacet::reflection(Vec2::splat(alpha), wo, wi)
}

/// The solid-angle density with which [`sample`] picks `wi` (local) from a rough layer given
/// `wo`; 0 for a smooth one.
#[inline]
pub fn pdf(alpha: f32, wo: Vec3, wi: Vec3) -> f32 {
    if !(wo.z > 0.0 && wi.z > 0.0) || alpha < crate::bsdf::SMOOTH_ALPHA {
        return 0.0;
    }
    crate::microfacet::reflection_pdf(Vec2::splat(alpha), wo, wi)
}

/// A direction from the layer for `wo` (local, `wo.z` > 0) with `u` ∈ [0,1)²: the mirror of a
/// smooth layer, else a visible normal's reflection (Heitz 2018); None below the surface.
#[inline]
pub fn sample(alpha: f32, wo: Vec3, u: Vec2) -> Option<Vec3> {
    if alpha >= crate::bsdf::SMOOTH_ALPHA {
        return crate::microfacet::sample_reflection(Vec2::splat(alpha), wo, u);
    }
    let wi = Vec3::new(-wo.x, -wo.y, wo.z);
    if wi.z > 0.0 {
        Some(wi)
    } else {
        None
    }
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests;
