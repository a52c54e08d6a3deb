//! The image normalisation b: the total of the target over the whole sample space,
//! `b = Σ_k ∫ c_k(u) du = (k_max + 1) · E[c]` where (u, depth) is drawn uniformly (Kelemen et
//! al. 2002, §4; pbrt-v3's `MLTIntegrator` bootstrap) — for the multiplexed estimator; the path
//! estimator's state u spans every depth at once and its b is E[c] (`crate::params::state_depths`
//! is the factor). The chains only say how b is spread
//! over the pixels; b sets the image's overall brightness, so its error is in every pixel.
//!
//! Two kinds of samples are independent draws of that same uniform (u, depth):
//! - the **bootstrap** samples, traced once before the chains start (sample i has depth
//!   [`bootstrap_depth`]`(i)`, a stratified uniform depth, and fresh uniform u);
//! - every **large-step candidate** while the chains run: its depth and samples are fresh
//!   uniforms, and whether a proposal is a large step is decided by its own random number
//!   before anything is evaluated (`mutation::is_large_step`, `is_reject_large_step`). In a
//!   speculative tree only the level-1 candidate is a large step; in a reject chain every
//!   proposal may be one.
//!
//! So the pooled mean of their targets is an ever better estimate of E[c]. The `select` pass
//! tallies the large steps' targets per chain ([`tally_large_step`]); the host drains the
//! tallies into [`Moments`] and pools them with the bootstrap's ([`estimate`]). A target that
//! is NaN, infinite or negative counts as zero ([`normalisation_sample`]), as it is never
//! splatted either.

use crate::acceptance::is_valid_target;
use crate::mmlt::ChainState;

/// Path depth of bootstrap sample `sample`: `sample mod (max_depth + 1)`, so the depths of
/// consecutive samples are uniform and stratified.
#[inline]
pub fn bootstrap_depth(sample: u32, max_depth: u32) -> u32 {
    sample % (max_depth + 1)
}

/// The value a target contributes to the estimate of E[c]: itself when it is a valid positive
/// target, otherwise 0 (an invalid candidate is never splatted, so it carries no light).
#[inline]
pub fn normalisation_sample(c: f32) -> f32 {
    if is_valid_target(c) && c > 0.0 {
        c
    } else {
        0.0
    }
}

/// Adds the target `c` of a large-step candidate to the chain's tallies (count, sum, sum of
/// squares since the host last drained them).
#[inline]
pub fn tally_large_step(state: &mut ChainState, c: f32) {
    let x = normalisation_sample(c);
    state.large_count += 1;
    state.large_sum += x;
    state.large_sum_sq += x * x;
}

/// Count, sum and sum of squares of independent samples of c, in f64, with an exact merge.
#[cfg(not(target_arch = "spirv"))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Moments {
    #[allow(missing_docs)] // of the samples: named for what it is
    pub count: u64,
    /// Σ c.
    pub sum: f64,
    /// Σ c².
    pub sum_sq: f64,
}

#[cfg(not(target_arch = "spirv"))]
impl Moments {
    /// Adds one sample (through [`normalisation_sample`]).
    pub fn add(&mut self, c: f32) {
        let x = normalisation_sample(c) as f64;
        self.count += 1;
        self.sum += x;
        self.sum_sq += x * x;
    }

    /// Adds a chain's tallies and clears them.
    pub fn drain(&mut self, state: &mut ChainState) {
        self.count += state.large_count as u64;
        self.sum += state.large_sum as f64;
        self.sum_sq += state.large_sum_sq as f64;
        state.large_count = 0;
        state.large_sum = 0.0;
        state.large_sum_sq = 0.0;
    }

    /// The moments of both sample sets together.
    pub fn merged(self, other: Moments) -> Moments {
        Moments {
            count: self.count + other.count,
            sum: self.sum + other.sum,
            sum_sq: self.sum_sq + other.sum_sq,
        }
    }
}

/// b and its standard error.
#[cfg(not(target_arch = "spirv"))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Estimate {
    /// `depths · mean(c)`.
    pub b: f64,
    /// `depths · sd(c) / √n`, from the samples' spread.
    pub standard_error: f64,
    /// Samples pooled.
    pub samples: u64,
}

