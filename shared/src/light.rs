//! The scene's lights, and picking one: emissive triangles (area lights), punctual lights
//! (`crate::punctual`: point, spot, directional) and the environment light
//! (`crate::environment`). A light is picked in proportion to its power
//! (a CDF over every emitter is uploaded; a triangle's power is its area × the luminance of its
//! emission, a punctual light's [`crate::punctual::PunctualLight::selection_power`], the same
//! scale), then a point on it: a uniform point on a triangle, whose area density is therefore
//! `pick(triangle) / area(triangle)`, which each triangle carries
//! ([`crate::triangle::Triangle`]); a punctual light's origin (its position, or a point on a
//! directional light's disk); a direction towards the environment.
//!
//! A triangle's emission is one-sided, along its geometric normal (counter-clockwise winding),
//! and directions leaving it are sampled cosine-weighted about that normal.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use glam::{Vec2, Vec3};

use crate::scene::Scene;
use crate::surface::material_at_barycentrics;

/// The bit of [`LightEntry::light`] that marks a punctual light (the rest is its index among
/// the scene's punctual lights); without it the entry is a triangle's index.
pub const PUNCTUAL: u32 = 1 << 31;

/// The [`LightEntry::light`] of the environment light (no triangle index reaches it).
pub const ENVIRONMENT: u32 = PUNCTUAL - 1;

/// Whether the light id `light` ([`LightEntry::light`]) is a punctual light's.
#[inline]
pub fn is_punctual(light: u32) -> bool {
    light & PUNCTUAL != 0
}

/// Whether the light id `light` ([`LightEntry::light`]) is the environment's.
#[inline]
pub fn is_environment(light: u32) -> bool {
    light == ENVIRONMENT
}

/// The index among the scene's punctual lights of the punctual light id `light`.
#[inline]
pub fn punctual_index(light: u32) -> u32 {
    light & !PUNCTUAL
}

/// A point sampled on the lights.
#[derive(Clone, Copy, Debug, Default)]
pub struct LightPoint {
    /// The point: on an emissive triangle, a point or spot light's position, or a point on a
    /// directional light's disk (for the environment, the centre of the scene's bounding
    /// sphere: its light comes from a direction, not a point).
    pub p: Vec3,
    /// A triangle's geometric normal there; a spot's axis or a directional light's direction;
    /// the direction the environment's light travels (−wi).
    pub n: Vec3,
    /// Which light ([`LightEntry::light`]).
    pub light: u32,
    /// A triangle's material (0 for a punctual light).
    pub material: u32,
    /// The area density the point was sampled with: the pick probability times the density
    /// of the point on the light (`Triangle::light_area_pdf` for a triangle; the pick for a
    /// point or spot light, a delta; pick / (π r²) on a directional light's disk). For the
    /// environment, the pick times the solid-angle density of the direction.
    pub pdf_area: f32,
    /// The probability with which the light was picked.
    pub pick: f32,
    /// A triangle's emitted radiance (`Material::emission`); a punctual light's intensity or
    /// irradiance (`PunctualLight::intensity`); the environment's radiance from the direction.
    pub emission: Vec3,
}

/// Picks a light from `u_pick` and a point on it from `u_point` (see [`LightPoint`]).
#[inline]
pub fn sample_light<R>(scene: &Scene<R>, light_count: u32, u_pick: f32, u_point: Vec2) -> LightPoint {
    let k = pick_light(scene.lights, light_count, u_pick);
    let entry = scene.lights[k as usize];
    let below = if k > 0 { scene.lights[k as usize - 1].cdf } else { 0.0 };
    let pick = entry.cdf - below;
    if is_environment(entry.light) {
        let e = scene.environment.sample(scene.environment_map, u_point);
        return LightPoint {
            p: Vec3::from_array(scene.environment.centre),
            n: -e.wi,
            light: entry.light,
            material: 0,
            pdf_area: pick * e.pdf,
            pick,
            emission: e.radiance,
        };
    }
    if is_punctual(entry.light) {
        let light = scene.punctual[punctual_index(entry.light) as usize];
        let (p, pdf_origin) = light.sample_origin(u_point);
        return LightPoint {
            p,
            n: Vec3::from_array(light.direction),
            light: entry.light,
            material: 0,
            pdf_area: pick * pdf_origin,
            pick,
            emission: Vec3::from_array(light.intensity),
        };
    }
    let tri = scene.triangles[entry.light as usize];
    let b = uniform_triangle(u_point);
    LightPoint {
        p: tri.point(b.x, b.y),
        n: tri.normal(),
        light: entry.light,
        material: tri.material,
        pdf_area: tri.light_area_pdf,
        pick,
        emission: Vec3::from_array(material_at_barycentrics(scene, entry.light, b).emission),
    }
}

/// One entry of the light-selection CDF (uploaded to the device as it is).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LightEntry {
    /// The light: an emissive triangle's index, or [`PUNCTUAL`] | a punctual light's index.
    pub light: u32,
    /// Running sum of the pick probabilities up to and including this entry (the last is 1).
    pub cdf: f32,
}

