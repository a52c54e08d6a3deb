//! The render loop: bootstrap (normalisation b and the chains' start states, drawn in
//! proportion to c), then iterations of mutate → trace → connect → select → splat on a
//! [`Backend`] (the device or CPU threads running the same kernel bodies), with the image
//! drained into f64 periodically and normalised as `b · pixels · S_j / W`, where S_j is the
//! sum of the splats (F/c times their expected-steps weight) in pixel j and W the total weight.

pub mod cpu;
pub mod gpu;

use std::str::FromStr;
use std::time::Instant;

use glam::Vec4;
use shared::mmlt::{
    bootstrap_sample, luminance, sample_dimensions, ChainState, RenderParams, BOOTSTRAP_ITERATION,
    METHOD_REJECT_CHAIN, METHOD_TREE, MODE_BOOTSTRAP, MODE_CHAINS,
};
use shared::mutation::MutationParams;
use shared::reject_chain::MAX_REJECT_CHAIN;
use shared::rng::{self, RngKey};
use shared::tree::{candidate_count, MAX_TREE_DEPTH};

use crate::scene::SceneData;

/// How the chains are parallelised.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Speculative tree of depth d (`s<d>`); d = 1 is the naive parallel MMLT (`naive`).
    Tree(u32),
    /// Reject chain of l proposals (`rc<l>`).
    RejectChain(u32),
}

impl Method {
    /// Candidates traced per chain and iteration.
    pub fn candidates_per_chain(&self) -> u32 {
        match self {
            Method::Tree(d) => candidate_count(*d),
            Method::RejectChain(l) => *l,
        }
    }

    /// Tree depth handed to the kernels (1 for a reject chain, unused there).
    pub fn tree_depth(&self) -> u32 {
        match self {
            Method::Tree(d) => *d,
            Method::RejectChain(_) => 1,
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Method::Tree(1) => write!(f, "naive"),
            Method::Tree(d) => write!(f, "s{d}"),
            Method::RejectChain(l) => write!(f, "rc{l}"),
        }
    }
}

impl FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s == "naive" {
            return Ok(Method::Tree(1));
        }
        if let Some(d) = s.strip_prefix('s') {
            return match d.parse::<u32>() {
                Ok(d) if (1..=MAX_TREE_DEPTH).contains(&d) => Ok(Method::Tree(d)),
                _ => Err(format!(
                    "'{s}': the speculative tree depth must be 1..={MAX_TREE_DEPTH} (s1..s{MAX_TREE_DEPTH})"
                )),
            };
        }
        if let Some(l) = s.strip_prefix("rc") {
            return match l.parse::<u32>() {
                Ok(l) if (2..=MAX_REJECT_CHAIN).contains(&l) => Ok(Method::RejectChain(l)),
                _ => Err(format!("'{s}': the reject-chain length must be 2..={MAX_REJECT_CHAIN} (rc2..rc{MAX_REJECT_CHAIN})")),
            };
        }
        Err(format!(
            "'{s}' is not a method: use naive, s<d> with d in 1..={MAX_TREE_DEPTH}, or rc<l> with l in 2..={MAX_REJECT_CHAIN}"
        ))
    }
}

/// When to stop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Budget {
    /// Wall-clock seconds of iterations (after the bootstrap).
    Seconds(f64),
    /// Candidates traced per pixel (pbrt's mutations per pixel).
    MutationsPerPixel(f64),
}

/// Everything that defines a render.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Maximum bounces (pbrt's maxdepth; paths of up to max_depth + 1 segments).
    pub max_depth: u32,
    /// Seed of every random number.
    pub seed: u32,
    /// Parallelisation.
    pub method: Method,
    /// When to stop.
    pub budget: Budget,
    /// Candidates traced per iteration (divided among chains).
    pub candidates: u32,
    /// Bootstrap samples.
    pub bootstrap_samples: u32,
    /// Mutation schedule.
    pub mutation: MutationParams,
}

