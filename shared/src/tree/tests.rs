use super::*;
use crate::rng::{uniform, RngKey};

fn rand(seed: u32, i: u32, j: u32) -> f32 {
    uniform(RngKey { seed, chain: i, iteration: j, dimension: 0 })
}

/// The reference: walk every one of the 2^d decision sequences of the d-step chain explicitly,
/// in f64, taking the acceptance of each step from `edge(level, history, source_state)`.
/// Returns (leaf probabilities, expected steps spent in each distinct state).
fn enumerate(depth: u32, edge: impl Fn(u32, u32, u32) -> f64) -> (Vec<f64>, Vec<f64>) {
    let leaves = 1usize << depth;
    let mut leaf_p = vec![0.0; leaves];
    let mut time = vec![0.0; leaves];
    for leaf in 0..leaves as u32 {
        let mut state = 0u32; // root
        let mut p = 1.0f64;
        let mut visits = Vec::new();
        for level in 1..=depth {
            let history = leaf >> (depth - level + 1); // decisions before this level
            let decision = (leaf >> (depth - level)) & 1;
            let k = (1u32 << (level - 1)) - 1 + history;
            let a = edge(level, history, state);
            p *= if decision == 1 { a } else { 1.0 - a };
            if decision == 1 {
                state = 1 + k;
            }
            visits.push(state);
        }
        leaf_p[leaf as usize] = p;
        // The probability of a prefix is the sum over the leaves that extend it, so spreading
        // each leaf's probability over the states it visits gives the expected visit counts.
        for s in visits {
            time[s as usize] += p;
        }
    }
    (leaf_p, time)
}

fn run(depth: u32, accept: &[f32; MAX_TREE_CANDIDATES]) -> ([f32; MAX_TREE_LEAVES], [f32; MAX_TREE_STATES]) {
    let mut p = [0.0; MAX_TREE_LEAVES];
    let mut w = [0.0; MAX_TREE_STATES];
    tree_probabilities_and_weights(depth, accept, &mut p, &mut w);
    (p, w)
}

#[test]
fn numbering_round_trips() {
    for k in 0..MAX_TREE_CANDIDATES as u32 {
        let level = candidate_level(k);
        let h = candidate_history(k);
        assert!(h < 1 << (level - 1));
        assert_eq!(candidate_index(level, h), k);
    }
    assert_eq!(candidate_level(0), 1);
    assert_eq!(candidate_level(1), 2);
    assert_eq!(candidate_level(2), 2);
    assert_eq!(candidate_level(3), 3);
    assert_eq!(candidate_count(1), 1);
    assert_eq!(candidate_count(8), 255);
    // d = 2: histories "0x" stay at the root or move to candidate 1; "1x" start at candidate 0.
    assert_eq!(state_after(2, 0b00), 0);
    assert_eq!(state_after(2, 0b01), 2);
    assert_eq!(state_after(2, 0b10), 1);
    assert_eq!(state_after(2, 0b11), 3);
    assert_eq!(state_after(1, 1), 1);
    assert_eq!(state_after(3, 0b100), 1, "accept, reject, reject stays at candidate 0");
}

/// Leaf probabilities and weights equal a brute-force enumeration of the d-step chain, for
/// every depth and random acceptances (including exact 0 and 1 edges).
#[test]
fn forward_pass_equals_brute_force_enumeration() {
    for depth in 1..=MAX_TREE_DEPTH {
        for trial in 0..20u32 {
            let mut accept = [0.0f32; MAX_TREE_CANDIDATES];
            for (k, a) in accept.iter_mut().enumerate() {
                let r = rand(depth * 100 + trial, k as u32, 1);
                *a = match trial % 4 {
                    0 => r,
                    1 => (r * 3.0).floor() / 2.0, // 0, 0.5 or 1
                    2 => r * r * r,               // mostly small
                    _ => 1.0 - r * r * r,         // mostly near 1
                };
            }
            let (p, w) = run(depth, &accept);
            let (ref_p, ref_w) =
                enumerate(depth, |level, history, _| accept[candidate_index(level, history) as usize] as f64);
            for leaf in 0..1usize << depth {
                assert!(
                    (p[leaf] as f64 - ref_p[leaf]).abs() < 1e-6,
                    "d={depth} leaf {leaf}: {} vs {}",
                    p[leaf],
                    ref_p[leaf]
                );
            }
            for s in 0..1usize << depth {
                assert!(
                    (w[s] as f64 - ref_w[s]).abs() < 1e-5,
                    "d={depth} state {s}: {} vs {}",
                    w[s],
                    ref_w[s]
                );
            }
        }
    }
}

