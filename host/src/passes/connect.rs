//! The `connect` pass: binds params, candidate samples, the scene, vertices and path infos,
//! writes the packed contributions, and reads the pixel importance they are divided by; the
//! path estimator also writes each candidate's depth (the vertices its path read).

use glam::Vec4;
use kernels::connect::connect;
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
        Stage::Connect.entry_point(),
        &[
            Binding::Read(&b.params),
            Binding::Read(&b.iteration.cand_u),
            Binding::Read(&b.scene.nodes),
            Binding::Read(&b.scene.triangles),
            Binding::Read(&b.scene.materials),
            Binding::Read(&b.scene.lights),
            Binding::Read(&b.iteration.vertices),
            Binding::Read(&b.iteration.paths),
            Binding::Write(&b.iteration.contributions),
            Binding::Read(&b.importance),
            Binding::Write(&b.iteration.cand_depth),
        ],
    )
}

/// The same body on the CPU, over every candidate.
#[allow(clippy::too_many_arguments)] // one slice per binding, as the kernel takes them
pub fn cpu<R: RayCaster>(
    params: &RenderParams,
    cand_u: &[f32],
    scene: Scene<R>,
    vertices: &[PathVertex],
    paths: &[PathInfo],
    importance: &[f32],
    contributions: &mut [Vec4],
    cand_depth: &mut [u32],
) {
    for k in 0..params.candidates as usize {
        connect(k, params, cand_u, scene, vertices, paths, importance, contributions, cand_depth);
    }
}
