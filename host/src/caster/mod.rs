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

impl HostCaster<'_> {
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
