//! Punctual lights (glTF `KHR_lights_punctual`): point, spot and directional lights. Each is a
//! delta distribution — in position (point, spot) or in direction (directional) — so no ray
//! ever hits one: they are reached only by sampling them (next-event estimation, the
//! multiplexed estimator's connections to a light vertex) or by leaving them (a light
//! subpath), never by a camera path that finds them by itself.
//!
//! - **Point**: radiant intensity I (W/sr) in every direction; the irradiance at distance r is
//!   I cos θ / r² (physical inverse square; glTF's `range` is not modelled).
//! - **Spot**: a point light whose intensity is I · [`spot_falloff`] about its axis: 1 inside
//!   the inner cone, 0 outside the outer one, and the spec's smooth ramp between.
//! - **Directional**: irradiance E (W/m²) on a surface facing it, arriving along one direction
//!   from outside the scene. A light subpath starts on a disk of the scene's bounding-sphere
//!   radius perpendicular to that direction (pbrt-v4's `DistantLight::SampleLe`), with area
//!   density 1 / (π r²).
//!
//! Lights are picked together with the emissive triangles, in proportion to
//! [`PunctualLight::selection_power`]: the emitted flux Φ divided by π, the scale on which a
//! one-sided Lambertian emitter of radiance L and area A has `A · luminance(L)` (what the
//! triangles are picked by, `crate::light`). A directional light's flux is the one through its
//! disk: Φ = E · π r².

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use core::f32::consts::PI;
use glam::{Vec2, Vec3};

use crate::bsdf::orthonormal_basis;
use crate::color::luminance;

/// [`PunctualLight::kind`]: a point light.
pub const POINT: u32 = 0;
/// [`PunctualLight::kind`]: a spot light.
pub const SPOT: u32 = 1;
/// [`PunctualLight::kind`]: a directional light.
pub const DIRECTIONAL: u32 = 2;

/// A punctual light in world space (uploaded to the device as it is).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PunctualLight {
    /// Point and spot: the light's position. Directional: the centre of the scene's bounding
    /// sphere (the centre of the disk its light subpaths start on).
    pub position: [f32; 3],
    /// [`POINT`], [`SPOT`] or [`DIRECTIONAL`].
    pub kind: u32,
    /// Spot: the unit axis it shines along. Directional: the unit direction its light travels.
    pub direction: [f32; 3],
    /// Spot: cosine of the outer cone angle (1 for the others).
    pub cos_outer: f32,
    /// Radiant intensity I in W/sr (point, spot) or irradiance E in W/m² (directional), rgb.
    pub intensity: [f32; 3],
    /// Spot: cosine of the inner cone angle (1 for the others).
    pub cos_inner: f32,
    /// Directional: the radius of the scene's bounding sphere (0 for the others).
    pub radius: f32,
    /// Padding to 64 bytes.
    pub _pad: [f32; 3],
}

/// The entry of a scene without punctual lights (a device buffer cannot be empty; no light
/// entry refers to it).
pub const NONE: PunctualLight = PunctualLight {
    position: [0.0; 3],
    kind: POINT,
    direction: [0.0, 0.0, -1.0],
    cos_outer: 1.0,
    intensity: [0.0; 3],
    cos_inner: 1.0,
    radius: 0.0,
    _pad: [0.0; 3],
};

/// Light arriving at a point from a punctual light: what next-event estimation and a
/// connection to the light need.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Incident {
    /// Unit direction from the point towards the light.
    pub wi: Vec3,
    /// Where the light comes from: the light's position, or (directional) a point along `wi`
    /// outside the scene's bounding sphere; the shadow ray runs up to it.
    pub from: Vec3,
    /// Incident radiance integrated over the delta: I(−wi) / r² (W/m² per unit cosine) for point
    /// and spot, E for directional. The reflected radiance is `f · radiance · |cos θ|`.
    pub radiance: Vec3,
}