#[cfg(not(target_arch = "spirv"))]
impl Estimate {
    /// Standard error relative to b (infinite when b is 0).
    pub fn relative_standard_error(&self) -> f64 {
        if self.b > 0.0 {
            self.standard_error / self.b
        } else {
            f64::INFINITY
        }
    }
}

/// b = depths · mean(c) over `m`, and its standard error from the sample variance; `depths`
/// is how many path depths a chain state spans (`crate::params::state_depths`: max_depth + 1
/// for the multiplexed estimator, 1 for the path estimator).
#[cfg(not(target_arch = "spirv"))]
pub fn estimate(depths: u32, m: &Moments) -> Estimate {
    if m.count == 0 {
        return Estimate::default();
    }
    let n = m.count as f64;
    let mean = m.sum / n;
    let variance = ((m.sum_sq - n * mean * mean) / (n - 1.0).max(1.0)).max(0.0);
    let scale = depths as f64;
    Estimate { b: scale * mean, standard_error: scale * (variance / n).sqrt(), samples: m.count }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_targets_count_as_zero() {
        for c in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -1.0, 0.0] {
            assert_eq!(normalisation_sample(c), 0.0, "{c}");
        }
        assert_eq!(normalisation_sample(0.25), 0.25);
    }

    #[test]
    fn bootstrap_depths_are_stratified() {
        let k = 4;
        let mut counts = [0u32; 5];
        for i in 0..50 {
            counts[bootstrap_depth(i, k) as usize] += 1;
        }
        assert_eq!(counts, [10; 5]);
    }

    /// The estimate equals the textbook mean and standard error, and the device tallies
    /// drained into Moments equal Moments filled directly.
    #[test]
    fn estimate_is_the_scaled_mean_and_its_standard_error() {
        let xs = [0.5f32, 1.5, 2.0, 0.0, 4.0, f32::NAN];
        let mut m = Moments::default();
        let mut state = ChainState::default();
        for &x in &xs {
            m.add(x);
            tally_large_step(&mut state, x);
        }
        let mut drained = Moments::default();
        drained.drain(&mut state);
        assert_eq!(drained, m);
        assert_eq!((state.large_count, state.large_sum, state.large_sum_sq), (0, 0.0, 0.0));
        let v: Vec<f64> = xs.iter().map(|&x| normalisation_sample(x) as f64).collect();
        let n = v.len() as f64;
        let mean = v.iter().sum::<f64>() / n;
        let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let e = estimate(4, &m);
        assert!((e.b - 4.0 * mean).abs() < 1e-12);
        assert!((e.standard_error - 4.0 * (var / n).sqrt()).abs() < 1e-12);
        assert_eq!(e.samples, 6);
    }

    /// Pooling is exact: the merge of two sample sets is the set of all samples, and the
    /// standard error of a mean of iid samples falls as 1/√n.
    #[test]
    fn pooled_standard_error_falls_as_one_over_root_n() {
        let mut state = 0x1234_5678u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        let (mut a, mut b, mut all) = (Moments::default(), Moments::default(), Moments::default());
        for i in 0..400_000 {
            let x = next() * 2.0;
            if i < 100_000 {
                a.add(x);
            } else {
                b.add(x);
            }
            all.add(x);
        }
        let pooled = a.merged(b);
        assert_eq!(pooled.count, all.count);
        assert!((pooled.sum - all.sum).abs() < 1e-6 * all.sum);
        let (ea, ep) = (estimate(1, &a), estimate(1, &pooled));
        let ratio = ea.standard_error / ep.standard_error;
        assert!((ratio - 2.0).abs() < 0.02, "4× the samples: se ratio {ratio}");
        // Uniform on [0, 2): mean 1, sd 2/√12.
        assert!((ep.b - 1.0).abs() < 4.0 * ep.standard_error);
        assert!((ep.standard_error - (4.0f64 / 12.0).sqrt() / 400_000f64.sqrt()).abs() < 1e-5);
    }
}
