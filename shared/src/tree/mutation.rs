//! The tree's mutations (the paper's §5.1): every candidate of a level carries that level's
//! one draw of Kelemen offsets (`crate::mutation`), and each candidate the offsets of the
//! earlier levels its history accepted, so the candidates of a chain stay close in primary
//! space and their paths coherent.

use glam::Vec4;

use crate::mutation::{small_step_offsets, small_steps, MutationParams};
use crate::rng::{self, RngKey};

use super::{candidate_level, MAX_TREE_DEPTH};

/// Level `lvl`'s mutation of dimensions `4·group .. 4·group + 4` of the chain named by `key`
/// (lane i: dimension 4·group + i), one draw per (chain, iteration, level, dimension) shared by
/// every candidate of the level (the paper's §5.1): the signed small-step offsets — or, for level 1
/// of a large step, the step's fresh values.
#[inline]
pub fn tree_level_step(key: RngKey, lvl: u32, large_step: bool, group: u32, params: &MutationParams) -> Vec4 {
    if lvl == 1 && large_step {
        Vec4::from_array(rng::uniform4(key, rng::STREAM_LARGE_STEP, group))
    } else {
        small_step_offsets(rng::uniform4(key, rng::STREAM_PERTURBATION + lvl, group), group, params)
    }
}

/// Applies level `lvl`'s [`tree_level_step`] `step` to the values `v`: a small step, or the
/// fresh values of level 1 of a large step.
#[inline]
pub fn apply_tree_level_step(v: Vec4, lvl: u32, large_step: bool, step: Vec4) -> Vec4 {
    if lvl == 1 && large_step {
        step
    } else {
        small_steps(v, step)
    }
}

/// Every level's [`tree_level_step`] of a tree of `depth` levels: `steps[lvl]` for levels
/// 1..=`depth`, slots beyond `depth` 0. Drawn once per chain and group of dimensions, not once
/// per candidate that carries them, which keeps a tree's `mutate` as cheap per level as the
/// naive chain's.
#[inline]
pub fn tree_level_steps(
    key: RngKey,
    depth: u32,
    large_step: bool,
    group: u32,
    params: &MutationParams,
) -> [Vec4; (MAX_TREE_DEPTH + 1) as usize] {
    let mut steps = [Vec4::ZERO; (MAX_TREE_DEPTH + 1) as usize];
    let mut lvl = 1u32;
    while lvl <= depth {
        steps[lvl as usize] = tree_level_step(key, lvl, large_step, group, params);
        lvl += 1;
    }
    steps
}

/// Dimensions `4·group .. 4·group + 4` of candidate `j` (breadth-first index, see
/// [`crate::tree`]) of a chain whose current values of them are `current`, given the tree's
/// [`tree_level_steps`] of the group.
///
/// The candidate is the current state with the mutations of the levels it descends through
/// applied in order: the mutation of its own level, and of every earlier level whose proposal
/// was accepted in its history ([`level_applies`]). The candidates of a level share the level's
/// mutation, so they differ only in which offsets they accumulated. Level 1 of a large step
/// replaces the values by the step's fresh ones.
#[inline]
pub fn tree_candidate_samples(
    current: Vec4,
    j: u32,
    large_step: bool,
    steps: &[Vec4; (MAX_TREE_DEPTH + 1) as usize],
) -> Vec4 {
    let level = candidate_level(j);
    let mut v = current;
    let mut lvl = 1u32;
    while lvl <= level {
        if level_applies(j, lvl) {
            v = apply_tree_level_step(v, lvl, large_step, steps[lvl as usize]);
        }
        lvl += 1;
    }
    v
}

/// Whether candidate `j` carries the mutation of level `lvl` (1 ≤ lvl ≤ its level): its own
/// level's, and each earlier level's whose proposal its history accepted.
#[inline]
pub fn level_applies(j: u32, lvl: u32) -> bool {
    let level = candidate_level(j);
    lvl == level || (crate::tree::candidate_history(j) >> (level - 1 - lvl)) & 1 == 1
}

