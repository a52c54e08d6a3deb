//! The `select` pass: binds params, chain states and samples (updated), candidate samples and
//! contributions, and writes the splat records.

use glam::Vec4;
use kernels::select::select;
use shared::mmlt::{ChainState, RenderParams};

use super::buffers::GpuBuffers;
use super::{Binding, Pass, Stage};
use crate::gpu::{Gpu, GpuError};

/// The pass on `gpu`, binding the buffers of `b` that the module doc lists.
pub fn gpu(gpu: &Gpu, b: &GpuBuffers) -> Result<Pass, GpuError> {
    Pass::new(
        gpu,
        Stage::Select.entry_point(),
        &[
            Binding::Read(&b.params),
            Binding::Write(&b.iteration.chains),
            Binding::Write(&b.iteration.chain_u),
            Binding::Read(&b.iteration.cand_u),
            Binding::Read(&b.iteration.cand_depth),
            Binding::Read(&b.iteration.contributions),
            Binding::Write(&b.iteration.splats),
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
