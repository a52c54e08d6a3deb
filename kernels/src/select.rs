//! The `select` pass (seed §5.3): one invocation per chain evaluates its speculative tree of
//! depth d (d = 1: the naive parallel MMLT) over the targets c = luminance(F) of the current
//! state and its candidates, writes one splat per distinct state (F/c times its expected-steps
//! weight, the pixel as bits; zero-weight and invalid states get `NO_PIXEL`), draws the next
//! state from the leaf probabilities and moves the chain there.

use shared::acceptance::is_valid_target;
use shared::layout::{pack_contribution, soa_index, unpack_contribution, NO_PIXEL};
use shared::mmlt::{luminance, ChainState, RenderParams};
use shared::rng::{self, RngKey};
use shared::tree::{self, candidate_count, MAX_TREE_CANDIDATES, MAX_TREE_LEAVES, MAX_TREE_STATES};
use spirv_std::glam::{UVec3, Vec3, Vec4};
use spirv_std::spirv;

/// The kernel body for chain `p`.
pub fn select(
    p: usize,
    params: &RenderParams,
    chains: &mut [ChainState],
    chain_u: &mut [f32],
    cand_u: &[f32],
    contributions: &[Vec4],
    splats: &mut [Vec4],
) {
    let p = p as u32;
    if p >= params.chains {
        return;
    }
    let d = params.tree_depth;
    let per_chain = candidate_count(d);
    let states = per_chain + 1;
    let base = p * per_chain;
    let mut state = chains[p as usize];
    let root = Vec4::from_array(state.contribution);
    let mut c = [0.0f32; MAX_TREE_STATES];
    c[0] = luminance(root.truncate());
    let mut invalid = 0u32;
    let mut k = 0u32;
    while k < per_chain {
        let v = contributions[(base + k) as usize];
        let ck = luminance(v.truncate());
        if !is_valid_target(ck) {
            invalid += 1;
        }
        c[(k + 1) as usize] = ck;
        k += 1;
    }
    let mut accept = [0.0f32; MAX_TREE_CANDIDATES];
    let mut leaf = [0.0f32; MAX_TREE_LEAVES];
    let mut weight = [0.0f32; MAX_TREE_STATES];
    tree::evaluate_tree(d, &c, &mut accept, &mut leaf, &mut weight);
    let mut s = 0u32;
    let mut expected_accepts = 0.0f32;
    while s < states {
        let v = if s == 0 { root } else { contributions[(base + s - 1) as usize] };
        let (rgb, pixel) = unpack_contribution(v);
        let w = weight[s as usize];
        let cs = c[s as usize];
        // F/c is bounded (each channel ≤ 1/0.0722 for non-negative F), unlike w/c, which
        // overflows for a denormal c; so divide first.
        let value = (rgb / cs) * w;
        let finite = is_valid_target(value.x) && is_valid_target(value.y) && is_valid_target(value.z);
        let splat = if w > 0.0 && cs > 0.0 && is_valid_target(cs) && finite {
            pack_contribution(value, 1.0, pixel)
        } else {
            pack_contribution(Vec3::ZERO, 0.0, NO_PIXEL)
        };
        splats[(p * states + s) as usize] = splat;
        // Leaves with more acceptances in their history: Σ popcount(leaf) · P(leaf).
        let mut bits = s;
        let mut ones = 0u32;
        while bits > 0 {
            ones += bits & 1;
            bits >>= 1;
        }
        expected_accepts += ones as f32 * leaf[s as usize];
        s += 1;
    }
    let key = RngKey {
        seed: params.seed,
        chain: p,
        iteration: params.iteration,
        dimension: rng::dimension(rng::STREAM_CONTROL, rng::CONTROL_SELECT),
    };
    let next = tree::select_next_state(d, &leaf, rng::uniform(key));
    if next > 0 {
        let cand = base + next - 1;
        let mut dim = 0;
        while dim < params.dims {
            chain_u[soa_index(p, dim, params.chains)] = cand_u[soa_index(cand, dim, params.candidates)];
            dim += 1;
        }
        state.contribution = contributions[cand as usize].to_array();
    }
    state.accepted += expected_accepts;
    state.invalid += invalid;
    chains[p as usize] = state;
}

/// Entry point: one invocation per chain.
#[spirv(compute(threads(64), entry_point_name = "select_cs"))]
pub fn select_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] params: &[RenderParams],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] chains: &mut [ChainState],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] chain_u: &mut [f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] cand_u: &[f32],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] contributions: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] splats: &mut [Vec4],
) {
    select(id.x as usize, &params[0], chains, chain_u, cand_u, contributions, splats);
}