impl Settings {
    /// Number of chains: the candidates per iteration divided by candidates per chain.
    pub fn chains(&self) -> u32 {
        (self.candidates / self.method.candidates_per_chain()).max(1)
    }
}

/// What a render measured.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// Chains N.
    pub chains: u32,
    /// Iterations run.
    pub iterations: u64,
    /// Candidate paths traced (the seed's "mutations").
    pub candidates: u64,
    /// Markov-chain steps advanced (total splat weight W).
    pub steps: f64,
    /// Bootstrap samples traced.
    pub bootstrap_samples: u64,
    /// The normalisation b.
    pub b: f64,
    /// Standard error of b (from the bootstrap samples' spread).
    pub b_standard_error: f64,
    /// Expected accepted steps / steps.
    pub acceptance: f64,
    /// Candidates rejected because F was NaN or infinite (never splatted).
    pub invalid: u64,
    /// Seconds of the bootstrap.
    pub bootstrap_seconds: f64,
    /// Seconds of the iterations.
    pub render_seconds: f64,
}

impl Stats {
    /// These statistics with the wall-clock times of `other` (to compare the rest exactly).
    pub fn with_times_of(mut self, other: &Stats) -> Stats {
        self.bootstrap_seconds = other.bootstrap_seconds;
        self.render_seconds = other.render_seconds;
        self
    }
}

/// A finished render.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Linear rgb, row-major from the top-left pixel.
    pub rgb: Vec<f32>,
    /// Measurements.
    pub stats: Stats,
}

/// Why a render failed.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// Every bootstrap sample had zero contribution.
    #[error("all {0} bootstrap samples carry no light to the camera: nothing visible is lit (is the camera inside a closed object, or every light facing away?)")]
    NothingVisible(u64),
    /// The device failed.
    #[error(transparent)]
    Gpu(#[from] crate::gpu::GpuError),
    /// The work does not fit the device.
    #[error("{0}")]
    TooLarge(String),
}

/// Watches a render: progress, an early stop (Ctrl-C), periodic checkpoints of the image so
/// far. A closure `FnMut(f64)` is an observer of progress only.
pub trait Observer {
    /// The fraction of the budget used, after each drain.
    fn progress(&mut self, _fraction: f64) {}
    /// Whether the render should end now (the image so far is returned as the result).
    fn stop_requested(&self) -> bool {
        false
    }
    /// Whether a checkpoint is due `elapsed` seconds into the iterations.
    fn checkpoint_due(&mut self, _elapsed: f64) -> bool {
        false
    }
    /// The image so far, normalised like a finished render.
    fn checkpoint(&mut self, _image: &Rendered) {}
}

impl<F: FnMut(f64)> Observer for F {
    fn progress(&mut self, fraction: f64) {
        self(fraction)
    }
}

/// The normalised image from the accumulated splats: b · pixels · S_j / W.
fn finish(image: &[f64], s: &Settings, stats: &Stats) -> Rendered {
    let pixels = s.width as f64 * s.height as f64;
    let scale = if stats.steps > 0.0 { stats.b * pixels / stats.steps } else { 0.0 };
    Rendered {
        width: s.width,
        height: s.height,
        rgb: image.iter().map(|v| (v * scale) as f32).collect(),
        stats: stats.clone(),
    }
}

/// Where the passes run: the same five kernels on the device or on CPU threads.
pub trait Backend {
    /// Traces `params.candidates` fresh bootstrap samples; returns their contributions.
    fn bootstrap(&mut self, params: &RenderParams) -> Result<Vec<Vec4>, RenderError>;
    /// Sets the chains' samples (SoA) and states.
    fn start(&mut self, chain_u: &[f32], chains: &[ChainState]) -> Result<(), RenderError>;
    /// One iteration of every chain.
    fn iterate(&mut self, params: &RenderParams) -> Result<(), RenderError>;
    /// Adds the splats accumulated since the last drain into `image` (rgb, f64) and clears
    /// them; returns the chains' expected steps since the last drain (their total weight) and
    /// resets those too.
    fn drain(&mut self, image: &mut [f64]) -> Result<f64, RenderError>;
    /// The chains' states.
    fn chain_states(&mut self) -> Result<Vec<ChainState>, RenderError>;
    /// A description of the device.
    fn describe(&self) -> String;
    /// The device backend, for what only it can do (per-pass timings, ray replay).
    fn as_gpu(&mut self) -> Option<&mut gpu::GpuBackend> {
        None
    }
}