/// A direction leaving a punctual light, with its solid-angle density (1 for the directional
/// light's delta direction).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmittedDirection {
    /// Unit direction.
    pub w: Vec3,
    /// Solid-angle density; 1 where the direction is a delta.
    pub pdf: f32,
}

/// The glTF spec's spot falloff for a direction at cosine `cos_theta` from the axis: the square
/// of a linear ramp in cos θ from 0 at the outer cone to 1 at the inner one (the
/// `KHR_lights_punctual` reference implementation, its `max(0.001, …)` guard included).
#[inline]
pub fn spot_falloff(cos_inner: f32, cos_outer: f32, cos_theta: f32) -> f32 {
    let scale = 1.0 / (cos_inner - cos_outer).max(0.001);
    let t = crate::float::clamp((cos_theta - cos_outer) * scale, 0.0, 1.0);
    t * t
}

/// A uniform direction on the unit sphere for `u` ∈ [0,1)², density 1/(4π).
#[inline]
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// A uniform direction in the cone of directions within angle acos(`cos_max`) of the unit
/// `axis`, for `u` ∈ [0,1)², density 1 / (2π (1 − cos_max)).
#[inline]
pub fn uniform_cone(axis: Vec3, cos_max: f32, u: Vec2) -> Vec3 {
    let cos_t = 1.0 - u.x * (1.0 - cos_max);
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    let (t, b) = orthonormal_basis(axis);
    (t * (sin_t * phi.cos()) + b * (sin_t * phi.sin()) + axis * cos_t).normalize()
}

impl PunctualLight {
    /// A point light at `position` of radiant intensity `intensity` (W/sr).
    pub fn point(position: Vec3, intensity: Vec3) -> Self {
        Self {
            position: position.to_array(),
            kind: POINT,
            direction: [0.0, 0.0, -1.0],
            cos_outer: 1.0,
            intensity: intensity.to_array(),
            cos_inner: 1.0,
            ..Default::default()
        }
    }

    /// A spot light at `position` shining along the unit `axis`, of on-axis intensity
    /// `intensity` (W/sr), with inner and outer cone half-angles in radians.
    pub fn spot(position: Vec3, axis: Vec3, intensity: Vec3, inner: f32, outer: f32) -> Self {
        Self {
            position: position.to_array(),
            kind: SPOT,
            direction: axis.to_array(),
            cos_outer: outer.cos(),
            intensity: intensity.to_array(),
            cos_inner: inner.cos(),
            ..Default::default()
        }
    }

    /// A directional light whose light travels along the unit `direction` with irradiance
    /// `irradiance` (W/m²), over a scene bounded by the sphere (`centre`, `radius`).
    pub fn directional(direction: Vec3, irradiance: Vec3, centre: Vec3, radius: f32) -> Self {
        Self {
            position: centre.to_array(),
            kind: DIRECTIONAL,
            direction: direction.to_array(),
            cos_outer: 1.0,
            intensity: irradiance.to_array(),
            cos_inner: 1.0,
            radius,
            _pad: [0.0; 3],
        }
    }

    #[inline]
    fn axis(&self) -> Vec3 {
        Vec3::from_array(self.direction)
    }

    /// Whether the light is directional (a delta in direction, not in position).
    #[inline]
    pub fn is_directional(&self) -> bool {
        self.kind == DIRECTIONAL
    }

    /// Point and spot: the radiant intensity (W/sr) leaving along the unit direction `w`.
    /// Directional: the irradiance E (its only direction is its own).
    #[inline]
    pub fn emitted(&self, w: Vec3) -> Vec3 {
        let i = Vec3::from_array(self.intensity);
        if self.kind == SPOT {
            i * spot_falloff(self.cos_inner, self.cos_outer, self.axis().dot(w))
        } else {
            i
        }
    }

