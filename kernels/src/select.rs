//! The `select` pass (the paper's §5.3): one invocation per chain evaluates the acceptance of its
//! candidates over the targets c = luminance(F) — as a speculative tree of depth d (d = 1: the
//! naive parallel MMLT) or as a reject chain of l proposals — writes one splat per distinct
//! state (F/c times its expected-steps weight, the pixel as bits; zero-weight and invalid
//! states get `NO_PIXEL`), draws the next state and moves the chain there (samples,
//! contribution and path depth).

use shared::acceptance::is_valid_target;
use shared::color::luminance;
use shared::layout::{soa_index, splat_record};
use shared::mmlt::ChainState;
use shared::mutation::is_large_step;
use shared::normalisation::tally_large_step;
use shared::params::{RenderParams, METHOD_REJECT_CHAIN};
use shared::reject_chain::{self, is_reject_large_step, MAX_REJECT_CHAIN, MAX_REJECT_CHAIN_STATES};
use shared::rng::{self, RngKey};
use shared::tree::{self, MAX_TREE_CANDIDATES, MAX_TREE_LEAVES, MAX_TREE_STATES};
use spirv_std::glam::Vec4;

/// What selection decided for one chain.
struct Decision {
    /// 0: stay; s ≥ 1: move to candidate s − 1.
    next: u32,
    /// Expected accepted steps of this iteration.
    accepted: f32,
    /// Expected steps of this iteration (the total splat weight).
    steps: f32,
    /// Candidates with a NaN or infinite target.
    invalid: u32,
}

/// The uniform that draws the next state of chain `p` (keyed by its render-wide index).
fn selection_uniform(params: &RenderParams, p: u32) -> f32 {
    rng::uniform(RngKey {
        seed: params.seed,
        chain: params.global_chain(p),
        iteration: params.iteration,
        dimension: rng::dimension(rng::STREAM_CONTROL, rng::CONTROL_SELECT),
    })
}

fn count_invalid<const N: usize>(c: &[f32; N], from: usize, to: usize) -> u32 {
    let mut n = 0;
    let mut i = from;
    while i < to {
        if !is_valid_target(c[i]) {
            n += 1;
        }
        i += 1;
    }
    n
}

/// The targets c of a chain's `states` distinct states: the current state (`root`) first,
/// then its candidates from `contributions[base..]`.
fn targets<const N: usize>(root: Vec4, contributions: &[Vec4], base: u32, states: u32) -> [f32; N] {
    let mut c = [0.0f32; N];
    c[0] = luminance(root.truncate());
    let mut s = 1u32;
    while s < states {
        c[s as usize] = luminance(contributions[(base + s - 1) as usize].truncate());
        s += 1;
    }
    c
}

/// The splat records of chain `p`'s `states` distinct states: the current state (`root`) and
/// its candidates (`contributions[base..]`), with targets `c` and expected-steps weights
/// `weight`.
fn write_splats<const N: usize>(
    p: u32,
    states: u32,
    root: Vec4,
    (contributions, base): (&[Vec4], u32),
    c: &[f32; N],
    weight: &[f32; N],
    splats: &mut [Vec4],
) {
    let mut s = 0;
    while s < states {
        let v = if s == 0 { root } else { contributions[(base + s - 1) as usize] };
        splats[(p * states + s) as usize] = splat_record(v, c[s as usize], weight[s as usize]);
        s += 1;
    }
}

/// The speculative tree: Eq. 2 leaf probabilities, generalised Eq. 3 weights, over private
/// arrays sized for the tree's depth (`shared::tree`'s array sizes).
fn select_tree(
    p: u32,
    params: &RenderParams,
    root: Vec4,
    contributions: &[Vec4],
    splats: &mut [Vec4],
) -> Decision {
    match params.tree_depth {
        1 => select_tree_sized::<2, 1, 2>(p, params, root, contributions, splats),
        2 | 3 => select_tree_sized::<8, 7, 8>(p, params, root, contributions, splats),
        4 | 5 => select_tree_sized::<32, 31, 32>(p, params, root, contributions, splats),
        _ => select_tree_sized::<MAX_TREE_STATES, MAX_TREE_CANDIDATES, MAX_TREE_LEAVES>(
            p,
            params,
            root,
            contributions,
            splats,
        ),
    }
}

