//! Kelemen et al., "A simple and robust mutation strategy for the Metropolis light transport
//! algorithm" (2002): mutations of the primary sample vector u ∈ [0,1)^D.
//!
//! - **Small step**, per coordinate: `u' = u ± s2 · exp(−ln(s2/s1) · ξ)`, wrapped into [0, 1).
//!   The offset's magnitude lies in (s1, s2] and is log-uniform there, the sign is a fair coin;
//!   the offset does not depend on u, so the proposal is symmetric. The two image-plane
//!   dimensions have their own s2 (`image_s2`, the same s2/s1), as LuxCore's image mutation
//!   range: a raster step large enough to leave the pixel spreads a chain's splats over more
//!   pixels.
//! - **Large step**: every coordinate a fresh uniform (an independent sample), chosen with
//!   probability `p_large`. In the speculative tree only the level-1 mutation may be large.
//!
//! Because a small step is an offset that does not depend on the state, one draw of offsets
//! per tree level can be applied to every candidate of that level (the paper's §5.1): the candidates
//! of one chain then differ only by the subset of earlier offsets they accumulated, which is
//! what keeps them close in primary space and their paths coherent.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use glam::Vec4;

use crate::rng::{self, RngKey};

/// Parameters of the mutation schedule (uploaded to the device as they are).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize), serde(deny_unknown_fields))]
pub struct MutationParams {
    /// Smallest small-step offset (Kelemen's s1; default 1/1024).
    pub s1: f32,
    /// Largest small-step offset (Kelemen's s2; default 1/64).
    pub s2: f32,
    /// Probability that the level-1 mutation of an iteration is a large step (default 0.3).
    pub p_large: f32,
    /// ln(s2 / s1), precomputed ([`MutationParams::new`]).
    pub log_ratio: f32,
    /// Largest small-step offset of the two image-plane dimensions, as a fraction of the
    /// image (LuxCore's image mutation range); their smallest is `image_s2 · s1 / s2`.
    pub image_s2: f32,
    /// First of the two image-plane dimensions (the estimator's raster position).
    pub image_dimension: u32,
}

impl MutationParams {
    /// The schedule for s1, s2 and p_large.
    pub fn new(s1: f32, s2: f32, p_large: f32) -> Self {
        Self { s1, s2, p_large, log_ratio: (s2 / s1).ln(), image_s2: s2, image_dimension: 0 }
    }
}

impl Default for MutationParams {
    fn default() -> Self {
        Self::new(1.0 / 1024.0, 1.0 / 64.0, 0.3)
    }
}

/// The signed small-step offset for one uniform `xi` ∈ [0, 1): the lower half of [0, 1)
/// gives a positive offset, the upper half a negative one, and the position inside the half
/// (rescaled to [0, 1)) sets the magnitude `s2 · exp(−ln(s2/s1) · ξ')` ∈ (s1, s2].
#[inline]
pub fn small_step_offset(xi: f32, s1: f32, s2: f32) -> f32 {
    small_step_offset_log(xi, s2, (s2 / s1).ln())
}

/// [`small_step_offset`] with ln(s2/s1) given (the device precomputes it once).
#[inline]
pub fn small_step_offset_log(xi: f32, s2: f32, log_ratio: f32) -> f32 {
    let (sign, t) = if xi < 0.5 { (1.0, 2.0 * xi) } else { (-1.0, 2.0 * xi - 1.0) };
    sign * s2 * (-log_ratio * t).exp()
}

/// Wraps `v` ∈ (−1, 2) into [0, 1). A value that rounds to 1.0 after wrapping is the same
/// point of the torus as 0.0 and is returned as 0.0, so the result is never 1.
#[inline]
pub fn wrap_unit(v: f32) -> f32 {
    let w = if v >= 1.0 {
        v - 1.0
    } else if v < 0.0 {
        v + 1.0
    } else {
        v
    };
    if w >= 1.0 || w < 0.0 {
        0.0
    } else {
        w
    }
}