    /// The light arriving at `p` (see [`Incident`]).
    #[inline]
    pub fn incident(&self, p: Vec3) -> Incident {
        let centre = Vec3::from_array(self.position);
        if self.kind == DIRECTIONAL {
            let wi = -self.axis();
            let from = crate::distant::beyond(centre, self.radius, p, wi);
            Incident { wi, from, radiance: Vec3::from_array(self.intensity) }
        } else {
            let to = centre - p;
            let d2 = to.length_squared();
            if !(d2 > 0.0) {
                return Incident { wi: Vec3::Z, from: centre, radiance: Vec3::ZERO };
            }
            let wi = to / d2.sqrt();
            Incident { wi, from: centre, radiance: self.emitted(-wi) / d2 }
        }
    }

    /// The origin of a light subpath for `u` ∈ [0,1)², with its area density: the light's
    /// position with density 1 (a delta), or (directional) a uniform point on the disk of
    /// radius r through the bounding sphere's far side from the light, density 1 / (π r²).
    #[inline]
    pub fn sample_origin(&self, u: Vec2) -> (Vec3, f32) {
        let centre = Vec3::from_array(self.position);
        if self.kind == DIRECTIONAL {
            (crate::distant::disk_origin(centre, self.radius, self.axis(), u), self.pdf_origin())
        } else {
            (centre, 1.0)
        }
    }

    /// The area density of [`Self::sample_origin`] (1 for a delta position).
    #[inline]
    pub fn pdf_origin(&self) -> f32 {
        if self.kind == DIRECTIONAL {
            crate::distant::disk_pdf(self.radius)
        } else {
            1.0
        }
    }

    /// A direction leaving the light for `u` ∈ [0,1)²: uniform on the sphere (point), uniform
    /// in the outer cone (spot), the light's own (directional, density 1).
    #[inline]
    pub fn sample_direction(&self, u: Vec2) -> EmittedDirection {
        if self.kind == DIRECTIONAL {
            EmittedDirection { w: self.axis(), pdf: 1.0 }
        } else if self.kind == SPOT {
            EmittedDirection {
                w: uniform_cone(self.axis(), self.cos_outer, u),
                pdf: self.pdf_direction(self.axis()),
            }
        } else {
            EmittedDirection { w: uniform_sphere(u), pdf: 1.0 / (4.0 * PI) }
        }
    }

    /// The solid-angle density with which [`Self::sample_direction`] picks `w` (0 for the
    /// directional light, whose direction is a delta: no other technique shares it).
    #[inline]
    pub fn pdf_direction(&self, w: Vec3) -> f32 {
        if self.kind == DIRECTIONAL {
            0.0
        } else if self.kind == SPOT {
            if self.axis().dot(w) >= self.cos_outer {
                1.0 / (2.0 * PI * (1.0 - self.cos_outer).max(1e-7))
            } else {
                0.0
            }
        } else {
            1.0 / (4.0 * PI)
        }
    }

    /// The emitted flux over π (see the module doc), by luminance: what the light is picked
    /// by. Point: Φ = 4π I, so 4 I. Spot: the flux of [`spot_falloff`] exactly, Φ = 2π I
    /// (1 − cos θ_outer − 2w/3) with w = max(cos θ_inner − cos θ_outer, 0.001) the ramp's width
    /// in cos θ (the ramp t² over a width w carries w/3), so 2 I (1 − cos θ_outer − 2w/3).
    /// Directional: the flux through its disk, Φ = E π r², so E r².
    #[inline]
    pub fn selection_power(&self) -> f32 {
        let i = luminance(Vec3::from_array(self.intensity)).max(0.0);
        if self.kind == DIRECTIONAL {
            i * self.radius * self.radius
        } else if self.kind == SPOT {
            let w = (self.cos_inner - self.cos_outer).max(0.001);
            2.0 * i * (1.0 - self.cos_outer - 2.0 * w / 3.0).max(0.0)
        } else {
            4.0 * i
        }
    }
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests;
