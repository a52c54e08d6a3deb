//! The `trace` pass: binds params, candidate depths and samples, the scene, and writes
//! the vertex and path-info buffers.

use kernels::trace::trace;
use shared::mmlt::{PathInfo, PathVertex, RenderParams, Scene};

use super::Pass;
use crate::gpu::{Gpu, GpuError};
use crate::render::gpu::GpuBuffers;

/// The GPU pass.
pub fn gpu(gpu: &Gpu, b: &GpuBuffers) -> Result<Pass, GpuError> {
    Pass::new(
        gpu,
        "trace_cs",
        &[
            (&b.params, true),
            (&b.cand_depth, true),
            (&b.cand_u, true),
            (&b.nodes, true),
            (&b.triangles, true),
            (&b.materials, true),
            (&b.lights, true),
            (&b.vertices, false),
            (&b.paths, false),
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
