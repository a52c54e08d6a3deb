//! obvhs's own traversal of the same compressed wide BVH the device traverses (its SSE node
//! test, eight children at a time), with smlt's triangle test, so it answers every query
//! exactly as the device's caster does (`shared::cwbvh`), cut-outs included.

use glam::Vec3;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};
use shared::cutout::Cutouts;
use shared::ray_caster::{Hit, RayCaster, NO_HIT};
use shared::triangle::TriangleEdges;

/// obvhs's CWBVH traversal over the scene's triangles (in the BVH's order).
#[derive(Clone, Copy)]
pub struct ObvhsCaster<'a> {
    /// obvhs's compressed wide BVH over the scene's triangles.
    pub bvh: &'a CwBvh,
    /// The triangles' vertices and edges, in the BVH's order (a leaf's triangle `i` is slot
    /// `i`), precomputed: 36 bytes a triangle instead of the 48 of a
    /// [`shared::triangle::Triangle`], and six subtractions fewer per test.
    pub edges: &'a [TriangleEdges],
    /// The cut-outs among them (`shared::cutout`).
    pub cutouts: Cutouts<'a>,
}

impl ObvhsCaster<'_> {
    /// The distance at which triangle `slot` stops the ray within (tmin, tmax), or [`NO_HIT`].
    #[inline]
    fn test(&self, slot: usize, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> f32 {
        let t = self.edges[slot].intersect(o, d, tmin, tmax);
        if t < tmax && !self.cutouts.stops(slot as u32, o, d, t, key) {
            NO_HIT
        } else {
            t
        }
    }
}

/// obvhs's ray for a query. A zero direction component of negative sign becomes +0: obvhs
/// takes the reciprocal's sign from `signum` (−1 for −0) but picks a box's near plane by
/// `direction < 0` (false for −0), so a −0 component would swap the planes and miss every box
/// (found by `tests/scene_loading.rs`).
#[inline]
fn obvhs_ray(o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Ray {
    Ray::new(o.into(), (d + Vec3::ZERO).into(), tmin, tmax)
}

impl RayCaster for ObvhsCaster<'_> {
    #[inline]
    fn closest_hit(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> Hit {
        let mut hit = RayHit::none();
        let ray = obvhs_ray(o, d, tmin, tmax);
        let found =
            self.bvh.ray_traverse(ray, &mut hit, |ray, slot| self.test(slot, o, d, tmin, ray.tmax, key));
        if found {
            Hit { t: hit.t, triangle: hit.primitive_id }
        } else {
            Hit::NONE
        }
    }

    #[inline]
    fn occluded(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> bool {
        let ray = obvhs_ray(o, d, tmin, tmax);
        !self.bvh.ray_traverse_miss(ray, |ray, slot| self.test(slot, o, d, tmin, ray.tmax, key))
    }
}