/// One small step of one coordinate: `wrap(u + offset)`.
#[inline]
pub fn small_step(u: f32, offset: f32) -> f32 {
    wrap_unit(u + offset)
}

/// Whether the level-1 mutation of `chain` at `iteration` is a large step.
#[inline]
pub fn is_large_step(seed: u32, chain: u32, iteration: u32, p_large: f32) -> bool {
    let key = RngKey {
        seed,
        chain,
        iteration,
        dimension: rng::dimension(rng::STREAM_CONTROL, rng::CONTROL_LARGE_STEP),
    };
    rng::uniform(key) < p_large
}

/// The largest small-step offset of dimension `dim`: `image_s2` for the two image-plane
/// dimensions, s2 for every other.
#[inline]
pub fn largest_small_step(dim: u32, params: &MutationParams) -> f32 {
    if dim == params.image_dimension || dim == params.image_dimension + 1 {
        params.image_s2
    } else {
        params.s2
    }
}

/// [`small_step_offset_log`] of four uniforms, for dimensions `4·group .. 4·group + 4`, each
/// with its [`largest_small_step`] (and the same ratio s2/s1).
#[inline]
pub fn small_step_offsets(u: [f32; 4], group: u32, params: &MutationParams) -> Vec4 {
    let offset = |x: f32, lane: u32| {
        small_step_offset_log(x, largest_small_step(4 * group + lane, params), params.log_ratio)
    };
    Vec4::new(offset(u[0], 0), offset(u[1], 1), offset(u[2], 2), offset(u[3], 3))
}

/// [`small_step`] of four dimensions.
#[inline]
pub fn small_steps(u: Vec4, offset: Vec4) -> Vec4 {
    Vec4::new(
        small_step(u.x, offset.x),
        small_step(u.y, offset.y),
        small_step(u.z, offset.z),
        small_step(u.w, offset.w),
    )
}

