//! The `raycast` pass: binds params (for the candidate count C), the BVH, the replayed rays
//! (`k + j·C`) and one answer word per candidate.

use kernels::raycast::raycast;
use shared::mmlt::RenderParams;
use shared::ray_caster::RayCaster;
use shared::rays::Ray;

use super::{Binding, Pass};
use crate::gpu::{Gpu, GpuError};

/// The GPU pass over `buffers` = [params, nodes, triangles, rays, answers].
pub fn gpu(gpu: &Gpu, buffers: [&wgpu::Buffer; 5]) -> Result<Pass, GpuError> {
    let [params, nodes, triangles, rays, answers] = buffers;
    Pass::new(
        gpu,
        "raycast_cs",
        &[
            Binding::Read(params),
            Binding::Read(nodes),
            Binding::Read(triangles),
            Binding::Read(rays),
            Binding::Write(answers),
        ],
    )
}

/// The same body on the CPU, over every candidate.
pub fn cpu<R: RayCaster>(params: &RenderParams, caster: &R, rays: &[Ray], answers: &mut [u32]) {
    for k in 0..params.candidates as usize {
        raycast(k, params, caster, rays, answers);
    }
}