/// End to end from targets: the edge acceptances come from `a(y|x)` with the source being the
/// state the chain is in, which the enumeration tracks itself. Targets include zeros and NaN.
#[test]
fn acceptances_from_targets_follow_the_chain() {
    for depth in 1..=MAX_TREE_DEPTH {
        let mut c = [0.0f32; MAX_TREE_STATES];
        for (s, v) in c.iter_mut().enumerate() {
            let r = rand(7 + depth, s as u32, 2);
            *v = if r < 0.1 {
                0.0
            } else if r < 0.15 {
                f32::NAN
            } else {
                r * 10.0
            };
        }
        let mut accept = [0.0; MAX_TREE_CANDIDATES];
        let mut p = [0.0; MAX_TREE_LEAVES];
        let mut w = [0.0; MAX_TREE_STATES];
        evaluate_tree(depth, &c, &mut accept, &mut p, &mut w);
        let (ref_p, ref_w) = enumerate(depth, |level, history, source| {
            acceptance(c[source as usize], c[(1 + candidate_index(level, history)) as usize]) as f64
        });
        for leaf in 0..1usize << depth {
            assert!((p[leaf] as f64 - ref_p[leaf]).abs() < 1e-6);
        }
        for s in 0..1usize << depth {
            assert!((w[s] as f64 - ref_w[s]).abs() < 1e-5);
            assert!(!w[s].is_nan());
            if c[s].is_nan() {
                assert_eq!(w[s], 0.0, "a NaN candidate is never splatted");
            }
        }
    }
}

/// Seed Eq. 2 and Eq. 3 for d = 2, term by term. a1: root → candidate 0; a_1^2: root →
/// candidate 1 (after a rejection); a_2^2: candidate 0 → candidate 2 (after an acceptance).
#[test]
fn depth_two_is_the_papers_equations() {
    for (a1, a12, a22) in [(0.3f32, 0.6f32, 0.9f32), (1.0, 0.0, 0.5), (0.25, 0.75, 0.125)] {
        let mut accept = [0.0; MAX_TREE_CANDIDATES];
        accept[0] = a1;
        accept[1] = a12;
        accept[2] = a22;
        let (p, w) = run(2, &accept);
        let eq2 = [(1.0 - a1) * (1.0 - a12), (1.0 - a1) * a12, a1 * (1.0 - a22), a1 * a22];
        for leaf in 0..4 {
            assert!((p[leaf] - eq2[leaf]).abs() < 1e-7, "Eq. 2 leaf {leaf}");
        }
        // States: 0 = X_{i−1} (root), 1 = X'_i, 2 = X^1_{i+1}, 3 = X^2_{i+1}.
        let eq3 = [(1.0 - a1) * (2.0 - a12), a1 * (2.0 - a22), (1.0 - a1) * a12, a1 * a22];
        for s in 0..4 {
            assert!((w[s] - eq3[s]).abs() < 1e-7, "Eq. 3 state {s}: {} vs {}", w[s], eq3[s]);
        }
    }
}

