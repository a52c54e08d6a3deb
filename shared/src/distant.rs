//! Light from outside the scene: a directional light's and the environment's rays arrive
//! parallel along a direction, from beyond the scene's bounding sphere (centre c, radius r). A
//! light subpath along such a direction starts on the disk of radius r perpendicular to it,
//! through the sphere's far side from the light (pbrt-v4's `DistantLight::SampleLe`), with area
//! density 1 / (π r²); a shadow ray towards the light ends outside the sphere.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use core::f32::consts::PI;
use glam::{Vec2, Vec3};

use crate::bsdf::orthonormal_basis;

/// A uniform point on the unit disk for `u` ∈ [0,1)², density 1/π.
#[inline]
pub fn uniform_disk(u: Vec2) -> Vec2 {
    let r = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    Vec2::new(r * phi.cos(), r * phi.sin())
}

/// The origin of a light subpath whose light travels along the unit `travel`, for `u` ∈
/// [0,1)²: a uniform point on the disk of the bounding sphere (`centre`, `radius`)
/// perpendicular to `travel`, one radius from the centre towards the light; density
/// [`disk_pdf`].
#[inline]
pub fn disk_origin(centre: Vec3, radius: f32, travel: Vec3, u: Vec2) -> Vec3 {
    let (t, b) = orthonormal_basis(travel);
    let q = uniform_disk(u) * radius;
    centre - travel * radius + t * q.x + b * q.y
}

/// The area density of [`disk_origin`] on a disk of radius `radius`, 1 / (π r²).
#[inline]
pub fn disk_pdf(radius: f32) -> f32 {
    1.0 / (PI * radius * radius)
}

/// Where a shadow ray from `p` (inside the bounding sphere) towards a distant light along the
/// unit `wi` ends: any segment of length 2r + |p − c| leaves the sphere.
#[inline]
pub fn beyond(centre: Vec3, radius: f32, p: Vec3, wi: Vec3) -> Vec3 {
    p + wi * (2.0 * radius + (p - centre).length())
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;
    use crate::rng::{uniform, RngKey};

    /// Origins lie on the disk one radius up-light, uniformly (a quarter of them within half
    /// the radius), and a shadow ray's end is outside the sphere.
    #[test]
    fn origins_lie_on_the_disk_facing_the_light() {
        let (c, r) = (Vec3::new(1.0, 2.0, 3.0), 2.5);
        let travel = Vec3::new(0.3, -1.0, 0.2).normalize();
        let mut inner = 0;
        let n = 20_000;
        for i in 0..n {
            let u = |d| uniform(RngKey { seed: 17, chain: i, iteration: 0, dimension: d });
            let o = disk_origin(c, r, travel, Vec2::new(u(0), u(1)));
            assert!(((o - c).dot(travel) + r).abs() < 1e-4, "on the plane one radius up-light");
            let off = (o - c + travel * r).length();
            assert!(off <= r * (1.0 + 1e-5), "within the disk");
            inner += usize::from(off < 0.5 * r);
            let p = c + crate::punctual::uniform_sphere(Vec2::new(u(2), u(3))) * r;
            assert!((beyond(c, r, p, -travel) - c).length() > r);
        }
        assert!((inner as f64 / n as f64 - 0.25).abs() < 0.01, "{inner}");
        assert!((disk_pdf(r) * PI * r * r - 1.0).abs() < 1e-6);
    }
}
