//! What defines a render: resolution, depth, seed, the [`Integrator`] (the path tracer, or the
//! Metropolis chains with their schedule, estimator and [`ChainSettings`]), the budget, the
//! candidates per iteration, and which part of the chains this process renders
//! (`--shard K/N`). [`Settings`] is also what a part file records of its render
//! (`crate::part`), serialised as it is.

use std::ops::Range;
use std::str::FromStr;

use serde::{Deserialize, Serialize};
use shared::mutation::MutationParams;
use shared::params::{
    estimator_dimensions, estimator_raster_dimension, state_depths, RenderParams, MODE_CHAINS,
};
use shared::path_tracer::PathTracerParams;

use super::{Estimator, Method, Schedule};
use crate::scene::SceneData;

/// Image width when none is given.
pub const DEFAULT_WIDTH: u32 = 256;
/// Maximum bounces when none is given (the paper's ground truth).
pub const DEFAULT_MAX_DEPTH: u32 = 10;
/// Bootstrap samples when none is given.
pub const DEFAULT_BOOTSTRAP: u32 = 65536;
/// The largest small step of the image-plane position when none is given, as a fraction of
/// the image (`MutationParams::image_s2`; every other dimension's is Kelemen's s2 = 1/64).
/// With 1/64 a chain stays in a pixel or two for several steps and a pixel's splats come in
/// clumps; LuxCore's Metropolis sampler moves its image dimensions up to 1/10. Measured at
/// equal time against 1/64: 12–18 % lower relMSE for the path estimator on Sibenik, Sponza,
/// the banner view and `sunblind` (`results/cpu-path/image_step/`), and 1.15–1.76× the
/// efficiency for the multiplexed one on six of seven views (`results/cpu-path/mmlt_target/`).
/// `--image-step 0.015625` restores the paper's schedule.
pub const DEFAULT_IMAGE_STEP: f32 = 1.0 / 16.0;
/// Candidates per pixel when neither `--time` nor `--mutations-per-pixel` is given.
pub const DEFAULT_MUTATIONS_PER_PIXEL: f64 = 64.0;

/// When to stop.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Budget {
    /// Seconds of iterations (after the bootstrap and the kernels' compilation).
    Seconds(f64),
    /// Candidates traced per pixel (pbrt's mutations per pixel), counted over the whole render
    /// (all shards): a shard runs the iterations the unsplit render runs.
    MutationsPerPixel(f64),
}

/// Part `index` (1-based) of `count` equal parts of a render's chains.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shard {
    /// K in 1..=N.
    pub index: u32,
    /// N.
    pub count: u32,
}

impl Shard {
    /// The whole render.
    pub const WHOLE: Shard = Shard { index: 1, count: 1 };

    /// The global chain indices of this part of `chains` chains: contiguous, in order, of
    /// sizes differing by at most one.
    pub fn chains(&self, chains: u32) -> Range<u32> {
        let split = |k: u32| (k as u64 * chains as u64 / self.count as u64) as u32;
        split(self.index - 1)..split(self.index)
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let parsed =
            s.split_once('/').and_then(|(k, n)| Some((k.parse::<u32>().ok()?, n.parse::<u32>().ok()?)));
        match parsed {
            Some((k, n)) if n >= 1 && (1..=n).contains(&k) => Ok(Shard { index: k, count: n }),
            _ => Err(format!("'{s}' is not a shard: use K/N with 1 ≤ K ≤ N, e.g. 2/4")),
        }
    }
}

/// What the Metropolis chains share, whatever their schedule and estimator.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChainSettings {
    /// Bootstrap samples, from which the chains' start states are drawn (at least one per chain
    /// is traced).
    pub bootstrap_samples: u32,
    /// Kelemen's s1 and s2, the large-step probability p_large, and the image step `image_s2`,
    /// the largest small step of the raster position as a fraction of the image (its
    /// `image_dimension` is the estimator's: [`Metropolis::mutation_params`]).
    pub mutation: MutationParams,
    /// Whether the chains' contributions are divided by the pixel importance Ĩ
    /// (`super::importance`), so that every pixel gets about the same share of their steps;
    /// without it the target is the contribution's luminance (the paper's). Either gives the
    /// same image.
    pub pixel_importance: bool,
}

impl Default for ChainSettings {
    fn default() -> Self {
        Self {
            bootstrap_samples: DEFAULT_BOOTSTRAP,
            mutation: MutationParams { image_s2: DEFAULT_IMAGE_STEP, ..Default::default() },
            pixel_importance: true,
        }
    }
}

