//! The `raycast` pass: the bench's bare ray throughput. One invocation per candidate replays
//! the rays that candidate's `trace` and `connect` cast (recorded on the host with
//! `shared::rays::logged`), in the same order, with nothing else around them: no sampling, no
//! shading, no vertex stores. Ray `j` of candidate `k` is at `k + j·C`, so neighbouring
//! invocations cast their j-th rays together, as they do in `trace` and `connect`; shorter
//! lists are padded with `RAY_NONE`. Each invocation writes the sum of its answers.

use shared::cwbvh::{WideBvh, WideNode};
use shared::mmlt::RenderParams;
use shared::ray_caster::RayCaster;
use shared::rays::{cast, Ray};
use shared::triangle::Triangle;
use spirv_std::glam::UVec3;
use spirv_std::spirv;

/// The kernel body for candidate `k` (`params.candidates` = C).
pub fn raycast<R: RayCaster>(k: usize, params: &RenderParams, caster: &R, rays: &[Ray], answers: &mut [u32]) {
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

/// Entry point: one invocation per candidate.
#[spirv(compute(threads(64), entry_point_name = "raycast_cs"))]
pub fn raycast_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] params: &[RenderParams],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] nodes: &[WideNode],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] triangles: &[Triangle],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] rays: &[Ray],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] answers: &mut [u32],
) {
    raycast(id.x as usize, &params[0], &WideBvh { nodes, triangles }, rays, answers);
}
