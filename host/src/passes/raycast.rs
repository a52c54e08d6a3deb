//! The `raycast` pass (the bench's bare ray throughput): binds params (for the candidate count
//! C), the replayed rays (`k + j·C`), one answer word per candidate, and the scene.

use kernels::raycast::RaycastIo;
use shared::params::RenderParams;
use shared::ray_caster::RayCaster;
use shared::rays::Ray;
use shared::scene::Scene;

use super::buffers::Registry;
use super::{Named, Pass};
use crate::gpu::{Gpu, GpuError};

/// The GPU pass over its own `params`, `rays` and `answers` buffers and the scene's, found in
/// `scene` (the registry of a `SceneBuffers` on the device).
pub fn gpu(
    gpu: &Gpu,
    [params, rays, answers]: [&wgpu::Buffer; 3],
    scene: &Registry,
) -> Result<Pass, GpuError> {
    use kernels::raycast::{BINDINGS, BINDS_SCENE, ENTRY_POINT};
    let find = |name: &str| match name {
        "params" => Some(Named { buffer: params, element: std::any::type_name::<RenderParams>() }),
        "rays" => Some(Named { buffer: rays, element: std::any::type_name::<Ray>() }),
        "answers" => Some(Named { buffer: answers, element: std::any::type_name::<u32>() }),
        _ => scene.named(name),
    };
    Pass::new(gpu, ENTRY_POINT, BINDINGS, BINDS_SCENE, &find)
}

/// The same body on the CPU, over every candidate.
pub fn cpu<R: RayCaster + Copy>(params: &RenderParams, scene: Scene<R>, rays: &[Ray], answers: &mut [u32]) {
    RaycastIo { params, rays, answers, scene }.run(params.candidates as usize);
}
