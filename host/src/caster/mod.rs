//! The CPU backend's ray casters, behind `shared::ray_caster::RayCaster` as the device's:
//! Intel Embree where its library is installed (the fastest traversal measured here, by
//! `host/examples/rays.rs`), else obvhs's traversal of the device's own BVH. `SMLT_RAY_CASTER`
//! (`embree` or `obvhs`) chooses one explicitly. Every caster answers every query as the
//! others do, ray by ray, cut-outs included (`tests/ray_casters.rs`).

mod embree;
mod obvhs;

use glam::Vec3;
use shared::ray_caster::{Hit, RayCaster};

pub use embree::{EmbreeCaster, EmbreeScene, PACKET};
pub use obvhs::ObvhsCaster;

/// The CPU backend's ray caster for one scene.
#[derive(Clone, Copy)]
pub enum HostCaster<'a> {
    /// Intel Embree 3.
    Embree(EmbreeCaster<'a>),
    /// obvhs's traversal of the compressed wide BVH.
    Obvhs(ObvhsCaster<'a>),
}

/// A ray query of a batch: the segment o + t·d for tmin < t < tmax, its cut-outs drawn by `key`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Query {
    #[allow(missing_docs)] // with direction, tmin and tmax: the segment
    pub origin: Vec3,
    /// A unit vector.
    pub direction: Vec3,
    #[allow(missing_docs)]
    pub tmin: f32,
    #[allow(missing_docs)]
    pub tmax: f32,
    #[allow(missing_docs)] // as RayCaster's
    pub key: u32,
}

impl HostCaster<'_> {
    /// The closest hits of a batch of independent queries, into `hits` (as many): Embree's
    /// packets, or one at a time. The answers are [`RayCaster::closest_hit`]'s.
    pub fn closest_hits(&self, queries: &[Query], hits: &mut [Hit]) {
        match self {
            HostCaster::Embree(e) => e.closest_hits(queries, hits),
            HostCaster::Obvhs(c) => {
                for (q, h) in queries.iter().zip(hits.iter_mut()) {
                    *h = c.closest_hit(q.origin, q.direction, q.tmin, q.tmax, q.key);
                }
            }
        }
    }

    /// Whether anything blocks each of a batch of independent queries, into `blocked` (as
    /// many): Embree's packets, or one at a time. The answers are [`RayCaster::occluded`]'s.
    pub fn occluded_all(&self, queries: &[Query], blocked: &mut [bool]) {
        match self {
            HostCaster::Embree(e) => e.occluded_all(queries, blocked),
            HostCaster::Obvhs(c) => {
                for (q, b) in queries.iter().zip(blocked.iter_mut()) {
                    *b = c.occluded(q.origin, q.direction, q.tmin, q.tmax, q.key);
                }
            }
        }
    }

    /// The caster in words (for the render's device line).
    pub fn describe(&self) -> &'static str {
        match self {
            HostCaster::Embree(_) => "Embree 3",
            HostCaster::Obvhs(_) => "obvhs",
        }
    }
}

impl RayCaster for HostCaster<'_> {
    #[inline]
    fn closest_hit(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> Hit {
        match self {
            HostCaster::Embree(e) => e.closest_hit(o, d, tmin, tmax, key),
            HostCaster::Obvhs(c) => c.closest_hit(o, d, tmin, tmax, key),
        }
    }

    #[inline]
    fn occluded(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> bool {
        match self {
            HostCaster::Embree(e) => e.occluded(o, d, tmin, tmax, key),
            HostCaster::Obvhs(c) => c.occluded(o, d, tmin, tmax, key),
        }
    }
}

/// Which caster the CPU backend should use: `SMLT_RAY_CASTER`, else Embree where it loads.
pub fn wants_embree() -> bool {
    match std::env::var("SMLT_RAY_CASTER").as_deref() {
        Ok("obvhs") => false,
        Ok("embree") => true,
        _ => embree::available().is_ok(),
    }
}

/// Why Embree is not used, if it is not available.
pub fn embree_unavailable() -> Option<&'static str> {
    embree::available().err()
}
