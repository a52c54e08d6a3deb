//! What every dispatch of the Metropolis chains' stages knows ([`RenderParams`]: the multiplexed
//! estimator's and the path estimator's alike), the dispatch modes and methods, and the
//! bootstrap samples' random keys.

use crate::camera::Camera;
use crate::mutation::MutationParams;

use crate::mmlt::sample_dimensions;

/// Mode of a render dispatch: advancing chains.
pub const MODE_CHAINS: u32 = 0;
/// Mode of a render dispatch: bootstrap (fresh samples; the multiplexed estimator's depth =
/// sample index mod (k_max + 1), the path estimator's k_max).
pub const MODE_BOOTSTRAP: u32 = 1;
/// Iteration word of the random keys of bootstrap samples.
pub const BOOTSTRAP_ITERATION: u32 = u32::MAX;

/// Dimension `dim` of bootstrap sample `sample`: a fresh uniform (the host regenerates the
/// chosen samples' vectors with this same function to start the chains).
#[inline]
pub fn bootstrap_sample(seed: u32, sample: u32, dim: u32) -> f32 {
    crate::rng::uniform_dim(bootstrap_key(seed, sample), crate::rng::STREAM_LARGE_STEP, dim)
}

/// The random key of bootstrap sample `sample`.
#[inline]
pub fn bootstrap_key(seed: u32, sample: u32) -> crate::rng::RngKey {
    crate::rng::RngKey { seed, chain: sample, iteration: BOOTSTRAP_ITERATION, dimension: 0 }
}

/// Everything a pass needs to know about the render (uploaded before each dispatch).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct RenderParams {
    #[allow(missing_docs)] // named for what it is
    pub camera: Camera,
    /// Kelemen's s1 and s2 and the large-step probability p_large.
    pub mutation: MutationParams,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Maximum number of bounces (pbrt's maxdepth).
    pub max_depth: u32,
    /// Primary sample dimensions, [`estimator_dimensions`] of the estimator and `max_depth`.
    pub dims: u32,
    /// Number of chains N.
    pub chains: u32,
    /// Number of candidates in this dispatch (N · candidates per chain, or bootstrap samples).
    pub candidates: u32,
    /// Speculative tree depth d (1 = naive parallel MMLT).
    pub tree_depth: u32,
    /// Iterations already run (0 first): the `iteration` word of the chains' random keys.
    pub iteration: u32,
    /// The `seed` word of every random key.
    pub seed: u32,
    /// Entries of the light CDF.
    pub light_count: u32,
    /// [`MODE_CHAINS`] or [`MODE_BOOTSTRAP`].
    pub mode: u32,
    /// Global index of the first bootstrap sample of this dispatch.
    pub sample_offset: u32,
    /// Ray-origin offset, relative to the scene's size.
    pub epsilon: f32,
    /// [`METHOD_TREE`] or [`METHOD_REJECT_CHAIN`].
    pub method: u32,
    /// Reject-chain length l (proposals per chain and iteration).
    pub reject_length: u32,
    /// Global index of this dispatch's chain 0: every random number of a chain is keyed by
    /// `chain_offset + p` (its index in the whole render), so any partition of the chains into
    /// buffers, threads, adapters or machines renders the same chains.
    pub chain_offset: u32,
    /// What a chain's state is a sample of: [`ESTIMATOR_MULTIPLEXED`] or [`ESTIMATOR_PATH`].
    pub estimator: u32,
}

/// The paper's estimator: Multiplexed MLT, one technique of one path depth per sample
/// (`crate::mmlt`).
pub const ESTIMATOR_MULTIPLEXED: u32 = 0;
/// Primary-sample-space MLT over the path tracer: every depth and both of its techniques per
/// sample (`crate::pssmlt`).
pub const ESTIMATOR_PATH: u32 = 1;

/// Primary sample dimensions of a chain of `estimator` over paths of up to `max_depth`
/// bounces.
#[inline]
pub fn estimator_dimensions(estimator: u32, max_depth: u32) -> u32 {
    if estimator == ESTIMATOR_PATH {
        crate::pssmlt::path_dimensions(max_depth)
    } else {
        sample_dimensions(max_depth)
    }
}

/// First of the two image-plane dimensions (the raster position) of a chain of `estimator`:
/// the dimensions [`crate::mutation::MutationParams::image_s2`] applies to.
#[inline]
pub fn estimator_raster_dimension(estimator: u32) -> u32 {
    if estimator == ESTIMATOR_PATH {
        crate::pssmlt::PATH_DIM_RASTER
    } else {
        crate::mmlt::DIM_RASTER
    }
}