/// The parameters shared by every dispatch of a render.
pub fn base_params(scene: &SceneData, s: &Settings) -> RenderParams {
    let chains = s.chains();
    RenderParams {
        camera: scene.camera(s.width, s.height),
        mutation: s.mutation,
        width: s.width,
        height: s.height,
        max_depth: s.max_depth,
        dims: sample_dimensions(s.max_depth),
        chains,
        candidates: chains * s.method.candidates_per_chain(),
        tree_depth: s.method.tree_depth(),
        iteration: 0,
        seed: s.seed,
        light_count: scene.lights.len() as u32,
        mode: MODE_CHAINS,
        sample_offset: 0,
        epsilon: scene.epsilon(),
        method: match s.method {
            Method::Tree(_) => METHOD_TREE,
            Method::RejectChain(_) => METHOD_REJECT_CHAIN,
        },
        reject_length: match s.method {
            Method::RejectChain(l) => l,
            Method::Tree(_) => 0,
        },
        _pad: 0,
    }
}

/// Iterations between drains of the device image into the f64 image.
const DRAIN_EVERY: u64 = 8;

/// A render in progress: bootstrapped chains on a backend, advanced an iteration at a time, so
/// that several methods can be advanced in turns (the bench interleaves them).
pub struct Renderer<'a> {
    backend: &'a mut dyn Backend,
    settings: Settings,
    base: RenderParams,
    image: Vec<f64>,
    stats: Stats,
    pending: u64,
}

impl<'a> Renderer<'a> {
    /// Bootstraps (normalisation b, chains started in proportion to c) and starts the chains.
    pub fn start(scene: &SceneData, s: &Settings, backend: &'a mut dyn Backend) -> Result<Self, RenderError> {
        let base = base_params(scene, s);
        let n = base.chains;
        let c = base.candidates;
        let dims = base.dims;
        let mut stats = Stats { chains: n, ..Default::default() };
        let start = Instant::now();
        let total = s.bootstrap_samples.max(n) as u64;
        let mut contributions: Vec<Vec4> = Vec::with_capacity(total as usize);
        let mut offset = 0u64;
        while offset < total {
            let count = (total - offset).min(c as u64) as u32;
            let params = RenderParams {
                mode: MODE_BOOTSTRAP,
                candidates: count,
                sample_offset: offset as u32,
                ..base
            };
            contributions.extend(backend.bootstrap(&params)?);
            offset += count as u64;
        }
        let targets: Vec<f64> = contributions
            .iter()
            .map(|v| {
                let y = luminance(v.truncate());
                if y.is_finite() && y > 0.0 {
                    y as f64
                } else {
                    0.0
                }
            })
            .collect();
        let sum: f64 = targets.iter().sum();
        if !(sum > 0.0) {
            return Err(RenderError::NothingVisible(total));
        }
        stats.bootstrap_samples = total;
        let mean = sum / total as f64;
        let variance =
            targets.iter().map(|t| (t - mean) * (t - mean)).sum::<f64>() / (total as f64 - 1.0).max(1.0);
        stats.b = (s.max_depth as f64 + 1.0) * mean;
        stats.b_standard_error = (s.max_depth as f64 + 1.0) * (variance / total as f64).sqrt();
        let mut cdf = Vec::with_capacity(targets.len());
        let mut running = 0.0;
        for t in &targets {
            running += t;
            cdf.push(running);
        }
        let mut chain_u = vec![0.0f32; (n * dims) as usize];
        let mut chains = vec![ChainState::default(); n as usize];
        for p in 0..n {
            let key = RngKey {
                seed: s.seed,
                chain: p,
                iteration: BOOTSTRAP_ITERATION,
                dimension: rng::dimension(rng::STREAM_CONTROL, rng::CONTROL_BOOTSTRAP_PICK),
            };
            let target = rng::uniform(key) as f64 * sum;
            let g = cdf.partition_point(|&x| x <= target).min(cdf.len() - 1);
            for dim in 0..dims {
                chain_u[(p + dim * n) as usize] = bootstrap_sample(s.seed, g as u32, dim);
            }
            chains[p as usize] = ChainState {
                contribution: contributions[g].to_array(),
                depth: g as u32 % (s.max_depth + 1),
                ..Default::default()
            };
        }
        backend.start(&chain_u, &chains)?;
        stats.bootstrap_seconds = start.elapsed().as_secs_f64();
        let pixels = s.width as usize * s.height as usize;
        Ok(Self { backend, settings: s.clone(), base, image: vec![0.0; pixels * 3], stats, pending: 0 })
    }

