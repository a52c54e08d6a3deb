//! The `mutate` pass (the paper's §5.1): one invocation per candidate builds primary samples in the
//! SoA candidate buffer. A chain's candidates are adjacent invocations. For a speculative
//! tree, each level's perturbation is one draw per (chain, iteration, level, dimension) shared
//! by the whole level (`shared::tree::tree_level_steps`), so a chain's invocations divide
//! its dimensions among them: each draws its dimensions' level steps once and builds those
//! dimensions of every candidate of the chain (`shared::tree::tree_candidate_samples`). For
//! a reject chain, each of the l proposals is its own mutation of the current state, built by
//! its own invocation. Each candidate also gets its path
//! depth: a large step proposes a fresh uniform depth with its fresh samples, small steps keep
//! the chain's (`shared::mutation::large_step_depth`). In bootstrap mode every candidate is a
//! fresh independent sample of depth `shared::normalisation::bootstrap_depth(index)`. Random numbers
//! are keyed by the chain's render-wide index (`RenderParams::global_chain`). Groups of four dimensions
//! that a candidate's depth never reads (`RenderParams::dimensions_used`) are left as they are.
//! The path estimator's chains (`shared::pssmlt`) span every depth: a candidate's depth is
//! max_depth until `connect` replaces it by the vertices its path read, and the naive and
//! reject chains' small steps draw the groups the state never read afresh
//! (`RenderParams::refreshes_group`).

use shared::layout::{load_group, store_group};
use shared::mmlt::ChainState;
use shared::mutation::{is_large_step, large_step_depth};
use shared::normalisation::bootstrap_depth;
use shared::params::{bootstrap_key, RenderParams, ESTIMATOR_PATH, METHOD_REJECT_CHAIN, MODE_BOOTSTRAP};
use shared::reject_chain::{is_reject_large_step, reject_chain_samples};
use shared::rng::{self, RngKey};
use shared::tree::{
    apply_tree_level_step, descends_from_level_one, tree_candidate_samples, tree_level_step, tree_level_steps,
};
use spirv_std::glam::Vec4;

stage! {
    /// What `mutate` binds.
    pub struct MutateIo<'a> {
        0 params: uniform RenderParams,
        1 chains: read ChainState,
        2 chain_u: read f32,
        /// The candidates' samples, SoA (`k + i·C`).
        3 cand_u: write f32,
        /// The candidates' path depths.
        4 cand_depth: write u32,
    }
    entry "mutate_cs" (threads 64) => mutate;
    bound;
}

/// The kernel body for candidate `k`. Dimensions are handled four at a time, one random hash
/// per level serving four dimensions.
pub fn mutate(k: usize, io: MutateIo) {
    let MutateIo { params, chains, chain_u, cand_u, cand_depth } = io;
    let k = k as u32;
    if k >= params.candidates {
        return;
    }
    let candidates = params.candidates;
    let (dims, groups) = (params.dims, params.dims.div_ceil(4));
    if params.mode == MODE_BOOTSTRAP {
        cand_depth[k as usize] =
            params.candidate_depth(true, || bootstrap_depth(params.sample_offset + k, params.max_depth), 0);
        let key = bootstrap_key(params.seed, params.sample_offset + k);
        let mut group = 0;
        while group < groups {
            let u = Vec4::from_array(rng::uniform4(key, rng::STREAM_LARGE_STEP, group));
            store_group(cand_u, k, group, candidates, dims, u);
            group += 1;
        }
        return;
    }
    let per_chain = params.candidates_per_chain();
    let chain = k / per_chain;
    let j = k % per_chain;
    // Buffers are indexed by the chain's place in this dispatch, random numbers by its
    // render-wide index.
    let global = params.global_chain(chain);
    let key = RngKey { seed: params.seed, chain: global, iteration: params.iteration, dimension: 0 };
    let mut group = 0;
    if params.method == METHOD_REJECT_CHAIN {
        // Proposal j of the reject chain: its own mutation of the current state.
        let large = is_reject_large_step(params.seed, global, params.iteration, j, params.mutation.p_large);
        let fresh = || {
            large_step_depth(
                params.seed,
                global,
                params.iteration,
                rng::CONTROL_REJECT_DEPTH + j,
                params.max_depth,
            )
        };
        let kept = chains[chain as usize].depth;
        let depth = params.candidate_depth(large, fresh, kept);
        cand_depth[k as usize] = depth;
        while group < groups {
            if params.dimensions_used(4 * group, 4, depth) {
                let fresh_group = large || params.refreshes_group(group, kept);
                let current = if fresh_group {
                    Vec4::ZERO
                } else {
                    load_group(chain_u, chain, group, params.chains, dims)
                };
                let out = reject_chain_samples(current, j, fresh_group, key, group, &params.mutation);
                store_group(cand_u, k, group, candidates, dims, out);
            }
            group += 1;
        }
        return;
    }
    // Candidate j of a speculative tree. Each level's mutation is shared by the level's
    // candidates, so the chain's invocations split the work by dimension instead: invocation j
    // draws the tree's level steps of groups j, j + 2^d − 1, … once and builds those
    // dimensions of every candidate of its chain (the naive chain, d = 1, builds all of its
    // one candidate's).
    let large = is_large_step(params.seed, global, params.iteration, params.mutation.p_large);
    let kept = chains[chain as usize].depth;
    let fresh = if large && params.estimator != ESTIMATOR_PATH {
        large_step_depth(params.seed, global, params.iteration, rng::CONTROL_DEPTH, params.max_depth)
    } else {
        kept
    };
    let depth_of = |i: u32| params.candidate_depth(large && descends_from_level_one(i), || fresh, kept);
    cand_depth[k as usize] = depth_of(j);
    group = j;
    while group < groups {
        // A large step's fresh depth reaches only the candidates that follow level 1.
        if !params.dimensions_used(4 * group, 4, kept) && !params.dimensions_used(4 * group, 4, fresh) {
            group += per_chain;
            continue;
        }
        if per_chain == 1 {
            // The naive chain: level 1 alone, without the tree's array of levels.
            if params.dimensions_used(4 * group, 4, depth_of(0)) {
                let fresh_group = large || params.refreshes_group(group, kept);
                let current = if fresh_group {
                    Vec4::ZERO
                } else {
                    load_group(chain_u, chain, group, params.chains, dims)
                };
                let step = tree_level_step(key, 1, fresh_group, group, &params.mutation);
                store_group(
                    cand_u,
                    k,
                    group,
                    candidates,
                    dims,
                    apply_tree_level_step(current, 1, fresh_group, step),
                );
            }
            group += 1;
            continue;
        }
        let current = load_group(chain_u, chain, group, params.chains, dims);
        let steps = tree_level_steps(key, params.tree_depth, large, group, &params.mutation);
        let mut i = 0;
        while i < per_chain {
            if params.dimensions_used(4 * group, 4, depth_of(i)) {
                let samples = tree_candidate_samples(current, i, large, &steps);
                store_group(cand_u, chain * per_chain + i, group, candidates, dims, samples);
            }
            i += 1;
        }
        group += per_chain;
    }
}
