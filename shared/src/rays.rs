//! The rays the path code casts, as data: a [`Ray`] record that the `raycast` kernel replays
//! with nothing around it (the bench's bare ray throughput, the ceiling against which the
//! mutation throughput is read), and, on the host only, a per-thread log of every ray that
//! [`crate::bvh::closest_hit`] and [`crate::bvh::occluded`] cast while [`logged`] runs (how the
//! bench counts rays per candidate without a counter in the kernels).

use crate::bvh::{closest_hit, occluded, BvhNode, Triangle};
use bytemuck::{Pod, Zeroable};
use glam::Vec3;

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
    /// Origin.
    pub origin: [f32; 3],
    /// Start of the interval.
    pub tmin: f32,
    /// Unit direction.
    pub direction: [f32; 3],
    /// End of the interval.
    pub tmax: f32,
    /// [`RAY_NONE`], [`RAY_CLOSEST`] or [`RAY_OCCLUSION`].
    pub kind: u32,
    /// Padding to 16 bytes.
    pub _pad: [u32; 3],
}

impl Ray {
    /// A ray query.
    pub fn new(kind: u32, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Self {
        Self { origin: o.to_array(), tmin, direction: d.to_array(), tmax, kind, _pad: [0; 3] }
    }
}

/// Casts `ray` and folds its answer into one word: the hit triangle's index + 1 for a
/// closest-hit query (0 on a miss), 1 when an occlusion query is blocked, 0 for padding. The
/// replay kernel sums these so that the device cannot skip the work, and the difftest compares
/// the sums with the host's.
#[inline]
pub fn cast(nodes: &[BvhNode], tris: &[Triangle], ray: &Ray) -> u32 {
    let o = Vec3::from_array(ray.origin);
    let d = Vec3::from_array(ray.direction);
    if ray.kind == RAY_CLOSEST {
        let hit = closest_hit(nodes, tris, o, d, ray.tmin, ray.tmax);
        if hit.found() {
            hit.triangle + 1
        } else {
            0
        }
    } else if ray.kind == RAY_OCCLUSION {
        occluded(nodes, tris, o, d, ray.tmin, ray.tmax) as u32
    } else {
        0
    }
}

#[cfg(not(target_arch = "spirv"))]
mod log {
    use super::Ray;
    use std::cell::RefCell;

    std::thread_local! {
        static LOG: RefCell<Option<Vec<Ray>>> = const { RefCell::new(None) };
    }

    /// Appends `ray` to this thread's log when [`logged`] is running.
    #[inline]
    pub fn record(ray: Ray) {
        LOG.with(|log| {
            if let Some(rays) = log.borrow_mut().as_mut() {
                rays.push(ray);
            }
        });
    }

    /// Runs `f` on this thread and returns its result with every ray it cast, in order.
    /// Nested calls log into the innermost.
    pub fn logged<R>(f: impl FnOnce() -> R) -> (R, Vec<Ray>) {
        let outer = LOG.with(|log| log.borrow_mut().replace(Vec::new()));
        let result = f();
        let rays = LOG.with(|log| core::mem::replace(&mut *log.borrow_mut(), outer)).unwrap_or_default();
        (result, rays)
    }
}

#[cfg(not(target_arch = "spirv"))]
pub use log::{logged, record};

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;
    use crate::bvh::NO_HIT;

    fn floor() -> (Vec<BvhNode>, Vec<Triangle>) {
        let tri = Triangle {
            v0: [-1.0, 0.0, -1.0],
            v1: [1.0, 0.0, -1.0],
            v2: [0.0, 0.0, 1.0],
            ..Default::default()
        };
        let node = BvhNode { min: [-1.0, 0.0, -1.0], count: 1, max: [1.0, 0.0, 1.0], first: 0 };
        (vec![node], vec![tri])
    }

    /// The log holds exactly the queries made inside it, in order, with their intervals, and
    /// replaying them with `cast` gives the same answers.
    #[test]
    fn the_log_records_every_query_and_replays_it() {
        let (nodes, tris) = floor();
        let down = Vec3::NEG_Y;
        let ((), rays) = logged(|| {
            assert!(closest_hit(&nodes, &tris, Vec3::Y, down, 0.0, NO_HIT).found());
            assert!(!closest_hit(&nodes, &tris, Vec3::Y, -down, 0.0, NO_HIT).found());
            assert!(occluded(&nodes, &tris, Vec3::Y, down, 0.0, 2.0));
            assert!(!occluded(&nodes, &tris, Vec3::Y, down, 0.0, 0.5));
        });
        assert_eq!(rays.len(), 4);
        assert_eq!(rays[0], Ray::new(RAY_CLOSEST, Vec3::Y, down, 0.0, NO_HIT));
        assert_eq!(rays[3], Ray::new(RAY_OCCLUSION, Vec3::Y, down, 0.0, 0.5));
        let answers: Vec<u32> = rays.iter().map(|r| cast(&nodes, &tris, r)).collect();
        assert_eq!(answers, [1, 0, 1, 0]);
        assert_eq!(cast(&nodes, &tris, &Ray::default()), 0, "padding casts nothing");
    }

    /// Outside `logged` nothing is kept; nested logs keep their own rays.
    #[test]
    fn logging_is_scoped() {
        let (nodes, tris) = floor();
        let cast_one = || closest_hit(&nodes, &tris, Vec3::Y, Vec3::NEG_Y, 0.0, NO_HIT);
        cast_one();
        let ((_, inner), outer) = logged(|| {
            cast_one();
            let inner = logged(|| {
                cast_one();
                cast_one();
            });
            cast_one();
            inner
        });
        assert_eq!((outer.len(), inner.len()), (2, 2));
        assert_eq!(logged(|| ()).1.len(), 0);
    }
}