/// The index into `lights[..count]` of the first entry whose CDF exceeds `u` (binary search).
#[inline]
pub fn pick_light(lights: &[LightEntry], count: u32, u: f32) -> u32 {
    let mut lo = 0u32;
    let mut hi = count - 1;
    while lo < hi {
        let mid = (lo + hi) / 2;
        if lights[mid as usize].cdf > u {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    lo
}

/// Barycentric coordinates (b0, b1) of a uniform point on a triangle for `u` ∈ [0,1)².
#[inline]
pub fn uniform_triangle(u: Vec2) -> Vec2 {
    let su = u.x.sqrt();
    Vec2::new(1.0 - su, u.y * su)
}

/// Emitted radiance leaving a light point with normal `n` in direction `w`: the emission on
/// the front side, 0 behind.
#[inline]
pub fn emitted(emission: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    if n.dot(w) > 0.0 {
        emission
    } else {
        Vec3::ZERO
    }
}

/// The light-selection CDF over the lights of the given `power` (on the scale of the module
/// doc; ≤ 0 for what does not emit), `ids` their [`LightEntry::light`]s, and each light's
/// pick probability divided by `area` (a triangle's light area density; pass 1 for a punctual
/// light to get its pick). None when nothing emits. What [`pick_light`] searches, built on the
/// host.
#[cfg(not(target_arch = "spirv"))]
pub fn light_cdf(power: &[f64], area: &[f32], ids: &[u32]) -> Option<(Vec<LightEntry>, Vec<f32>)> {
    let total: f64 = power.iter().filter(|p| **p > 0.0).sum();
    if !(total > 0.0) {
        return None;
    }
    let mut lights = Vec::new();
    let mut pdf = vec![0.0f32; power.len()];
    let mut running = 0.0f64;
    for (i, &p) in power.iter().enumerate() {
        if p > 0.0 {
            running += p;
            lights.push(LightEntry { light: ids[i], cdf: (running / total) as f32 });
            pdf[i] = (p / total / area[i] as f64) as f32;
        }
    }
    lights.last_mut().expect("an emitter exists").cdf = 1.0;
    Some((lights, pdf))
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    /// The CDF picks emitters in proportion to their power, skips the rest, ends at exactly 1,
    /// and each emitter's area density integrates its pick probability over its area.
    #[test]
    fn light_cdf_is_proportional_to_power() {
        let power = [0.0, 2.0, 0.0, 6.0, -1.0];
        let area = [1.0, 0.5, 1.0, 3.0, 1.0];
        let ids = [0, 1, 2, 3 | PUNCTUAL, 4];
        let (lights, pdf) = light_cdf(&power, &area, &ids).unwrap();
        assert_eq!(
            lights,
            vec![LightEntry { light: 1, cdf: 0.25 }, LightEntry { light: 3 | PUNCTUAL, cdf: 1.0 }]
        );
        assert_eq!(pdf, vec![0.0, 0.5, 0.0, 0.25, 0.0]);
        assert_eq!(pick_light(&lights, 2, 0.2), 0);
        assert_eq!(pick_light(&lights, 2, 0.3), 1);
        assert!(light_cdf(&[0.0, -1.0], &[1.0, 1.0], &[0, 1]).is_none());
        assert!(is_punctual(lights[1].light) && punctual_index(lights[1].light) == 3);
    }

    #[test]
    fn picking_inverts_the_cdf() {
        let lights = [
            LightEntry { light: 4, cdf: 0.25 },
            LightEntry { light: 9, cdf: 0.25 }, // zero-probability entry
            LightEntry { light: 2, cdf: 0.75 },
            LightEntry { light: 7, cdf: 1.0 },
        ];
        assert_eq!(pick_light(&lights, 4, 0.0), 0);
        assert_eq!(pick_light(&lights, 4, 0.2499), 0);
        assert_eq!(pick_light(&lights, 4, 0.25), 2, "the zero-width entry is skipped");
        assert_eq!(pick_light(&lights, 4, 0.9999), 3);
        assert_eq!(pick_light(&lights, 1, 0.7), 0);
    }

    #[test]
    fn uniform_triangle_points_are_uniform() {
        let n = 100_000;
        let mut in_first_half = 0;
        for i in 0..n {
            let u = Vec2::new(
                crate::rng::uniform(crate::rng::RngKey { seed: 1, chain: i, iteration: 0, dimension: 0 }),
                crate::rng::uniform(crate::rng::RngKey { seed: 1, chain: i, iteration: 0, dimension: 1 }),
            );
            let b = uniform_triangle(u);
            assert!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0 + 1e-6);
            // The sub-triangle with b0 > 1/2 has a quarter of the area.
            if b.x > 0.5 {
                in_first_half += 1;
            }
        }
        let share = in_first_half as f64 / n as f64;
        assert!((share - 0.25).abs() < 0.005, "{share}");
    }

    #[test]
    fn emission_is_one_sided() {
        let e = Vec3::new(1.0, 2.0, 3.0);
        assert_eq!(emitted(e, Vec3::Y, Vec3::new(0.1, 0.9, 0.0)), e);
        assert_eq!(emitted(e, Vec3::Y, Vec3::new(0.1, -0.9, 0.0)), Vec3::ZERO);
    }
}