/// How many path depths one chain state spans, the factor of b = depths · E[c] over uniform
/// states (`crate::normalisation`): the multiplexed state (u, depth) one of max_depth + 1,
/// the path estimator's u every depth at once (1).
#[inline]
pub fn state_depths(estimator: u32, max_depth: u32) -> u32 {
    if estimator == ESTIMATOR_PATH {
        1
    } else {
        max_depth + 1
    }
}

/// Chains evaluate a speculative tree of depth `tree_depth` (1: the naive method).
pub const METHOD_TREE: u32 = 0;
/// Chains evaluate a reject chain of `reject_length` proposals.
pub const METHOD_REJECT_CHAIN: u32 = 1;

/// Candidates a chain traces per iteration: the speculative tree's 2^d − 1 (`METHOD_TREE`,
/// depth d = `tree_depth`) or the reject chain's l proposals (`METHOD_REJECT_CHAIN`, l =
/// `reject_length`).
#[inline]
pub fn candidates_per_chain(method: u32, tree_depth: u32, reject_length: u32) -> u32 {
    if method == METHOD_REJECT_CHAIN {
        reject_length
    } else {
        crate::tree::candidate_count(tree_depth)
    }
}

impl RenderParams {
    /// Candidates traced per chain and iteration: 2^d − 1 or l.
    #[inline]
    pub fn candidates_per_chain(&self) -> u32 {
        candidates_per_chain(self.method, self.tree_depth, self.reject_length)
    }

    /// The render-wide index of this dispatch's chain `p` (what its random numbers are keyed by).
    #[inline]
    pub fn global_chain(&self, p: u32) -> u32 {
        self.chain_offset + p
    }

    /// Whether candidates of path depth `depth` read any of dimensions `first .. first +
    /// count` (the multiplexed estimator's [`crate::mmlt::dimensions_used`]; the path estimator's
    /// paths may read them all).
    #[inline]
    pub fn dimensions_used(&self, first: u32, count: u32, depth: u32) -> bool {
        self.estimator == ESTIMATOR_PATH || crate::mmlt::dimensions_used(first, count, depth, self.max_depth)
    }

    /// Whether a small step gives dimensions `4·group .. 4·group + 4` of a chain at `depth`
    /// fresh uniforms (the large step's of the same key, which a small step leaves unused)
    /// instead of perturbing them: the path estimator's groups that its state's path never
    /// read (its depth counts the vertices it read, `crate::pssmlt::path_group_read`), for the
    /// naive chain and the reject chain. The target does not depend on unread uniforms, so
    /// on paths (the read uniforms) the proposal is still symmetric — perturb what x read,
    /// draw afresh what it did not — and a small step costs only the dimensions its path
    /// used. The speculative tree's levels share offsets and perturb every dimension.
    #[inline]
    pub fn refreshes_group(&self, group: u32, depth: u32) -> bool {
        self.estimator == ESTIMATOR_PATH && !crate::pssmlt::path_group_read(group, depth)
    }

    /// The depth of a candidate whose proposal is `large` (a large step or a bootstrap sample,
    /// which draws a fresh depth with `fresh_depth`, only then) or a small step (which keeps its
    /// chain's `kept`): the path estimator's chains all span every depth, so `mutate` gives its
    /// candidates max_depth, which `connect` replaces by the vertices each path read.
    #[inline]
    pub fn candidate_depth(&self, large: bool, fresh_depth: impl FnOnce() -> u32, kept: u32) -> u32 {
        if self.estimator == ESTIMATOR_PATH {
            self.max_depth
        } else if large {
            fresh_depth()
        } else {
            kept
        }
    }

    /// Distinct states (splat records) per chain: the current state and every candidate.
    #[inline]
    pub fn states_per_chain(&self) -> u32 {
        self.candidates_per_chain() + 1
    }
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    /// Only the path estimator refreshes, and only the groups its state's path did not read: a
    /// state that read two vertices (dimensions 0..14) keeps groups 0..=3 and refreshes 4..=15; the
    /// multiplexed estimator perturbs every group it uses, whatever its depth.
    #[test]
    fn only_the_path_estimator_refreshes_unread_groups() {
        let path = RenderParams { estimator: ESTIMATOR_PATH, max_depth: 10, ..Default::default() };
        let refreshed: Vec<u32> = (0..16).filter(|&g| path.refreshes_group(g, 2)).collect();
        assert_eq!(refreshed, (4..16).collect::<Vec<u32>>());
        assert!((0..16).all(|g| !path.refreshes_group(g, 10)), "a path of every vertex read them all");
        let multiplexed =
            RenderParams { estimator: ESTIMATOR_MULTIPLEXED, max_depth: 10, ..Default::default() };
        assert!((0..16).all(|g| (0..=10).all(|d| !multiplexed.refreshes_group(g, d))));
    }
}
