//! The speculative mutation tree of depth d (the paper's §4): from the current state, the proposal
//! at level j = 1..d is made for every one of the 2^(j−1) histories of accept/reject
//! decisions before it, so one iteration evaluates 2^d − 1 candidates and advances the chain
//! by d Metropolis–Hastings steps.
//!
//! **Numbering.** A history of j decisions is a j-bit number whose most significant bit is the
//! first decision (1 = accept). The candidate proposed at level j after history h (j − 1 bits)
//! has index `k = 2^(j−1) − 1 + h`: candidates are stored breadth-first, level by level. The
//! tree's distinct states are numbered 0 (the root: the current state, not traced again) and
//! `1 + k` for candidate k. After a history, the chain is in the candidate of the last
//! accepted level, or at the root if every decision was a rejection ([`state_after`]).
//!
//! **Leaf probabilities (the paper's Eq. 2).** The probability of a full history of d decisions is the
//! product of `a` or `1 − a` along it; the 2^d leaves sum to 1 and the next state is drawn from
//! them.
//!
//! **Weights (the paper's Eq. 3, generalised).** Every distinct state is splatted with the expected
//! number of the d steps that the chain spends in it, given the tree:
//! `w(s) = Σ_{j=1..d} Σ_{h : state_after(j, h) = s} P(h)`, where P(h) is the probability of the
//! j-decision prefix h. The weights sum to d. For d = 2 this is exactly the paper's Eq. 3.
//! The paper's remark that for deeper trees "all (1 − a) become (2 − a)" does not hold beyond
//! d = 2 (its weights would not sum to d); the forward pass here is checked against a
//! brute-force enumeration of the chain instead (see the tests).
//!
//! **Array sizes.** The functions take arrays of any length that holds a depth-d tree (states
//! and leaves 2^d, candidates 2^d − 1), so a kernel sizes its private arrays for the depth it
//! runs: [`MAX_TREE_STATES`] and the like hold any depth, but zeroing and indexing them per
//! chain costs a naive chain more than its whole selection.

use crate::acceptance::acceptance;

mod mutation;
pub use mutation::*;

/// Deepest tree supported (2^8 − 1 = 255 candidates per chain).
pub const MAX_TREE_DEPTH: u32 = 8;
/// Candidates of the deepest tree.
pub const MAX_TREE_CANDIDATES: usize = (1 << MAX_TREE_DEPTH) - 1;
/// Distinct states of the deepest tree: the root and every candidate.
pub const MAX_TREE_STATES: usize = MAX_TREE_CANDIDATES + 1;
/// Leaves (full histories) of the deepest tree.
pub const MAX_TREE_LEAVES: usize = 1 << MAX_TREE_DEPTH;

/// Number of candidates traced per chain and iteration for a tree of depth `depth`: 2^d − 1.
#[inline]
pub fn candidate_count(depth: u32) -> u32 {
    (1u32 << depth) - 1
}

/// Index of the candidate proposed at `level` (1-based) after the `level − 1` decisions `history`.
#[inline]
pub fn candidate_index(level: u32, history: u32) -> u32 {
    (1u32 << (level - 1)) - 1 + history
}

/// The level (1-based) of candidate `k`.
#[inline]
pub fn candidate_level(k: u32) -> u32 {
    let mut level = 1;
    while k + 1 >= (1u32 << level) {
        level += 1;
    }
    level
}

/// The history (level − 1 decisions) after which candidate `k` is proposed.
#[inline]
pub fn candidate_history(k: u32) -> u32 {
    k + 1 - (1u32 << (candidate_level(k) - 1))
}

/// The distinct state (0 = root, 1 + k = candidate k) the chain is in after the `steps`
/// decisions `history`: the candidate of the last accepted level, or the root.
#[inline]
pub fn state_after(steps: u32, history: u32) -> u32 {
    if history == 0 {
        return 0;
    }
    // The lowest set bit is the last acceptance; it happened at level `steps − zeros`.
    let mut zeros = 0u32;
    while (history >> zeros) & 1 == 0 {
        zeros += 1;
    }
    let level = steps - zeros;
    1 + candidate_index(level, history >> (zeros + 1))
}

