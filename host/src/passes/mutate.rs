//! The `mutate` pass: binds params, chain samples (read), candidate samples (write).

use kernels::mutate::mutate;
use shared::mmlt::RenderParams;

use super::Pass;
use crate::gpu::{Gpu, GpuError};
use crate::render::gpu::GpuBuffers;

/// The GPU pass.
pub fn gpu(gpu: &Gpu, b: &GpuBuffers) -> Result<Pass, GpuError> {
    Pass::new(gpu, "mutate_cs", &[(&b.params, true), (&b.chain_u, true), (&b.cand_u, false)])
}

/// The same body on the CPU, over every candidate.
pub fn cpu(params: &RenderParams, chain_u: &[f32], cand_u: &mut [f32]) {
    for k in 0..params.candidates as usize {
        mutate(k, params, chain_u, cand_u);
    }
}