/// The path depth a large step proposes: uniform over 0..=max_depth, drawn with the control
/// uniform `control` of (chain, iteration). With the depth part of the chain's state and
/// proposed uniformly with the fresh samples, the large step stays an independent, symmetric
/// proposal over (u, depth), and every chain samples one target ∝ c(u, depth) whose
/// normalisation is b = (max_depth + 1) · E[c] — so chains that advance different numbers of
/// steps per iteration (reject chains) can share one image normalisation.
#[inline]
pub fn large_step_depth(seed: u32, chain: u32, iteration: u32, control: u32, max_depth: u32) -> u32 {
    let key = RngKey { seed, chain, iteration, dimension: rng::dimension(rng::STREAM_CONTROL, control) };
    ((rng::uniform(key) * (max_depth + 1) as f32) as u32).min(max_depth)
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    #[test]
    fn large_step_depths_are_uniform() {
        let mut counts = [0u32; 4];
        for chain in 0..40_000 {
            counts[large_step_depth(1, chain, 2, rng::CONTROL_DEPTH, 3) as usize] += 1;
        }
        assert!(counts.iter().all(|&c| (c as f64 - 10_000.0).abs() < 500.0), "{counts:?}");
    }

    /// The image-plane dimensions (wherever the estimator puts them) step by up to image_s2,
    /// every other by up to s2, with the same s2/s1; with image_s2 = s2 every dimension steps
    /// as before (the paper's estimator's images are unchanged).
    #[test]
    fn the_image_plane_has_its_own_step() {
        let base = MutationParams::default();
        let u = [0.0, 0.0, 0.0, 0.0]; // ξ = 0: the largest offset, +s2
        for image_dimension in [0, 1, 5] {
            let p = MutationParams { image_s2: 0.25, image_dimension, ..base };
            for group in 0..3 {
                let o = small_step_offsets(u, group, &p);
                for lane in 0..4 {
                    let d = 4 * group + lane;
                    let image = d == image_dimension || d == image_dimension + 1;
                    assert_eq!(o[lane as usize], if image { 0.25 } else { base.s2 }, "dim {d}");
                }
            }
            let same = MutationParams { image_dimension, ..base };
            for i in 0..100 {
                let xi = [i as f32 / 100.0, 0.3, 0.7, 0.99];
                let expected =
                    Vec4::from_array(xi.map(|x| small_step_offset_log(x, base.s2, base.log_ratio)));
                assert_eq!(small_step_offsets(xi, 0, &same), expected);
            }
        }
        // The smallest image offset keeps the ratio: image_s2 · s1 / s2.
        let p = MutationParams { image_s2: 0.25, ..base };
        let smallest = small_step_offsets([0.5 - 1e-7; 4], 0, &p)[0].abs();
        assert!((smallest / (0.25 * base.s1 / base.s2) - 1.0).abs() < 1e-3, "{smallest}");
    }

    #[test]
    fn precomputed_log_ratio_gives_the_same_offsets() {
        let p = MutationParams::default();
        for i in 0..100 {
            let xi = i as f32 / 100.0;
            assert_eq!(small_step_offset(xi, p.s1, p.s2), small_step_offset_log(xi, p.s2, p.log_ratio));
        }
    }

    #[test]
    fn offsets_lie_between_s1_and_s2_with_both_signs() {
        let p = MutationParams::default();
        let (mut pos, mut neg) = (0, 0);
        for i in 0..10_000 {
            let xi = i as f32 / 10_000.0;
            let o = small_step_offset(xi, p.s1, p.s2);
            assert!(o.abs() <= p.s2 * (1.0 + 1e-6), "{o}");
            assert!(o.abs() >= p.s1 * (1.0 - 1e-5), "{o}");
            if o > 0.0 {
                pos += 1
            } else {
                neg += 1
            }
        }
        assert_eq!(pos, 5000);
        assert_eq!(neg, 5000);
        assert_eq!(small_step_offset(0.0, p.s1, p.s2), p.s2);
        assert_eq!(small_step_offset(0.5, p.s1, p.s2), -p.s2);
    }

    /// The magnitude is log-uniform on [s1, s2]: ln|offset| is uniform on [ln s1, ln s2].
    #[test]
    fn magnitude_is_log_uniform() {
        let p = MutationParams::default();
        let n = 100_000;
        let mut bins = [0u32; 10];
        let (ls1, ls2) = (p.s1.ln(), p.s2.ln());
        for i in 0..n {
            let xi =
                crate::rng::uniform(crate::rng::RngKey { seed: 3, chain: i, iteration: 0, dimension: 0 });
            let t = (small_step_offset(xi, p.s1, p.s2).abs().ln() - ls1) / (ls2 - ls1);
            bins[((t * 10.0) as usize).min(9)] += 1;
        }
        for b in bins {
            assert!((b as f64 - 10_000.0).abs() < 5.0 * 100.0, "{bins:?}");
        }
    }

    #[test]
    fn wrap_unit_returns_the_half_open_interval() {
        assert_eq!(wrap_unit(0.25), 0.25);
        assert_eq!(wrap_unit(1.25), 0.25);
        assert_eq!(wrap_unit(-0.25), 0.75);
        assert_eq!(wrap_unit(1.0), 0.0);
        assert_eq!(wrap_unit(0.0), 0.0);
        // -1e-10 + 1 rounds to 1.0 in f32: the same torus point as 0.
        assert_eq!(wrap_unit(-1e-10), 0.0);
        let below_one = 1.0 - f32::EPSILON / 2.0;
        assert_eq!(wrap_unit(below_one), below_one);
    }

    /// A small step followed by the opposite small step returns (within rounding) to the start:
    /// the proposal is symmetric.
    #[test]
    fn small_steps_are_symmetric() {
        let p = MutationParams::default();
        for i in 0..1000 {
            let u = i as f32 / 1000.0;
            let o = small_step_offset((i as f32 * 0.618_034) % 1.0, p.s1, p.s2);
            let back = small_step(small_step(u, o), -o);
            let d = (back - u).abs();
            assert!(d < 1e-6 || (1.0 - d) < 1e-6, "u = {u}, back = {back}");
        }
    }
}
