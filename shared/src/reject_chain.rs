//! The reject chain of length l (Byrd et al. 2010; the paper's §3.3): l proposals are all made from
//! the current state x and traced at once, then consumed in order until the first acceptance.
//! Each consumed proposal is one ordinary Metropolis–Hastings step (a rejection leaves the
//! chain at x, so the next proposal is still one from x), so the chain stays an exact MH chain
//! that advances a random number of steps per iteration.
//!
//! **States.** 0 is the current state x, i = 1..=l is proposal i.
//!
//! **Probabilities.** Proposal i is consumed with probability `R_i = Π_{k<i} (1 − a_k)`
//! (every earlier one rejected). The next state is proposal i with probability `R_i · a_i`
//! (first acceptance at i) and x with probability `R_{l+1}` (none accepted); they sum to 1.
//!
//! **Weights.** As for the speculative tree, each state is splatted with the expected number of
//! steps the chain spends in it given the l proposals — expected-value splatting of every
//! consumed step, averaged over the acceptance draws: `w(y_i) = R_i · a_i` and
//! `w(x) = Σ_i R_i · (1 − a_i)`. They sum to the expected number of steps consumed,
//! `Σ_i R_i` ∈ [1, l], which varies between iterations, so an image made with reject chains is
//! normalised by the total weight accumulated (not by a fixed steps-per-iteration). For the
//! same reason the state at iteration boundaries is not distributed as the target (an
//! iteration ends at a stopping time, right after an acceptance): only the step-weighted splats
//! are, which is what the renderer accumulates.

use glam::Vec4;

use crate::acceptance::acceptance;
use crate::mutation::{small_step_offsets, small_steps, MutationParams};
use crate::rng::{self, RngKey};

/// Longest reject chain supported.
pub const MAX_REJECT_CHAIN: u32 = 64;
/// Distinct states of the longest chain: the current state and every proposal.
pub const MAX_REJECT_CHAIN_STATES: usize = MAX_REJECT_CHAIN as usize + 1;

/// Evaluates a reject chain of `length` proposals. `c[0]` is the current state's target and
/// `c[i]` proposal i's. Writes `accept[i − 1] = a(y_i | x)`, the probability that each state
/// is the next state into `next_probability[..=length]`, and each state's weight into
/// `weight[..=length]`. Returns the expected number of steps consumed (Σ weight). The arrays
/// may have any length that holds `length` (`MAX_REJECT_CHAIN_STATES` and
/// `MAX_REJECT_CHAIN` for any).
#[inline]
pub fn evaluate_reject_chain<const S: usize, const C: usize>(
    length: u32,
    c: &[f32; S],
    accept: &mut [f32; C],
    next_probability: &mut [f32; S],
    weight: &mut [f32; S],
) -> f32 {
    let mut reach = 1.0f32; // R_i: probability that proposal i is consumed
    let mut steps = 0.0f32;
    let mut stay = 0.0f32;
    let mut i = 1u32;
    while i <= length {
        let a = acceptance(c[0], c[i as usize]);
        accept[(i - 1) as usize] = a;
        let moved = reach * a;
        next_probability[i as usize] = moved;
        weight[i as usize] = moved;
        stay += reach * (1.0 - a);
        steps += reach;
        reach *= 1.0 - a;
        i += 1;
    }
    next_probability[0] = reach;
    weight[0] = stay;
    steps
}

/// Draws the next state for `xi` ∈ [0, 1) from the probabilities of
/// [`evaluate_reject_chain`]: 0 = stays at x, i = proposal i.
#[inline]
pub fn select_next_state<const S: usize>(length: u32, next_probability: &[f32; S], xi: f32) -> u32 {
    crate::discrete::sample_discrete(next_probability, length + 1, xi)
}

/// The reject chain's mutations: each proposal is its own Kelemen mutation of the current
/// state, a large step with probability p_large.
/// Whether reject-chain proposal `i` (0-based) of `chain` at `iteration` is a large step:
/// each proposal is an independent Kelemen mutation of the current state.
#[inline]
pub fn is_reject_large_step(seed: u32, chain: u32, iteration: u32, i: u32, p_large: f32) -> bool {
    let key = RngKey {
        seed,
        chain,
        iteration,
        dimension: rng::dimension(rng::STREAM_CONTROL, rng::CONTROL_REJECT_LARGE_STEP + i),
    };
    rng::uniform(key) < p_large
}

