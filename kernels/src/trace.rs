//! The `trace` pass: one invocation per candidate chooses the MMLT technique and traces the
//! camera and light subpaths into the vertex buffer (`shared::mmlt::trace_candidate`). The
//! path estimator (`shared::pssmlt`) has nothing to trace here.

use shared::bsdf::Material;
use shared::cwbvh::{WideBvh, WideNode};
use shared::light::LightEntry;
use shared::mmlt::{trace_candidate, PathInfo, PathVertex, RenderParams, Samples, ESTIMATOR_PATH};
use shared::ray_caster::RayCaster;
use shared::scene::Scene;
use shared::triangle::Triangle;
use spirv_std::glam::UVec3;
use spirv_std::spirv;

/// The kernel body for candidate `k`.
#[allow(clippy::too_many_arguments)]
pub fn trace<R: RayCaster>(
    k: usize,
    params: &RenderParams,
    cand_depth: &[u32],
    cand_u: &[f32],
    scene: Scene<R>,
    vertices: &mut [PathVertex],
    paths: &mut [PathInfo],
) {
    let k = k as u32;
    // The path estimator traces its whole path in `connect`.
    if k >= params.candidates || params.estimator == ESTIMATOR_PATH {
        return;
    }
    let depth = cand_depth[k as usize];
    let samples = Samples { candidate: k, count: params.candidates };
    paths[k as usize] = trace_candidate(params, scene, cand_u, samples, depth, vertices);
}

/// Entry point: one invocation per candidate.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64), entry_point_name = "trace_cs"))]
pub fn trace_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] params: &[RenderParams],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] cand_depth: &[u32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] cand_u: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] nodes: &[WideNode],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] triangles: &[Triangle],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] materials: &[Material],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] lights: &[LightEntry],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 7)] vertices: &mut [PathVertex],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 8)] paths: &mut [PathInfo],
) {
    let scene = Scene { caster: WideBvh { nodes, triangles }, triangles, materials, lights };
    trace(id.x as usize, &params[0], cand_depth, cand_u, scene, vertices, paths);
}
