//! The `trace` pass: binds params, candidate depths and samples, the scene, and writes
//! the vertex and path-info buffers.

use kernels::trace::trace;
use shared::mmlt::{PathInfo, PathVertex, RenderParams};
use shared::ray_caster::RayCaster;
use shared::scene::Scene;

use super::buffers::GpuBuffers;
use super::{Binding, Pass, Stage};
use crate::gpu::{Gpu, GpuError};

/// The pass on `gpu`, binding the buffers of `b` that the module doc lists.
pub fn gpu(gpu: &Gpu, b: &GpuBuffers) -> Result<Pass, GpuError> {
    Pass::new(
        gpu,
        Stage::Trace.entry_point(),
        &[
            Binding::Read(&b.params),
            Binding::Read(&b.iteration.cand_depth),
            Binding::Read(&b.iteration.cand_u),
            Binding::Read(&b.scene.nodes),
            Binding::Read(&b.scene.triangles),
            Binding::Read(&b.scene.materials),
            Binding::Read(&b.scene.lights),
            Binding::Write(&b.iteration.vertices),
            Binding::Write(&b.iteration.paths),
        ],
    )
}

/// The same body on the CPU, over every candidate.
pub fn cpu<R: RayCaster>(
    params: &RenderParams,
    cand_depth: &[u32],
    cand_u: &[f32],
    scene: Scene<R>,
    vertices: &mut [PathVertex],
    paths: &mut [PathInfo],
) {
    for k in 0..params.candidates as usize {
        trace(k, params, cand_depth, cand_u, scene, vertices, paths);
    }
}
