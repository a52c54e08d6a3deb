//! The `mutate` pass: binds params, chain states and samples (read), candidate samples and
//! depths (write).

use kernels::mutate::mutate;
use shared::mmlt::{ChainState, RenderParams};

use super::buffers::GpuBuffers;
use super::{Binding, Pass, Stage};
use crate::gpu::{Gpu, GpuError};

/// The pass on `gpu`, binding the buffers of `b` that the module doc lists.
pub fn gpu(gpu: &Gpu, b: &GpuBuffers) -> Result<Pass, GpuError> {
    Pass::new(
        gpu,
        Stage::Mutate.entry_point(),
        &[
            Binding::Read(&b.params),
            Binding::Read(&b.iteration.chains),
            Binding::Read(&b.iteration.chain_u),
            Binding::Write(&b.iteration.cand_u),
            Binding::Write(&b.iteration.cand_depth),
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