/// Acceptance probability of every tree edge: `accept[k]` is `a(candidate k | its source)`,
/// where the source is the state after the history that candidate k follows. `c[s]` is the
/// scalar target of distinct state s (`c[0]` the current state's).
#[inline]
pub fn tree_acceptances<const S: usize, const C: usize>(depth: u32, c: &[f32; S], accept: &mut [f32; C]) {
    let n = candidate_count(depth);
    let mut k = 0u32;
    while k < n {
        let level = candidate_level(k);
        let source = state_after(level - 1, candidate_history(k));
        accept[k as usize] = acceptance(c[source as usize], c[(k + 1) as usize]);
        k += 1;
    }
}

/// From the edge acceptances, the probability of every leaf (the paper's Eq. 2) into
/// `leaf_probability[..2^d]` and the weight of every distinct state (Eq. 3 generalised) into
/// `weight[..2^d]`, by one forward pass over the levels.
#[inline]
pub fn tree_probabilities_and_weights<const S: usize, const C: usize, const L: usize>(
    depth: u32,
    accept: &[f32; C],
    leaf_probability: &mut [f32; L],
    weight: &mut [f32; S],
) {
    let states = 1u32 << depth;
    let mut s = 0u32;
    while s < states {
        weight[s as usize] = 0.0;
        leaf_probability[s as usize] = 0.0;
        s += 1;
    }
    // leaf_probability[h] holds P(h) for the prefixes of the current level; each level
    // splits P(h) into P(2h) (reject) and P(2h + 1) (accept) in place, from the top down so
    // that no prefix is overwritten before it is read.
    leaf_probability[0] = 1.0;
    let mut level = 1u32;
    while level <= depth {
        let prefixes = 1u32 << (level - 1);
        let mut h = prefixes;
        while h > 0 {
            h -= 1;
            let k = candidate_index(level, h);
            let a = accept[k as usize];
            let p = leaf_probability[h as usize];
            let p_accept = p * a;
            let p_reject = p * (1.0 - a);
            leaf_probability[(2 * h + 1) as usize] = p_accept;
            leaf_probability[(2 * h) as usize] = p_reject;
            weight[(k + 1) as usize] += p_accept;
            weight[state_after(level - 1, h) as usize] += p_reject;
        }
        level += 1;
    }
}

/// The whole tree at once: edge acceptances from the targets, leaf probabilities and weights.
#[inline]
pub fn evaluate_tree<const S: usize, const C: usize, const L: usize>(
    depth: u32,
    c: &[f32; S],
    accept: &mut [f32; C],
    leaf_probability: &mut [f32; L],
    weight: &mut [f32; S],
) {
    tree_acceptances(depth, c, accept);
    tree_probabilities_and_weights(depth, accept, leaf_probability, weight);
}

/// Draws the leaf for `xi` ∈ [0, 1) from the leaf probabilities and returns the distinct state
/// the chain moves to (0 = stays at the root, 1 + k = candidate k).
#[inline]
pub fn select_next_state<const L: usize>(depth: u32, leaf_probability: &[f32; L], xi: f32) -> u32 {
    let leaf = crate::discrete::sample_discrete(leaf_probability, 1u32 << depth, xi);
    state_after(depth, leaf)
}

/// Expected number of accepted steps among the tree's d: Σ over leaves of the leaf's
/// probability times its acceptances (leaf h, a history of d decisions, has popcount(h)).
#[inline]
pub fn expected_acceptances<const L: usize>(depth: u32, leaf_probability: &[f32; L]) -> f32 {
    let mut accepted = 0.0f32;
    let mut leaf = 0u32;
    while leaf < 1u32 << depth {
        // popcount by shifting (no bit-count intrinsic needed on the device)
        let mut bits = leaf;
        let mut ones = 0u32;
        while bits > 0 {
            ones += bits & 1;
            bits >>= 1;
        }
        accepted += ones as f32 * leaf_probability[leaf as usize];
        leaf += 1;
    }
    accepted
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests;
