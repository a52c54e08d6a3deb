//! Area lights: emissive triangles. A light point is chosen by picking an emissive triangle in
//! proportion to its power (area × luminance of its emission; a CDF over the emissive
//! triangles is uploaded) and a uniform point on it; its area density is therefore
//! `pick(triangle) / area(triangle)`, which each triangle carries ([`crate::triangle::Triangle`]).
//! Emission is one-sided, along the triangle's geometric normal (counter-clockwise winding),
//! and directions leaving a light are sampled cosine-weighted about that normal.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use glam::{Vec2, Vec3};

use crate::bsdf::Material;
use crate::triangle::Triangle;

/// A point sampled on the lights.
#[derive(Clone, Copy, Debug, Default)]
pub struct LightPoint {
    /// The point.
    pub p: Vec3,
    /// The light's normal there (its triangle's geometric normal).
    pub n: Vec3,
    /// Its triangle.
    pub triangle: u32,
    /// The triangle's material.
    pub material: u32,
    /// The area density the point was sampled with (`Triangle::light_area_pdf`).
    pub pdf_area: f32,
    /// Emitted radiance of the light's material (`Material::emission`).
    pub emission: Vec3,
}

/// Picks a light point from `u_pick` and `u_point` (area density `triangle.light_area_pdf`).
#[inline]
pub fn sample_light(
    lights: &[LightEntry],
    light_count: u32,
    tris: &[Triangle],
    materials: &[Material],
    u_pick: f32,
    u_point: Vec2,
) -> LightPoint {
    let entry = lights[pick_light(lights, light_count, u_pick) as usize];
    let tri = tris[entry.triangle as usize];
    let b = uniform_triangle(u_point);
    LightPoint {
        p: tri.point(b.x, b.y),
        n: tri.normal(),
        triangle: entry.triangle,
        material: tri.material,
        pdf_area: tri.light_area_pdf,
        emission: Vec3::from_array(materials[tri.material as usize].emission),
    }
}

/// One entry of the light-selection CDF (uploaded to the device as it is).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LightEntry {
    /// The emissive triangle.
    pub triangle: u32,
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

/// The light-selection CDF of triangles of the given emitted `power` (area × luminance of
/// emission; ≤ 0 for non-emitters), and each triangle's light area density
/// `pick(triangle) / area(triangle)` (0 for non-emitters). None when nothing emits. What
/// [`pick_light`] searches, built on the host.
#[cfg(not(target_arch = "spirv"))]
pub fn light_cdf(power: &[f64], area: &[f32]) -> Option<(Vec<LightEntry>, Vec<f32>)> {
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
            lights.push(LightEntry { triangle: i as u32, cdf: (running / total) as f32 });
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
        let (lights, pdf) = light_cdf(&power, &area).unwrap();
        assert_eq!(lights, vec![LightEntry { triangle: 1, cdf: 0.25 }, LightEntry { triangle: 3, cdf: 1.0 }]);
        assert_eq!(pdf, vec![0.0, 0.5, 0.0, 0.25, 0.0]);
        assert_eq!(pick_light(&lights, 2, 0.2), 0);
        assert_eq!(pick_light(&lights, 2, 0.3), 1);
        assert!(light_cdf(&[0.0, -1.0], &[1.0, 1.0]).is_none());
    }

    #[test]
    fn picking_inverts_the_cdf() {
        let lights = [
            LightEntry { triangle: 4, cdf: 0.25 },
            LightEntry { triangle: 9, cdf: 0.25 }, // zero-probability entry
            LightEntry { triangle: 2, cdf: 0.75 },
            LightEntry { triangle: 7, cdf: 1.0 },
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