/// The Metropolis family: chains parallelised by a schedule over an estimator.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Metropolis {
    /// How the chains are parallelised (naive, speculative tree, reject chain).
    pub schedule: Schedule,
    /// What a chain's state is a sample of.
    pub estimator: Estimator,
    #[allow(missing_docs)] // what every schedule and estimator shares
    pub chains: ChainSettings,
}

impl Metropolis {
    /// The mutation schedule the chains run: the settings' on the estimator's image-plane
    /// dimensions.
    pub fn mutation_params(&self) -> MutationParams {
        MutationParams {
            image_dimension: estimator_raster_dimension(self.estimator.code()),
            ..self.chains.mutation
        }
    }

    /// How many path depths a chain state spans (the factor of b), with `max_depth` bounces.
    pub fn state_depths(&self, max_depth: u32) -> u32 {
        state_depths(self.estimator.code(), max_depth)
    }
}

/// How a render estimates its image.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Integrator {
    /// The path tracer (`pt`): independent samples of every pixel, no chains
    /// (`shared::path_tracer`, the estimator `smlt reference` runs).
    PathTracer,
    /// Metropolis chains (the paper's).
    Metropolis(Metropolis),
}

impl Integrator {
    /// The integrator `method` names, its chains (if any) with `chains`.
    pub fn new(method: Method, chains: ChainSettings) -> Self {
        match method {
            Method::PathTracer => Integrator::PathTracer,
            Method::Metropolis { schedule, estimator } => {
                Integrator::Metropolis(Metropolis { schedule, estimator, chains })
            }
        }
    }

    /// Its name on the command line.
    pub fn method(&self) -> Method {
        match self {
            Integrator::PathTracer => Method::PathTracer,
            Integrator::Metropolis(m) => Method::Metropolis { schedule: m.schedule, estimator: m.estimator },
        }
    }
}

/// Everything that defines a render.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Maximum bounces (pbrt's maxdepth; paths of up to max_depth + 1 segments).
    pub max_depth: u32,
    /// Seed of every random number.
    pub seed: u32,
    /// The path tracer, or the Metropolis chains.
    pub integrator: Integrator,
    /// When to stop.
    pub budget: Budget,
    /// Candidates traced per iteration by the whole render (divided among chains; the path
    /// tracer's paths per round).
    pub candidates: u32,
    /// The part of the chains this process renders.
    pub shard: Shard,
}

impl Default for Settings {
    /// The embedded scene's render as `smlt render` makes it on the CPU backend: 256², 10
    /// bounces, seed 1, naive chains over multiplexed paths, 64 candidates per pixel.
    fn default() -> Self {
        Self {
            width: DEFAULT_WIDTH,
            height: DEFAULT_WIDTH,
            max_depth: DEFAULT_MAX_DEPTH,
            seed: 1,
            integrator: Integrator::new(Method::NAIVE, ChainSettings::default()),
            budget: Budget::MutationsPerPixel(DEFAULT_MUTATIONS_PER_PIXEL),
            candidates: default_candidates(None),
            shard: Shard::WHOLE,
        }
    }
}

impl Settings {
    /// These settings with the integrator `method` names (its chains with the chain settings
    /// these have, or the defaults).
    pub fn with_method(self, method: Method) -> Self {
        let chains = self.metropolis().map_or_else(ChainSettings::default, |m| m.chains);
        Settings { integrator: Integrator::new(method, chains), ..self }
    }

    /// The method's name on the command line.
    pub fn method(&self) -> Method {
        self.integrator.method()
    }

    /// The Metropolis chains' settings; None for the path tracer.
    pub fn metropolis(&self) -> Option<&Metropolis> {
        match &self.integrator {
            Integrator::PathTracer => None,
            Integrator::Metropolis(m) => Some(m),
        }
    }

    /// The Metropolis chains' settings to change; None for the path tracer.
    pub fn metropolis_mut(&mut self) -> Option<&mut Metropolis> {
        match &mut self.integrator {
            Integrator::PathTracer => None,
            Integrator::Metropolis(m) => Some(m),
        }
    }

    /// Whether the chains follow the pixel importance (never for the path tracer).
    pub fn pixel_importance(&self) -> bool {
        self.metropolis().is_some_and(|m| m.chains.pixel_importance)
    }