    /// One iteration of every chain; its wall time is added to the render time.
    pub fn iterate(&mut self) -> Result<(), RenderError> {
        let start = Instant::now();
        let params = self.next_params();
        self.backend.iterate(&params)?;
        self.stats.iterations += 1;
        self.stats.candidates += self.base.candidates as u64;
        self.pending += 1;
        if self.pending >= DRAIN_EVERY {
            self.drain()?;
        }
        self.stats.render_seconds += start.elapsed().as_secs_f64();
        Ok(())
    }

    /// Moves the device's splats and step counts into the f64 image.
    pub fn drain(&mut self) -> Result<(), RenderError> {
        self.stats.steps += self.backend.drain(&mut self.image)?;
        self.pending = 0;
        Ok(())
    }

    /// The parameters of the next iteration.
    pub fn next_params(&self) -> RenderParams {
        RenderParams { iteration: self.stats.iterations as u32, ..self.base }
    }

    /// The statistics so far (steps as of the last drain).
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// The image so far without reading the chains (for checkpoints).
    pub fn image(&mut self) -> Result<Rendered, RenderError> {
        self.drain()?;
        Ok(finish(&self.image, &self.settings, &self.stats))
    }

    /// The image so far with acceptance and NaN/Inf counts from the chains.
    pub fn snapshot(&mut self) -> Result<Rendered, RenderError> {
        let start = Instant::now();
        self.drain()?;
        let states = self.backend.chain_states()?;
        self.stats.acceptance =
            states.iter().map(|x| x.accepted as f64).sum::<f64>() / self.stats.steps.max(1e-30);
        self.stats.invalid = states.iter().map(|x| x.invalid as u64).sum();
        self.stats.render_seconds += start.elapsed().as_secs_f64();
        Ok(finish(&self.image, &self.settings, &self.stats))
    }
}

/// Renders `scene` on `backend`, reporting to `observer`.
pub fn render(
    scene: &SceneData,
    s: &Settings,
    backend: &mut dyn Backend,
    mut observer: impl Observer,
) -> Result<Rendered, RenderError> {
    let mut r = Renderer::start(scene, s, backend)?;
    let pixels = s.width as f64 * s.height as f64;
    loop {
        r.iterate()?;
        let stats = r.stats();
        let fraction = match s.budget {
            Budget::Seconds(t) => stats.render_seconds / t,
            Budget::MutationsPerPixel(m) => stats.candidates as f64 / (m * pixels),
        };
        let done = fraction >= 1.0 || observer.stop_requested();
        if done {
            break;
        }
        if stats.iterations.is_multiple_of(DRAIN_EVERY) {
            observer.progress(fraction.min(1.0));
            let elapsed = stats.render_seconds;
            if observer.checkpoint_due(elapsed) {
                let image = r.image()?;
                observer.checkpoint(&image);
            }
        }
    }
    observer.progress(1.0);
    r.snapshot()
}
