//! The `connect` pass: binds params, candidate samples, the scene, vertices and path infos,
//! and writes the packed contributions.

use glam::Vec4;
use kernels::connect::connect;
use shared::mmlt::{PathInfo, PathVertex, RenderParams, Scene};

use super::Pass;
use crate::gpu::{Gpu, GpuError};
use crate::render::gpu::GpuBuffers;

/// The GPU pass.
pub fn gpu(gpu: &Gpu, b: &GpuBuffers) -> Result<Pass, GpuError> {
    Pass::new(
        gpu,
        "connect_cs",
        &[
            (&b.params, true),
            (&b.cand_u, true),
            (&b.nodes, true),
            (&b.triangles, true),
            (&b.materials, true),
            (&b.lights, true),
            (&b.vertices, true),
            (&b.paths, true),
            (&b.contributions, false),
        ],
    )
}

/// The same body on the CPU, over every candidate.
pub fn cpu(
    params: &RenderParams,
    cand_u: &[f32],
    scene: Scene,
    vertices: &[PathVertex],
    paths: &[PathInfo],
    contributions: &mut [Vec4],
) {
    for k in 0..params.candidates as usize {
        connect(k, params, cand_u, scene, vertices, paths, contributions);
    }
}
