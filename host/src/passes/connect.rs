//! The `connect` pass: binds params, candidate samples, the scene, vertices and path infos,
//! and writes the packed contributions.

use glam::Vec4;
use kernels::connect::connect;
use shared::mmlt::{PathInfo, PathVertex, RenderParams, Scene};

use super::{Binding, Pass, Stage};
use crate::gpu::{Gpu, GpuError};
use crate::render::gpu::GpuBuffers;

/// The GPU pass.
pub fn gpu(gpu: &Gpu, b: &GpuBuffers) -> Result<Pass, GpuError> {
    Pass::new(
        gpu,
        Stage::Connect.entry_point(),
        &[
            Binding::Read(&b.params),
            Binding::Read(&b.cand_u),
            Binding::Read(&b.nodes),
            Binding::Read(&b.triangles),
            Binding::Read(&b.materials),
            Binding::Read(&b.lights),
            Binding::Read(&b.vertices),
            Binding::Read(&b.paths),
            Binding::Write(&b.contributions),
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
