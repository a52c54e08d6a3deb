//! The unit tests' sample points: keyed uniforms and directions, one definition for every
//! module's tests.

use core::f32::consts::PI;
use glam::{Vec2, Vec3};

use crate::rng::{uniform, RngKey};

/// Two uniforms, sample `i` of the stream `seed`.
pub fn u2(i: u32, seed: u32) -> Vec2 {
    let k = |d| uniform(RngKey { seed, chain: i, iteration: 0, dimension: d });
    Vec2::new(k(0), k(1))
}

/// A direction at polar angle whose cosine is `c` and azimuth `phi`, about +z.
pub fn dir(c: f32, phi: f32) -> Vec3 {
    let s = (1.0 - c * c).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), c)
}

/// A direction uniform on the sphere, sample `i` of the stream `seed`.
pub fn sphere(i: u32, seed: u32) -> Vec3 {
    let u = u2(i, seed);
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(r * (2.0 * PI * u.y).cos(), r * (2.0 * PI * u.y).sin(), z)
}
