//! The one seam between the path code and ray casting: closest-hit and occlusion queries
//! through a [`RayCaster`], chosen by static dispatch. The kernels cast through the wide BVH
//! traversed in [`crate::cwbvh`]; the CPU backend through the fastest host traversal (the
//! host's `caster` module). Every caster answers the same way: hits with t strictly inside
//! (tmin, tmax), both faces, degenerate triangles never, NaN never — the triangle test is
//! [`crate::triangle::intersect_triangle`] for all of them — and a cut-out triangle only where
//! [`crate::cutout::Cutouts::stops`] says it stops the ray, its stochastic opacity drawn from
//! the query's `key` ([`crate::cutout::blend_key`] of the uniforms that chose the ray).

use glam::Vec3;

pub use crate::triangle::NO_HIT;

/// The closest hit of a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the (unit) direction, or [`NO_HIT`].
    pub t: f32,
    /// Triangle slot (an index into the scene's triangles).
    pub triangle: u32,
}

impl Hit {
    /// A miss: `t` is [`NO_HIT`], so [`Hit::found`] is false.
    pub const NONE: Hit = Hit { t: NO_HIT, triangle: 0 };

    /// Whether the ray hit anything.
    #[inline]
    pub fn found(&self) -> bool {
        self.t < NO_HIT
    }
}

/// Answers ray queries against the scene's triangles (the directions are unit vectors). A
/// caster is a small handle (slices, a reference), copied into every stage as the scene is.
pub trait RayCaster: Copy {
    /// The closest triangle the ray hits in (tmin, tmax); `key` draws its BLEND cut-outs.
    fn closest_hit(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> Hit;
    /// Whether anything blocks the ray in (tmin, tmax); `key` draws its BLEND cut-outs.
    fn occluded(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> bool;
}

impl<T: RayCaster> RayCaster for &T {
    #[inline]
    fn closest_hit(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> Hit {
        (**self).closest_hit(o, d, tmin, tmax, key)
    }

    #[inline]
    fn occluded(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> bool {
        (**self).occluded(o, d, tmin, tmax, key)
    }
}

/// A ray origin moved off the surface at `p` (normal `n`) to the side `d` leaves on.
#[inline]
pub fn spawn(p: Vec3, n: Vec3, d: Vec3, epsilon: f32) -> Vec3 {
    let scale = epsilon * (1.0 + p.abs().max_element());
    if n.dot(d) >= 0.0 {
        p + n * scale
    } else {
        p - n * scale
    }
}
