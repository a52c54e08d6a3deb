//! The `mutate` pass: binds params, chain states and samples (read), candidate samples and
//! depths (write).

use kernels::mutate::mutate;
use shared::mmlt::{ChainState, RenderParams};

use super::Pass;
use crate::gpu::{Gpu, GpuError};
use crate::render::gpu::GpuBuffers;

/// The GPU pass.
pub fn gpu(gpu: &Gpu, b: &GpuBuffers) -> Result<Pass, GpuError> {
    Pass::new(
        gpu,
        "mutate_cs",
        &[
            (&b.params, true),
            (&b.chains, true),
            (&b.chain_u, true),
            (&b.cand_u, false),
            (&b.cand_depth, false),
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
