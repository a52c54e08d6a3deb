//! The `select` pass: binds params, chain states and samples (updated), candidate samples and
//! contributions, and writes the splat records.

use glam::Vec4;
use kernels::select::select;
use shared::mmlt::{ChainState, RenderParams};

use super::{Binding, Pass, Stage};
use crate::gpu::{Gpu, GpuError};
use crate::render::gpu::GpuBuffers;

/// The GPU pass.
pub fn gpu(gpu: &Gpu, b: &GpuBuffers) -> Result<Pass, GpuError> {
    Pass::new(
        gpu,
        Stage::Select.entry_point(),
        &[
            Binding::Read(&b.params),
            Binding::Write(&b.chains),
            Binding::Write(&b.chain_u),
            Binding::Read(&b.cand_u),
            Binding::Read(&b.cand_depth),
            Binding::Read(&b.contributions),
            Binding::Write(&b.splats),
        ],
    )
}

/// The same body on the CPU, over every chain.
pub fn cpu(
    params: &RenderParams,
    chains: &mut [ChainState],
    chain_u: &mut [f32],
    cand_u: &[f32],
    cand_depth: &[u32],
    contributions: &[Vec4],
    splats: &mut [Vec4],
) {
    for p in 0..params.chains as usize {
        select(p, params, chains, chain_u, cand_u, cand_depth, contributions, splats);
    }
}
