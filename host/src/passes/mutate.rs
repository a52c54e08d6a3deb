//! The `mutate` pass: binds params, chain states and samples (read), candidate samples and
//! depths (write).

use kernels::mutate::mutate;
use shared::mmlt::{ChainState, RenderParams};

use super::{Binding, Pass, Stage};
use crate::gpu::{Gpu, GpuError};
use crate::render::gpu::GpuBuffers;

/// The GPU pass.
pub fn gpu(gpu: &Gpu, b: &GpuBuffers) -> Result<Pass, GpuError> {
    Pass::new(
        gpu,
        Stage::Mutate.entry_point(),
        &[
            Binding::Read(&b.params),
            Binding::Read(&b.chains),
            Binding::Read(&b.chain_u),
            Binding::Write(&b.cand_u),
            Binding::Write(&b.cand_depth),
        ],
    )
}

/// The same body on the CPU, over every candidate.
pub fn cpu(
    params: &RenderParams,
    chains: &[ChainState],
    chain_u: &[f32],
    cand_u: &mut [f32],
    cand_depth: &mut [u32],
) {
    for k in 0..params.candidates as usize {
        mutate(k, params, chains, chain_u, cand_u, cand_depth);
    }
}
