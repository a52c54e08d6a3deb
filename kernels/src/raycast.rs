//! The `raycast` pass: the bench's bare ray throughput. One invocation per candidate replays
//! the rays that candidate's `trace` and `connect` cast (recorded on the host with
//! `shared::rays::logged`), in the same order, with nothing else around them: no sampling, no
//! shading, no vertex stores. Ray `j` of candidate `k` is at `k + j·C`, so neighbouring
//! invocations cast their j-th rays together, as they do in `trace` and `connect`; shorter
//! lists are padded with `RAY_NONE`. Each invocation writes the sum of its answers.

use shared::params::RenderParams;
use shared::ray_caster::RayCaster;
use shared::rays::{cast, Ray};

stage! {
    /// What `raycast` binds.
    pub struct RaycastIo<'a> over scene R {
        0 params: uniform RenderParams,
        /// The rays, ray `j` of candidate `k` at `k + j·C`.
        1 rays: read Ray,
        /// The sum of each candidate's answers.
        2 answers: write u32,
    }
    entry "raycast_cs" (threads 64) => raycast;
}

/// The kernel body for candidate `k` (`params.candidates` = C).
pub fn raycast<R: RayCaster>(k: usize, io: RaycastIo<R>) {
    let RaycastIo { params, scene, rays, answers } = io;
    let caster = &scene.caster;
    let candidates = params.candidates as usize;
    if k >= candidates {
        return;
    }
    let mut sum = 0u32;
    let mut j = k;
    while j < rays.len() {
        sum = sum.wrapping_add(cast(caster, &rays[j]));
        j += candidates;
    }
    answers[k] = sum;
}