/// [`select_tree`] with arrays of S states, C candidates and L leaves (enough for its depth).
fn select_tree_sized<const S: usize, const C: usize, const L: usize>(
    p: u32,
    params: &RenderParams,
    root: Vec4,
    contributions: &[Vec4],
    splats: &mut [Vec4],
) -> Decision {
    let d = params.tree_depth;
    let states = params.states_per_chain();
    let base = p * (states - 1);
    let c: [f32; S] = targets(root, contributions, base, states);
    let mut accept = [0.0f32; C];
    let mut leaf = [0.0f32; L];
    let mut weight = [0.0f32; S];
    tree::evaluate_tree(d, &c, &mut accept, &mut leaf, &mut weight);
    write_splats(p, states, root, (contributions, base), &c, &weight, splats);
    Decision {
        next: tree::select_next_state(d, &leaf, selection_uniform(params, p)),
        accepted: tree::expected_acceptances(d, &leaf),
        steps: d as f32,
        invalid: count_invalid(&c, 1, states as usize),
    }
}

/// The reject chain: next-state probabilities R_i·a_i, expected-steps weights, over private
/// arrays sized for its length.
fn select_reject_chain(
    p: u32,
    params: &RenderParams,
    root: Vec4,
    contributions: &[Vec4],
    splats: &mut [Vec4],
) -> Decision {
    match params.reject_length {
        0..=4 => select_reject_chain_sized::<5, 4>(p, params, root, contributions, splats),
        5..=16 => select_reject_chain_sized::<17, 16>(p, params, root, contributions, splats),
        _ => select_reject_chain_sized::<MAX_REJECT_CHAIN_STATES, { MAX_REJECT_CHAIN as usize }>(
            p,
            params,
            root,
            contributions,
            splats,
        ),
    }
}

/// [`select_reject_chain`] with arrays of S states and C proposals (enough for its length).
fn select_reject_chain_sized<const S: usize, const C: usize>(
    p: u32,
    params: &RenderParams,
    root: Vec4,
    contributions: &[Vec4],
    splats: &mut [Vec4],
) -> Decision {
    let l = params.reject_length;
    let states = l + 1;
    let base = p * l;
    let c: [f32; S] = targets(root, contributions, base, states);
    let mut accept = [0.0f32; C];
    let mut next = [0.0f32; S];
    let mut weight = [0.0f32; S];
    let steps = reject_chain::evaluate_reject_chain(l, &c, &mut accept, &mut next, &mut weight);
    write_splats(p, states, root, (contributions, base), &c, &weight, splats);
    Decision {
        next: reject_chain::select_next_state(l, &next, selection_uniform(params, p)),
        // The chain moves (accepts once) with probability 1 − R_{l+1}.
        accepted: 1.0 - next[0],
        steps,
        invalid: count_invalid(&c, 1, states as usize),
    }
}

/// Tallies the targets of chain `p`'s large-step candidates of this iteration, independent
/// samples of the normalisation's distribution (`shared::normalisation`): a tree's level-1
/// candidate when the iteration is a large step, a reject chain's large-step proposals.
fn tally_large_steps(p: u32, params: &RenderParams, contributions: &[Vec4], state: &mut ChainState) {
    let global = params.global_chain(p);
    let per = params.candidates_per_chain();
    let base = p * per;
    if params.method == METHOD_REJECT_CHAIN {
        let mut j = 0;
        while j < per {
            if is_reject_large_step(params.seed, global, params.iteration, j, params.mutation.p_large) {
                tally_large_step(state, luminance(contributions[(base + j) as usize].truncate()));
            }
            j += 1;
        }
    } else if is_large_step(params.seed, global, params.iteration, params.mutation.p_large) {
        tally_large_step(state, luminance(contributions[base as usize].truncate()));
    }
}

stage! {
    /// What `select` binds.
    pub struct SelectIo<'a> {
        0 params: uniform RenderParams,
        /// The chains' states, moved on.
        1 chains: write ChainState,
        /// The chains' samples, SoA (`p + i·N`), moved on.
        2 chain_u: write f32,
        3 cand_u: read f32,
        4 cand_depth: read u32,
        5 contributions: read Vec4,
        /// One record per distinct state of each chain.
        6 splats: write Vec4,
    }
    entry "select_cs" (threads 64) => select;
    bound;
}

