//! The `connect` pass: one invocation per candidate connects the end points of its subpaths
//! with one shadow ray, weighs the path with the balance heuristic, and stores the packed
//! contribution (F divided by its pixel's importance in rgb, the pixel index as the bits of w;
//! seed §5.3). For the path estimator it traces the candidate's whole path instead
//! (`shared::pssmlt::path_candidate`), divided the same way, and stores as the candidate's depth
//! how many vertices' uniforms the path read (what `mutate` perturbs of the state it moves to).

use shared::bsdf::Material;
use shared::cwbvh::{WideBvh, WideNode};
use shared::layout::pack_over_importance;
use shared::light::LightEntry;
use shared::mmlt::{connect_candidate, PathInfo, PathVertex, RenderParams, Samples, ESTIMATOR_PATH};
use shared::pssmlt::path_candidate;
use shared::ray_caster::RayCaster;
use shared::scene::Scene;
use shared::triangle::Triangle;
use spirv_std::glam::{UVec3, Vec4};
use spirv_std::spirv;

/// The kernel body for candidate `k`.
#[allow(clippy::too_many_arguments)] // one slice per binding, as the entry point hands them over
pub fn connect<R: RayCaster>(
    k: usize,
    params: &RenderParams,
    cand_u: &[f32],
    scene: Scene<R>,
    vertices: &[PathVertex],
    paths: &[PathInfo],
    importance: &[f32],
    contributions: &mut [Vec4],
    cand_depth: &mut [u32],
) {
    let k = k as u32;
    if k >= params.candidates {
        return;
    }
    let samples = Samples { candidate: k, count: params.candidates };
    if params.estimator == ESTIMATOR_PATH {
        let (contribution, vertices) = path_candidate(params, scene, cand_u, samples, importance);
        contributions[k as usize] = contribution;
        cand_depth[k as usize] = vertices;
        return;
    }
    let connection = connect_candidate(params, scene, cand_u, samples, &paths[k as usize], vertices);
    contributions[k as usize] = pack_over_importance(connection.contribution, connection.pixel, importance);
}

/// Entry point: one invocation per candidate.
#[allow(clippy::too_many_arguments)]
#[spirv(compute(threads(64), entry_point_name = "connect_cs"))]
pub fn connect_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] params: &[RenderParams],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] cand_u: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] nodes: &[WideNode],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] triangles: &[Triangle],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] materials: &[Material],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] lights: &[LightEntry],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 6)] vertices: &[PathVertex],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 7)] paths: &[PathInfo],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 8)] contributions: &mut [Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 9)] importance: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 10)] cand_depth: &mut [u32],
) {
    let scene = Scene { caster: WideBvh { nodes, triangles }, triangles, materials, lights };
    connect(id.x as usize, &params[0], cand_u, scene, vertices, paths, importance, contributions, cand_depth);
}