/// Whether tree candidate `j` descends through an accepted level-1 proposal (or is it), so
/// that a level-1 large step's depth applies to it.
#[inline]
pub fn descends_from_level_one(j: u32) -> bool {
    let level = candidate_level(j);
    level == 1 || (crate::tree::candidate_history(j) >> (level - 2)) & 1 == 1
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;
    use crate::mutation::{small_step, small_step_offset_log, wrap_unit};

    fn sample(root: f32, j: u32, large: bool, key: RngKey, dim: u32) -> f32 {
        let p = MutationParams::default();
        let steps = tree_level_steps(key, candidate_level(j), large, dim / 4, &p);
        tree_candidate_samples(Vec4::splat(root), j, large, &steps)[(dim % 4) as usize]
    }

    /// Candidates of one level share the level's offset: for a d = 3 tree, the candidate after
    /// history "accept, reject" is the level-1 candidate moved by exactly the level-3 offset
    /// that the root's level-3 candidate was moved by.
    #[test]
    fn candidates_share_each_levels_offset() {
        let p = MutationParams::default();
        let key = RngKey { seed: 5, chain: 9, iteration: 3, dimension: 0 };
        let root = 0.5f32;
        for dim in [0, 7, 50] {
            let c0 = sample(root, 0, false, key, dim); // level 1
            let c3 = sample(root, 3, false, key, dim); // level 3, history 00
            let c5 = sample(root, 5, false, key, dim); // level 3, history 10
            let c1 = sample(root, 1, false, key, dim); // level 2, history 0
            let off3 = c3 - root;
            assert!((c5 - c0 - off3).abs() < 1e-6, "{c5} {c0} {off3}");
            assert!(off3.abs() <= p.s2 && c1 != root);
            // A large step replaces level 1 only; deeper levels still add their offsets.
            let l0 = sample(root, 0, true, key, dim);
            let l2 = sample(root, 2, true, key, dim); // level 2 after accepting level 1
            let off2 = sample(root, 1, true, key, dim) - root;
            assert!((wrap_unit(l0 + off2) - l2).abs() < 1e-6);
        }
        // Lanes are different dimensions: different offsets.
        assert_ne!(sample(root, 0, false, key, 4), sample(root, 0, false, key, 5));
    }

    /// Each level's slot holds that level's own draw (level 1 of a large step its fresh
    /// values), whatever the tree's depth; candidate 5 (level 3, history 10) carries levels 1
    /// and 3, candidate 4 (history 01) levels 2 and 3, and each candidate is the current value
    /// moved by exactly the levels it carries.
    #[test]
    fn level_steps_are_each_levels_own_draw() {
        let p = MutationParams::default();
        let key = RngKey { seed: 5, chain: 9, iteration: 3, dimension: 0 };
        let carried: Vec<Vec<u32>> =
            (0..7).map(|j| (1..=candidate_level(j)).filter(|&l| level_applies(j, l)).collect()).collect();
        assert_eq!(carried, [vec![1], vec![2], vec![1, 2], vec![3], vec![2, 3], vec![1, 3], vec![1, 2, 3]]);
        for large in [false, true] {
            let steps = tree_level_steps(key, 3, large, 2, &p);
            let deeper = tree_level_steps(key, 5, large, 2, &p);
            for lvl in 1..=3usize {
                let drawn = rng::uniform4(key, rng::STREAM_PERTURBATION + lvl as u32, 2);
                let fresh = rng::uniform4(key, rng::STREAM_LARGE_STEP, 2);
                for lane in 0..4 {
                    let expected = if lvl == 1 && large {
                        fresh[lane]
                    } else {
                        small_step_offset_log(drawn[lane], p.s2, p.log_ratio)
                    };
                    assert_eq!(steps[lvl][lane], expected, "level {lvl} lane {lane}");
                    assert_eq!(deeper[lvl][lane], expected);
                }
            }
            assert!(steps[4..].iter().all(|s| *s == Vec4::ZERO) && deeper[5] != Vec4::ZERO);
            for (j, levels) in carried.iter().enumerate() {
                for lane in 0..4 {
                    let mut v = 0.3f32;
                    for &l in levels {
                        v = if l == 1 && large {
                            steps[1][lane]
                        } else {
                            small_step(v, steps[l as usize][lane])
                        };
                    }
                    assert_eq!(tree_candidate_samples(Vec4::splat(0.3), j as u32, large, &steps)[lane], v);
                }
            }
        }
    }

    #[test]
    fn level_one_descendants() {
        // d = 3: candidate 0 is level 1; 2 (history 1), 5 (10) and 6 (11) follow its acceptance.
        let followers: Vec<u32> = (0..7).filter(|&j| descends_from_level_one(j)).collect();
        assert_eq!(followers, vec![0, 2, 5, 6]);
    }
}