/// The paper's closing remark on Eq. 3 ("for deeper trees all (1 − a) become (2 − a)") read
/// literally gives the root of a d = 3 tree the weight (1 − a1)(2 − b)(2 − c): with every
/// acceptance 0 that is 4, but a 3-step chain that rejects everything spends 3 steps at the
/// root. The forward pass gives 3, as the enumeration does.
#[test]
fn the_papers_rule_for_deeper_trees_overcounts() {
    let accept = [0.0; MAX_TREE_CANDIDATES];
    let (_, w) = run(3, &accept);
    let (a1, b, c) = (0.0f32, 0.0f32, 0.0f32);
    let seed_rule_root = (1.0 - a1) * (2.0 - b) * (2.0 - c);
    assert_eq!(seed_rule_root, 4.0);
    assert_eq!(w[0], 3.0);
    let (_, ref_w) = enumerate(3, |_, _, _| 0.0);
    assert_eq!(ref_w[0], 3.0);
}

/// Σp = 1 and Σw = d within 1e-5 in f32, for acceptances from {0, 1e-30, 0.5, 1 − 1e-7, 1}
/// (all edges equal, and mixed) and uniformly random ones, at every depth.
#[test]
fn probabilities_sum_to_one_and_weights_to_depth() {
    let edge_values = [0.0f32, 1e-30, 0.5, 1.0 - 1e-7, 1.0];
    for depth in 1..=MAX_TREE_DEPTH {
        let mut cases: Vec<[f32; MAX_TREE_CANDIDATES]> = Vec::new();
        for v in edge_values {
            cases.push([v; MAX_TREE_CANDIDATES]);
        }
        for trial in 0..50u32 {
            let mut mixed = [0.0; MAX_TREE_CANDIDATES];
            let mut random = [0.0; MAX_TREE_CANDIDATES];
            for k in 0..MAX_TREE_CANDIDATES {
                let r = rand(trial, k as u32, depth);
                mixed[k] = edge_values[((r * 5.0) as usize).min(4)];
                random[k] = rand(trial + 1000, k as u32, depth);
            }
            cases.push(mixed);
            cases.push(random);
        }
        for accept in &cases {
            let (p, w) = run(depth, accept);
            let n = 1usize << depth;
            let sp: f32 = p[..n].iter().sum();
            let sw: f32 = w[..n].iter().sum();
            assert!((sp - 1.0).abs() <= 1e-5, "d={depth}: Σp = {sp}");
            assert!((sw - depth as f32).abs() <= 1e-5, "d={depth}: Σw = {sw}");
            assert!(p[..n].iter().chain(&w[..n]).all(|x| x.is_finite() && *x >= 0.0));
        }
    }
}

#[test]
fn the_next_state_is_drawn_from_the_leaves() {
    let depth = 3;
    let mut accept = [0.0; MAX_TREE_CANDIDATES];
    for (k, a) in accept.iter_mut().enumerate().take(7) {
        *a = [0.2, 0.7, 0.4, 0.9, 0.1, 0.5, 0.3][k];
    }
    let (p, _) = run(depth, &accept);
    let mut expected = [0.0f64; 8];
    for leaf in 0..8 {
        expected[state_after(depth, leaf) as usize] += p[leaf as usize] as f64;
    }
    let n = 200_000;
    let mut counts = [0u32; 8];
    for i in 0..n {
        counts[select_next_state(depth, &p, (i as f32 + 0.5) / n as f32) as usize] += 1;
    }
    for s in 0..8 {
        assert!((counts[s] as f64 / n as f64 - expected[s]).abs() < 1e-4, "{counts:?} vs {expected:?}");
    }
}

