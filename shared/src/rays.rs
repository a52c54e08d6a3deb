//! The rays the path code casts, as data: a [`Ray`] record that the `raycast` kernel replays
//! with nothing around it (the bench's bare ray throughput, the ceiling against which the
//! candidate throughput is read). The host records them with a logging ray caster around the
//! kernel bodies; nothing here sits in the traversal's way.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use crate::ray_caster::RayCaster;

/// No ray: padding in a replay buffer.
pub const RAY_NONE: u32 = 0;
/// A closest-hit query (a path vertex is being found).
pub const RAY_CLOSEST: u32 = 1;
/// An any-hit query (a shadow ray of a connection or of next-event estimation).
pub const RAY_OCCLUSION: u32 = 2;

/// One ray query: origin, unit direction, the interval (tmin, tmax) and which query it is.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Ray {
    #[allow(missing_docs)] // with direction, tmin and tmax: the ray o + t·d, tmin < t < tmax
    pub origin: [f32; 3],
    #[allow(missing_docs)]
    pub tmin: f32,
    /// A unit vector.
    pub direction: [f32; 3],
    #[allow(missing_docs)]
    pub tmax: f32,
    /// [`RAY_NONE`], [`RAY_CLOSEST`] or [`RAY_OCCLUSION`].
    pub kind: u32,
    /// The query's key for its BLEND cut-outs ([`crate::cutout::blend_key`]).
    pub key: u32,
    /// Padding to 16 bytes.
    pub _pad: [u32; 2],
}

impl Ray {
    /// The query `kind` along o + t·d for tmin < t < tmax, its cut-outs drawn by `key`.
    pub fn new(kind: u32, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> Self {
        Self { origin: o.to_array(), tmin, direction: d.to_array(), tmax, kind, key, _pad: [0; 2] }
    }
}

/// Casts `ray` and folds its answer into one word: the hit triangle's index + 1 for a
/// closest-hit query (0 on a miss), 1 when an occlusion query is blocked, 0 for padding. The
/// replay kernel sums these so that the device cannot skip the work, and the difftest compares
/// the sums with the host's.
#[inline]
pub fn cast<R: RayCaster>(caster: &R, ray: &Ray) -> u32 {
    let o = Vec3::from_array(ray.origin);
    let d = Vec3::from_array(ray.direction);
    if ray.kind == RAY_CLOSEST {
        let hit = caster.closest_hit(o, d, ray.tmin, ray.tmax, ray.key);
        if hit.found() {
            hit.triangle + 1
        } else {
            0
        }
    } else if ray.kind == RAY_OCCLUSION {
        caster.occluded(o, d, ray.tmin, ray.tmax, ray.key) as u32
    } else {
        0
    }
}
