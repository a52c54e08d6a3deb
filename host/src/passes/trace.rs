//! The `trace` pass: binds params, candidate depths and samples, the scene, and writes
//! the vertex and path-info buffers.

use kernels::trace::trace;
use shared::mmlt::{PathInfo, PathVertex, RenderParams, Scene};

use super::{Binding, Pass, Stage};
use crate::gpu::{Gpu, GpuError};
use crate::render::gpu::GpuBuffers;

/// The GPU pass.
pub fn gpu(gpu: &Gpu, b: &GpuBuffers) -> Result<Pass, GpuError> {
    Pass::new(
        gpu,
        Stage::Trace.entry_point(),
        &[
            Binding::Read(&b.params),
            Binding::Read(&b.cand_depth),
            Binding::Read(&b.cand_u),
            Binding::Read(&b.nodes),
            Binding::Read(&b.triangles),
            Binding::Read(&b.materials),
            Binding::Read(&b.lights),
            Binding::Write(&b.vertices),
            Binding::Write(&b.paths),
        ],
    )
}

/// The same body on the CPU, over every candidate.
pub fn cpu(
    params: &RenderParams,
    cand_depth: &[u32],
    cand_u: &[f32],
    scene: Scene,
    vertices: &mut [PathVertex],
    paths: &mut [PathInfo],
) {
    for k in 0..params.candidates as usize {
        trace(k, params, cand_depth, cand_u, scene, vertices, paths);
    }
}
