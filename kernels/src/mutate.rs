//! The `mutate` pass (seed §5.1): one invocation per candidate builds its primary samples in
//! the SoA candidate buffer. A chain's 2^d − 1 candidates are adjacent invocations; each level's
//! perturbation is one draw per (chain, iteration, level, dimension) shared by the whole level
//! (`shared::mutation::tree_candidate_sample`). In bootstrap mode every candidate is a fresh
//! independent sample.

use shared::layout::soa_index;
use shared::mmlt::{bootstrap_key, RenderParams, MODE_BOOTSTRAP};
use shared::mutation::{is_large_step, tree_candidate_sample, tree_level_uniforms};
use shared::rng::{self, RngKey};
use shared::tree::candidate_count;
use spirv_std::glam::UVec3;
use spirv_std::spirv;

/// The kernel body for candidate `k`. Dimensions are handled four at a time, one random hash
/// per level serving four dimensions.
pub fn mutate(k: usize, params: &RenderParams, chain_u: &[f32], cand_u: &mut [f32]) {
    let k = k as u32;
    if k >= params.candidates {
        return;
    }
    let c = params.candidates;
    let groups = params.dims.div_ceil(4);
    if params.mode == MODE_BOOTSTRAP {
        let key = bootstrap_key(params.seed, params.sample_offset + k);
        let mut group = 0;
        while group < groups {
            let u = rng::uniform4(key, rng::STREAM_LARGE_STEP, group);
            let mut lane = 0;
            while lane < 4 && 4 * group + lane < params.dims {
                cand_u[soa_index(k, 4 * group + lane, c)] = u[lane as usize];
                lane += 1;
            }
            group += 1;
        }
        return;
    }
    let per_chain = candidate_count(params.tree_depth);
    let chain = k / per_chain;
    let j = k % per_chain;
    let large = is_large_step(params.seed, chain, params.iteration, params.mutation.p_large);
    let key = RngKey { seed: params.seed, chain, iteration: params.iteration, dimension: 0 };
    let mut group = 0;
    while group < groups {
        let u = tree_level_uniforms(key, j, large, group);
        let mut lane = 0;
        while lane < 4 && 4 * group + lane < params.dims {
            let dim = 4 * group + lane;
            let current = chain_u[soa_index(chain, dim, params.chains)];
            cand_u[soa_index(k, dim, c)] =
                tree_candidate_sample(current, j, large, &u[lane as usize], &params.mutation);
            lane += 1;
        }
        group += 1;
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