    /// How many path depths a chain state spans (the factor of b; 1 for the path tracer,
    /// whose b is 1).
    pub fn state_depths(&self) -> u32 {
        self.metropolis().map_or(1, |m| m.state_depths(self.max_depth))
    }

    /// Number of chains of the whole render: the candidates per iteration divided by the
    /// candidates per chain (none for the path tracer).
    pub fn chains(&self) -> u32 {
        self.metropolis().map_or(0, |m| (self.candidates / m.schedule.candidates_per_chain()).max(1))
    }

    /// Global indices of the chains this shard renders.
    pub fn shard_chains(&self) -> Range<u32> {
        self.shard.chains(self.chains())
    }

    /// The path tracer's samples per pixel in one iteration (a round): the candidates per
    /// iteration over the pixels, at least one.
    pub fn samples_per_round(&self) -> u32 {
        (self.candidates / (self.width * self.height).max(1)).max(1)
    }

    /// The path tracer's round that this shard traces in its iteration `iteration`: the
    /// shards take the rounds in turns (shard K of N rounds K − 1, K − 1 + N, …), so their
    /// parts hold disjoint samples and merge into the unsplit render's.
    pub fn round(&self, iteration: u64) -> u32 {
        (iteration * self.shard.count as u64 + self.shard.index as u64 - 1) as u32
    }

    /// Iterations a `--mutations-per-pixel` budget runs: as many as the whole render needs to
    /// trace that many candidates per pixel (the same for every shard of the chains; for the
    /// path tracer, this shard's share of the rounds of whole samples per pixel that reach it).
    pub fn iterations_for(&self, mutations_per_pixel: f64) -> u64 {
        let Some(m) = self.metropolis() else {
            let rounds = ((mutations_per_pixel / self.samples_per_round() as f64).ceil() as u64).max(1);
            let (k, n) = (self.shard.index as u64, self.shard.count as u64);
            return (rounds + n - k) / n;
        };
        let per_iteration = (self.chains() * m.schedule.candidates_per_chain()) as f64;
        let pixels = self.width as f64 * self.height as f64;
        ((mutations_per_pixel * pixels / per_iteration).ceil() as u64).max(1)
    }
}

/// Candidates per iteration when none are given: 262 144 on a GPU (the paper's Table 2), 16 384
/// on a CPU Vulkan driver (lavapipe), 4 096 on the CPU backend.
pub fn default_candidates(gpu: Option<&crate::gpu::Gpu>) -> u32 {
    match gpu {
        Some(g) if g.info.device_type == wgpu::DeviceType::Cpu => 16384,
        Some(_) => 262_144,
        None => 4096,
    }
}

/// The parameters shared by every dispatch of this shard's chains: the scene's camera, the
/// image, depth and seed, and the chains' schedule. The path tracer has no chains: its
/// parameters hold none (the backends then keep no chain buffers worth the name).
pub fn base_params(scene: &SceneData, s: &Settings) -> RenderParams {
    let common = RenderParams {
        camera: scene.camera(s.width, s.height),
        width: s.width,
        height: s.height,
        max_depth: s.max_depth,
        seed: s.seed,
        light_count: scene.lights.len() as u32,
        epsilon: scene.epsilon(),
        mode: MODE_CHAINS,
        ..Default::default()
    };
    let Some(m) = s.metropolis() else { return common };
    let chains = s.shard_chains();
    let n = chains.end - chains.start;
    RenderParams {
        mutation: m.mutation_params(),
        dims: estimator_dimensions(m.estimator.code(), s.max_depth),
        chains: n,
        candidates: n * m.schedule.candidates_per_chain(),
        tree_depth: m.schedule.tree_depth(),
        iteration: 0,
        sample_offset: 0,
        method: m.schedule.code(),
        reject_length: m.schedule.reject_length(),
        chain_offset: chains.start,
        estimator: m.estimator.code(),
        ..common
    }
}

/// The path tracer's parameters for a `width`×`height` image of `scene` with `max_depth`
/// bounces and `seed`, in rounds of `samples` samples per pixel (`round` 0; each round sets
/// its own): what `smlt reference` and `--method pt` run.
pub fn path_tracer_params(
    scene: &SceneData,
    (width, height): (u32, u32),
    max_depth: u32,
    seed: u32,
    samples: u32,
) -> PathTracerParams {
    PathTracerParams {
        camera: scene.camera(width, height),
        width,
        height,
        max_depth,
        seed,
        light_count: scene.lights.len() as u32,
        epsilon: scene.epsilon(),
        samples,
        round: 0,
        samples_per_round: samples,
    }
}