/// Dimensions `4·group .. 4·group + 4` of reject-chain proposal `i` of the chain named by
/// `key`, whose current values are `current`: a fresh uniform for a large step, else a small
/// step by the proposal's own offset.
#[inline]
pub fn reject_chain_samples(
    current: Vec4,
    i: u32,
    large_step: bool,
    key: RngKey,
    group: u32,
    params: &MutationParams,
) -> Vec4 {
    if large_step {
        return Vec4::from_array(rng::uniform4(key, rng::STREAM_REJECT_LARGE_STEP + i, group));
    }
    small_steps(
        current,
        small_step_offsets(rng::uniform4(key, rng::STREAM_REJECT_PERTURBATION + i, group), group, params),
    )
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;
    use crate::rng::{uniform, RngKey};
    use crate::tree;

    fn rand(seed: u32, i: u32, j: u32) -> f32 {
        uniform(RngKey { seed, chain: i, iteration: j, dimension: 1 })
    }

    fn eval(length: u32, c: &[f32; MAX_REJECT_CHAIN_STATES]) -> ([f32; 64], [f32; 65], [f32; 65], f32) {
        let mut a = [0.0; 64];
        let mut p = [0.0; 65];
        let mut w = [0.0; 65];
        let steps = evaluate_reject_chain(length, c, &mut a, &mut p, &mut w);
        (a, p, w, steps)
    }

    /// Reference by enumeration of the l + 1 outcomes of the step-by-step chain, in f64: the
    /// first acceptance at m (m steps consumed: m − 1 spent at x, then one at y_m), or none
    /// (l steps at x). Expected time in each state = Σ over outcomes of P(outcome) · count.
    fn enumerate(a: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let l = a.len();
        let mut next = vec![0.0; l + 1];
        let mut time = vec![0.0; l + 1];
        for m in 1..=l {
            let p: f64 = a[..m - 1].iter().map(|x| 1.0 - x).product::<f64>() * a[m - 1];
            next[m] += p;
            time[0] += p * (m - 1) as f64;
            time[m] += p;
        }
        let none: f64 = a.iter().map(|x| 1.0 - x).product();
        next[0] += none;
        time[0] += none * l as f64;
        (next, time)
    }

    fn random_targets(seed: u32) -> [f32; MAX_REJECT_CHAIN_STATES] {
        let mut c = [0.0; MAX_REJECT_CHAIN_STATES];
        for (i, v) in c.iter_mut().enumerate() {
            let r = rand(seed, i as u32, 0);
            *v = match seed % 3 {
                0 => r * 4.0,
                1 => {
                    if r < 0.2 {
                        0.0
                    } else {
                        r
                    }
                }
                _ => 1.0 + r * 1e-3, // acceptances close to 1
            };
        }
        c
    }

    #[test]
    fn equals_enumeration_of_the_step_by_step_chain() {
        for length in 1..=MAX_REJECT_CHAIN {
            for seed in 0..6 {
                let c = random_targets(seed * 100 + length);
                let (a, p, w, steps) = eval(length, &c);
                let a64: Vec<f64> = a[..length as usize].iter().map(|&x| x as f64).collect();
                let (ref_next, ref_time) = enumerate(&a64);
                for i in 0..=length as usize {
                    assert!((p[i] as f64 - ref_next[i]).abs() < 1e-5, "l={length} i={i}");
                    assert!(
                        (w[i] as f64 - ref_time[i]).abs() < 1e-4,
                        "l={length} i={i}: {} vs {}",
                        w[i],
                        ref_time[i]
                    );
                }
                let sw: f32 = w[..=length as usize].iter().sum();
                assert!((sw - steps).abs() < 1e-4);
                assert!((1.0 - 1e-5..=length as f32 + 1e-4).contains(&steps));
            }
        }
    }

    /// Monte Carlo of the realised chain: draw acceptance uniforms step by step, stop at the
    /// first acceptance, count the steps spent in each state. The averages approach the
    /// weights, and the final states the next-state probabilities.
    #[test]
    fn matches_simulated_consumption() {
        let length = 8;
        let mut c = [0.0; MAX_REJECT_CHAIN_STATES];
        c[0] = 1.0;
        c[1..=length as usize].copy_from_slice(&[0.1, 0.5, 0.05, 2.0, 0.3, 0.0, 0.9, 0.2]);
        let (a, p, w, _) = eval(length, &c);
        let trials = 200_000u32;
        let mut time = [0.0f64; 9];
        let mut next = [0.0f64; 9];
        for t in 0..trials {
            let mut state = 0;
            for i in 1..=length {
                if rand(5, t, i) < a[(i - 1) as usize] {
                    state = i as usize;
                    time[state] += 1.0;
                    break;
                }
                time[0] += 1.0;
            }
            next[state] += 1.0;
        }
        for i in 0..=length as usize {
            assert!((time[i] / trials as f64 - w[i] as f64).abs() < 0.01, "weight {i}");
            assert!((next[i] / trials as f64 - p[i] as f64).abs() < 0.005, "next {i}");
        }
    }

    #[test]
    fn length_one_is_the_depth_one_tree() {
        for seed in 0..20 {
            let c = random_targets(seed);
            let (_, p, w, steps) = eval(1, &c);
            let mut tc = [0.0; tree::MAX_TREE_STATES];
            tc[0] = c[0];
            tc[1] = c[1];
            let mut ta = [0.0; tree::MAX_TREE_CANDIDATES];
            let mut tp = [0.0; tree::MAX_TREE_LEAVES];
            let mut tw = [0.0; tree::MAX_TREE_STATES];
            tree::evaluate_tree(1, &tc, &mut ta, &mut tp, &mut tw);
            assert_eq!([p[0], p[1]], [tp[0], tp[1]]);
            assert_eq!([w[0], w[1]], [tw[0], tw[1]]);
            assert_eq!(steps, 1.0);
        }
    }

    /// Σ next-state probability = 1 within 1e-5, for l up to 64 and acceptances near 0 and 1.
    #[test]
    fn probabilities_sum_to_one_at_the_extremes() {
        for target in [0.0f32, 1e-30, 0.5, 1.0 - 1e-7, 1.0, f32::NAN] {
            let mut c = [target; MAX_REJECT_CHAIN_STATES];
            c[0] = 1.0;
            for length in [1, 2, 8, 63, 64] {
                let (_, p, w, steps) = eval(length, &c);
                let sp: f32 = p[..=length as usize].iter().sum();
                assert!((sp - 1.0).abs() <= 1e-5, "c = {target}, l = {length}: {sp}");
                assert!(w.iter().all(|x| x.is_finite() && *x >= 0.0));
                if target.is_nan() || target == 0.0 {
                    assert_eq!(steps, length as f32, "nothing accepted: all l steps consumed");
                }
            }
        }
    }

    /// The discrete ring target of the tree test, advanced with reject chains of length 4.
    ///
    /// An iteration ends at a stopping time (right after the first acceptance), so the state at
    /// iteration boundaries is *not* distributed as the target: chains end iterations on states
    /// they have just moved to. What is exact is the step-weighted average, i.e. the
    /// expected-value splats normalised by the total weight, which is what the renderer
    /// accumulates. Both facts are checked here.
    #[test]
    fn a_reject_chain_samples_the_target_when_weighted_by_steps() {
        const K: usize = 8;
        let target = [1.0f32, 2.0, 3.0, 4.0, 0.0, 6.0, 7.0, 8.0];
        let total: f32 = target.iter().sum();
        let length = 4u32;
        let chains = 20_000u32;
        let mut finals = [0u32; K];
        let mut splats = [0.0f64; K];
        for chain in 0..chains {
            let mut x = chain as usize % K;
            for it in 0..40u32 {
                let key = |dim: u32| uniform(RngKey { seed: 3, chain, iteration: it, dimension: dim });
                let mut value = [0usize; MAX_REJECT_CHAIN_STATES];
                let mut c = [0.0; MAX_REJECT_CHAIN_STATES];
                value[0] = x;
                c[0] = target[x];
                for i in 1..=length as usize {
                    let u = key(i as u32);
                    value[i] = if u < 0.3 {
                        ((u / 0.3 * K as f32) as usize).min(K - 1)
                    } else {
                        (x + [1, 2, K - 1, K - 2][(((u - 0.3) / 0.7 * 4.0) as usize).min(3)]) % K
                    };
                    c[i] = target[value[i]];
                }
                let (_, p, w, _) = eval(length, &c);
                if it >= 10 {
                    for i in 0..=length as usize {
                        splats[value[i]] += w[i] as f64;
                    }
                }
                x = value[select_next_state(length, &p, key(100)) as usize];
            }
            finals[x] += 1;
        }
        assert_eq!(finals[4], 0);
        assert_eq!(splats[4], 0.0);
        let splat_total: f64 = splats.iter().sum();
        for s in 0..K {
            let share = splats[s] / splat_total;
            let expected = (target[s] / total) as f64;
            assert!((share - expected).abs() < 0.01, "state {s}: {share} vs {expected}");
        }
        let chi2: f64 = (0..K)
            .filter(|&s| target[s] > 0.0)
            .map(|s| {
                let e = chains as f64 * (target[s] / total) as f64;
                (finals[s] as f64 - e).powi(2) / e
            })
            .sum();
        assert!(chi2 > 100.0, "iteration-boundary states unexpectedly unbiased: chi2 = {chi2}");
    }
}
