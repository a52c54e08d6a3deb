//! The `mutate` pass (seed §5.1): one invocation per candidate builds its primary samples in
//! the SoA candidate buffer. A chain's 2^d − 1 candidates are adjacent invocations; each level's
//! perturbation is one draw per (chain, iteration, level, dimension) shared by the whole level
//! (`shared::mutation::tree_candidate_sample`). In bootstrap mode every candidate is a fresh
//! independent sample.

use shared::layout::soa_index;
use shared::mmlt::{bootstrap_sample, RenderParams, MODE_BOOTSTRAP};
use shared::mutation::{is_large_step, tree_candidate_sample};
use shared::rng::RngKey;
use shared::tree::candidate_count;
use spirv_std::glam::UVec3;
use spirv_std::spirv;

/// The kernel body for candidate `k`.
pub fn mutate(k: usize, params: &RenderParams, chain_u: &[f32], cand_u: &mut [f32]) {
    let k = k as u32;
    if k >= params.candidates {
        return;
    }
    let c = params.candidates;
    if params.mode == MODE_BOOTSTRAP {
        let mut dim = 0;
        while dim < params.dims {
            cand_u[soa_index(k, dim, c)] = bootstrap_sample(params.seed, params.sample_offset + k, dim);
            dim += 1;
        }
        return;
    }
    let per_chain = candidate_count(params.tree_depth);
    let chain = k / per_chain;
    let j = k % per_chain;
    let large = is_large_step(params.seed, chain, params.iteration, params.mutation.p_large);
    let key = RngKey { seed: params.seed, chain, iteration: params.iteration, dimension: 0 };
    let mut dim = 0;
    while dim < params.dims {
        let current = chain_u[soa_index(chain, dim, params.chains)];
        cand_u[soa_index(k, dim, c)] = tree_candidate_sample(current, j, large, key, dim, &params.mutation);
        dim += 1;
    }
}

/// Entry point: one invocation per candidate.
#[spirv(compute(threads(64), entry_point_name = "mutate_cs"))]
pub fn mutate_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] params: &[RenderParams],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] chain_u: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] cand_u: &mut [f32],
) {
    mutate(id.x as usize, &params[0], chain_u, cand_u);
}