/// A discrete target on the ring Z_8 with one zero-mass state; symmetric ±1/±2 offsets shared
/// by every candidate of a level (as on the device), large steps only at level 1. A chain
/// advanced by sampling the d = 3 tree must visit states in the target's proportions:
/// chi-squared over the final states of 20 000 independent chains (fixed seed), and the
/// expected-value splats (the weights) must match too.
#[test]
fn a_depth_three_chain_samples_the_target() {
    const K: usize = 8;
    let target = [1.0f32, 2.0, 3.0, 4.0, 0.0, 6.0, 7.0, 8.0];
    let total: f32 = target.iter().sum();
    let depth = 3;
    let chains = 20_000u32;
    let iterations = 30u32;
    let mut finals = [0u32; K];
    let mut splats = [0.0f64; K];
    for chain in 0..chains {
        let mut x = (chain as usize) % K;
        for it in 0..iterations {
            let key = |dim: u32| uniform(RngKey { seed: 99, chain, iteration: it, dimension: dim });
            let large = key(0) < 0.3;
            // One offset per level, shared by the whole level.
            let offsets: Vec<usize> =
                (1..=depth).map(|j| [1usize, 2, K - 1, K - 2][((key(j) * 4.0) as usize).min(3)]).collect();
            let fresh = ((key(10) * K as f32) as usize).min(K - 1);
            let mut value = [0usize; MAX_TREE_STATES];
            value[0] = x;
            for k in 0..candidate_count(depth) {
                let level = candidate_level(k);
                let source = value[state_after(level - 1, candidate_history(k)) as usize];
                value[(k + 1) as usize] =
                    if level == 1 && large { fresh } else { (source + offsets[level as usize - 1]) % K };
            }
            let mut c = [0.0; MAX_TREE_STATES];
            for s in 0..=candidate_count(depth) as usize {
                c[s] = target[value[s]];
            }
            let mut accept = [0.0; MAX_TREE_CANDIDATES];
            let mut p = [0.0; MAX_TREE_LEAVES];
            let mut w = [0.0; MAX_TREE_STATES];
            evaluate_tree(depth, &c, &mut accept, &mut p, &mut w);
            if it >= 10 {
                for s in 0..=candidate_count(depth) as usize {
                    splats[value[s]] += w[s] as f64;
                }
            }
            x = value[select_next_state(depth, &p, key(11)) as usize];
        }
        finals[x] += 1;
    }
    assert_eq!(finals[4], 0, "the zero-mass state is never the chain's state at the end");
    assert_eq!(splats[4], 0.0, "the zero-mass state is never splatted");
    let mut chi2 = 0.0;
    for s in 0..K {
        if target[s] > 0.0 {
            let expected = chains as f64 * (target[s] / total) as f64;
            chi2 += (finals[s] as f64 - expected).powi(2) / expected;
        }
    }
    // 6 degrees of freedom: the 99.9 % quantile is 22.46.
    assert!(chi2 < 22.46, "chi2 = {chi2}, finals = {finals:?}");
    let splat_total: f64 = splats.iter().sum();
    for s in 0..K {
        let share = splats[s] / splat_total;
        let expected = (target[s] / total) as f64;
        assert!((share - expected).abs() < 0.01, "state {s}: {share} vs {expected}");
    }
}

/// The expected acceptances of the tree equal the brute-force chain's: Σ over decision
/// sequences of their probability times their number of acceptances.
#[test]
fn expected_acceptances_match_enumeration() {
    for depth in 1..=MAX_TREE_DEPTH {
        let mut accept = [0.0f32; MAX_TREE_CANDIDATES];
        for (k, a) in accept.iter_mut().enumerate() {
            *a = rand(depth, k as u32, 7);
        }
        let (p, _) = run(depth, &accept);
        let (ref_p, _) =
            enumerate(depth, |level, history, _| accept[candidate_index(level, history) as usize] as f64);
        let expected: f64 =
            ref_p.iter().enumerate().map(|(leaf, q)| q * (leaf as u32).count_ones() as f64).sum();
        let got = expected_acceptances(depth, &p) as f64;
        assert!((got - expected).abs() < 1e-5 * depth as f64, "d={depth}: {got} vs {expected}");
    }
}