/// The path tracer's parameters for this render ([`path_tracer_params`] in rounds of
/// [`Settings::samples_per_round`]).
pub fn path_params(scene: &SceneData, s: &Settings) -> PathTracerParams {
    path_tracer_params(scene, (s.width, s.height), s.max_depth, s.seed, s.samples_per_round())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shards of any count cover every chain exactly once, in order.
    #[test]
    fn shards_partition_the_chains() {
        for chains in [1u32, 2, 7, 64, 1000, 4096] {
            for count in 1..=9u32.min(chains) {
                let mut next = 0;
                for index in 1..=count {
                    let r = Shard { index, count }.chains(chains);
                    assert_eq!(r.start, next, "{chains} chains, {index}/{count}");
                    assert!(r.end > r.start, "{chains} chains, {index}/{count} is empty");
                    next = r.end;
                }
                assert_eq!(next, chains);
            }
        }
    }

    /// A render's image step is the default unless one is given, on the estimator's own
    /// raster dimensions; the rest of the schedule is the settings'.
    #[test]
    fn the_image_step_moves_the_estimators_raster_dimensions() {
        let chains = ChainSettings {
            mutation: MutationParams { p_large: 0.5, ..ChainSettings::default().mutation },
            ..Default::default()
        };
        let path = Metropolis { schedule: Schedule::NAIVE, estimator: Estimator::Path, chains };
        let m = path.mutation_params();
        assert_eq!((m.image_s2, m.image_dimension, m.p_large), (1.0 / 16.0, 0, 0.5));
        let multiplexed = Metropolis { estimator: Estimator::Multiplexed, ..path };
        let m = multiplexed.mutation_params();
        assert_eq!((m.image_s2, m.image_dimension, m.s2), (1.0 / 16.0, 1, MutationParams::default().s2));
        let mut stepped = multiplexed;
        stepped.chains.mutation.image_s2 = 0.25;
        assert_eq!(stepped.mutation_params().image_s2, 0.25);
    }

    /// The path tracer's shards take the rounds in turns: together, every round of the unsplit
    /// render's budget exactly once.
    #[test]
    fn path_tracer_shards_share_the_rounds() {
        let whole = Settings {
            width: 10,
            height: 6,
            max_depth: 5,
            integrator: Integrator::PathTracer,
            budget: Budget::MutationsPerPixel(17.0),
            candidates: 120,
            ..Default::default()
        };
        assert_eq!(whole.samples_per_round(), 2);
        assert_eq!(whole.iterations_for(17.0), 9);
        for count in 1..=11u32 {
            let mut rounds = Vec::new();
            for index in 1..=count {
                let s = Settings { shard: Shard { index, count }, ..whole.clone() };
                rounds.extend((0..s.iterations_for(17.0)).map(|i| s.round(i)));
            }
            rounds.sort();
            assert_eq!(rounds, (0..9).collect::<Vec<u32>>(), "{count} shards");
        }
        assert_eq!(Settings { candidates: 1, ..whole }.samples_per_round(), 1);
    }

    /// A method keeps the chain settings it is given, and the path tracer has no chains: no
    /// chain count, no pixel importance, b's depth factor 1.
    #[test]
    fn integrators_carry_their_own_settings() {
        let chains = ChainSettings { bootstrap_samples: 7, pixel_importance: false, ..Default::default() };
        let s = Settings::default().with_method("path-s3".parse().unwrap());
        let s = Settings { integrator: Integrator::new(s.method(), chains), candidates: 70, ..s };
        assert_eq!(s.method().to_string(), "path-s3");
        assert_eq!(s.chains(), 10);
        assert_eq!(s.clone().with_method("rc4".parse().unwrap()).metropolis().unwrap().chains, chains);
        let pt = s.with_method(Method::PathTracer);
        assert_eq!((pt.chains(), pt.pixel_importance(), pt.state_depths()), (0, false, 1));
        // Back from the path tracer, the chains get the defaults.
        let back = pt.with_method(Method::NAIVE);
        assert_eq!(back.metropolis().unwrap().chains, ChainSettings::default());
    }

    #[test]
    fn shard_names_parse() {
        assert_eq!("2/3".parse::<Shard>(), Ok(Shard { index: 2, count: 3 }));
        assert_eq!("1/1".parse::<Shard>(), Ok(Shard::WHOLE));
        for bad in ["0/3", "4/3", "3", "a/b", "1/0", "-1/2", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }
}