/// The kernel body for chain `p`.
pub fn select(p: usize, io: SelectIo) {
    let SelectIo { params, chains, chain_u, cand_u, cand_depth, contributions, splats } = io;
    let p = p as u32;
    if p >= params.chains {
        return;
    }
    let mut state = chains[p as usize];
    let root = Vec4::from_array(state.contribution);
    let decision = if params.method == METHOD_REJECT_CHAIN {
        select_reject_chain(p, params, root, contributions, splats)
    } else {
        select_tree(p, params, root, contributions, splats)
    };
    if decision.next > 0 {
        let cand = p * params.candidates_per_chain() + decision.next - 1;
        let mut dim = 0;
        while dim < params.dims {
            chain_u[soa_index(p, dim, params.chains)] = cand_u[soa_index(cand, dim, params.candidates)];
            dim += 1;
        }
        state.contribution = contributions[cand as usize].to_array();
        state.depth = cand_depth[cand as usize];
    }
    tally_large_steps(p, params, contributions, &mut state);
    state.accepted += decision.accepted;
    state.steps += decision.steps;
    state.invalid += decision.invalid;
    chains[p as usize] = state;
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;
    use shared::layout::{pack_contribution, unpack_contribution, NO_PIXEL};
    use shared::params::{METHOD_REJECT_CHAIN, METHOD_TREE};
    use spirv_std::glam::Vec3;

    fn params(method: u32, per_chain: u32) -> RenderParams {
        RenderParams {
            chains: 1,
            candidates: per_chain,
            dims: 2,
            tree_depth: if method == METHOD_TREE { per_chain.trailing_ones() } else { 1 },
            method,
            reject_length: if method == METHOD_REJECT_CHAIN { per_chain } else { 0 },
            iteration: 3,
            seed: 9,
            ..Default::default()
        }
    }

    fn run(p: &RenderParams, root: Vec4, cands: &[Vec4]) -> (ChainState, Vec<Vec4>, Vec<f32>) {
        let mut chains = [ChainState { contribution: root.to_array(), depth: 2, ..Default::default() }];
        let mut chain_u = vec![0.25f32; 2];
        let cand_u: Vec<f32> = (0..cands.len() * 2).map(|i| 0.5 + i as f32 * 0.01).collect();
        let cand_depth = vec![4u32; cands.len()];
        let mut splats = vec![Vec4::ZERO; cands.len() + 1];
        let io = SelectIo {
            params: p,
            chains: &mut chains,
            chain_u: &mut chain_u,
            cand_u: &cand_u,
            cand_depth: &cand_depth,
            contributions: cands,
            splats: &mut splats,
        };
        select(0, io);
        (chains[0], splats, chain_u)
    }

    fn px(rgb: f32, pixel: u32) -> Vec4 {
        pack_contribution(Vec3::splat(rgb), 1.0, pixel)
    }

    /// NaN and ±Inf contributions are rejected, counted, and never splatted, by trees and
    /// reject chains alike; the chain never moves to them.
    #[test]
    fn invalid_contributions_are_counted_and_never_splatted() {
        let bad = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY];
        for (method, per) in [(METHOD_TREE, 1), (METHOD_TREE, 3), (METHOD_REJECT_CHAIN, 4)] {
            for b in bad {
                let mut cands: Vec<Vec4> = (0..per).map(|i| px(0.5, 10 + i)).collect();
                cands[0] = pack_contribution(Vec3::new(b, 1.0, 1.0), 1.0, 10);
                let (state, splats, _) = run(&params(method, per), px(1.0, 5), &cands);
                assert_eq!(state.invalid, 1, "method {method}/{per}: {b}");
                let (rgb, pixel) = unpack_contribution(splats[1]);
                assert_eq!(pixel, NO_PIXEL, "the invalid candidate is not splatted");
                assert_eq!(rgb, Vec3::ZERO);
                assert!(
                    splats.iter().all(|s| s.truncate().is_finite()),
                    "rgb of every record is finite (w holds pixel bits)"
                );
                assert!(Vec4::from_array(state.contribution).is_finite(), "the chain never moves to it");
            }
        }
    }

    /// A chain whose current state has c(x) = 0 accepts any valid proposal (a = 1).
    #[test]
    fn a_chain_started_at_zero_moves_to_a_valid_proposal() {
        let (state, splats, chain_u) = run(&params(METHOD_TREE, 1), px(0.0, 5), &[px(0.5, 7)]);
        assert_eq!(Vec4::from_array(state.contribution), px(0.5, 7));
        assert_eq!(state.depth, 4, "the candidate's depth moves with it");
        assert_eq!(chain_u, vec![0.5, 0.51]);
        assert_eq!(unpack_contribution(splats[0]).1, NO_PIXEL, "the zero state splats nothing");
        assert_eq!(unpack_contribution(splats[1]).1, 7);
        assert!((state.accepted - 1.0).abs() < 1e-6 && state.steps == 1.0);
    }
}
