//! The render loop: compile the kernels, bootstrap, then iterations of mutate → trace →
//! connect → select → splat on a [`Backend`], drained into an [`Accumulation`] every
//! [`DRAIN_EVERY`] iterations. The image is `b · pixels · S_j / W`, where S_j is the sum of the
//! splats in pixel j, W the total splat weight, and b the pooled estimate of the bootstrap's
//! and every large step's targets (`shared::normalisation`).
//!
//! The path tracer (`--method pt`) runs in the same loop: no bootstrap, an iteration is a
//! round of whole samples per pixel, S_j the sum of pixel j's samples, W the paths traced and
//! b = 1, so that the same formula is each pixel's mean.

use std::time::Instant;

use shared::normalisation::{estimate, Estimate, Moments};
use shared::params::RenderParams;
use shared::path_tracer::PathTracerParams;

use super::bootstrap::{bootstrap, Bootstrap, Preparation};
use super::importance::estimate_pixel_importance;
use super::{base_params, path_params, Accumulation, Backend, Budget, Integrator, RenderError, Settings};
use crate::scene::SceneData;

/// What a render measured.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// Chains N (of this shard).
    pub chains: u32,
    /// Iterations run.
    pub iterations: u64,
    /// Candidate paths traced (the paper's "mutations").
    pub candidates: u64,
    /// Markov-chain steps advanced (total splat weight W).
    pub steps: f64,
    /// Bootstrap samples traced.
    pub bootstrap_samples: u64,
    /// Large-step candidates whose targets refined b.
    pub large_steps: u64,
    /// The normalisation b (bootstrap and large steps pooled).
    pub b: f64,
    /// Standard error of b, from the pooled samples' spread.
    pub b_standard_error: f64,
    /// Expected accepted steps / steps.
    pub acceptance: f64,
    /// Candidates rejected because F was NaN or infinite (never splatted).
    pub invalid: u64,
    /// Seconds spent preparing the device's kernels (compilation) before the clock started;
    /// None where there is nothing to compile (the CPU backend).
    pub compile_seconds: Option<f64>,
    /// Seconds of the bootstrap.
    pub bootstrap_seconds: f64,
    /// Seconds of the pixel importance (`super::importance`), before the clock like the
    /// bootstrap; None for `pt` and with `--no-pixel-importance`.
    pub importance_seconds: Option<f64>,
    /// Seconds of the iterations (what `--time` counts).
    pub render_seconds: f64,
}

impl Stats {
    /// b's standard error relative to b.
    pub fn b_relative_standard_error(&self) -> f64 {
        if self.b > 0.0 {
            self.b_standard_error / self.b
        } else {
            f64::INFINITY
        }
    }
}

/// A finished render (or a part of one), with what it needs to be merged with others.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Linear rgb, row-major from the top-left pixel.
    pub rgb: Vec<f32>,
    #[allow(missing_docs)] // named for what it is
    pub stats: Stats,
    /// The splat sums and tallies the image was computed from.
    pub accumulation: Accumulation,
    /// The bootstrap samples' moments.
    pub bootstrap: Moments,
}

/// b of a Metropolis render with these bootstrap moments and accumulation, whose chain states
/// span `depths` path depths (`Settings::state_depths`).
pub fn normalisation(depths: u32, bootstrap: &Moments, acc: &Accumulation) -> Estimate {
    estimate(depths, &bootstrap.merged(acc.large_steps))
}

/// b of a render by `integrator`: the Metropolis chains' [`normalisation`] with `max_depth`
/// bounces, exactly 1 for the path tracer (its splats are the samples themselves).
fn integrator_normalisation(
    integrator: &Integrator,
    max_depth: u32,
    bootstrap: &Moments,
    acc: &Accumulation,
) -> Estimate {
    match integrator {
        Integrator::PathTracer => Estimate { b: 1.0, standard_error: 0.0, samples: 0 },
        Integrator::Metropolis(m) => normalisation(m.state_depths(max_depth), bootstrap, acc),
    }
}

impl Rendered {
    /// The normalised image `b · pixels · S_j / W` of an accumulation of a render with
    /// settings `s`; `stats` gets b, its error, the steps, acceptance and NaN/Inf counts from it.
    pub fn from_accumulation(
        s: &Settings,
        bootstrap: Moments,
        accumulation: Accumulation,
        mut stats: Stats,
    ) -> Rendered {
        let (width, height) = (s.width, s.height);
        let b = integrator_normalisation(&s.integrator, s.max_depth, &bootstrap, &accumulation);
        let pixels = width as f64 * height as f64;
        let w = accumulation.weight;
        let scale = if w > 0.0 { b.b * pixels / w } else { 0.0 };
        stats.b = b.b;
        stats.b_standard_error = b.standard_error;
        stats.bootstrap_samples = bootstrap.count;
        stats.large_steps = accumulation.large_steps.count;
        stats.steps = w;
        stats.candidates = accumulation.candidates;
        stats.acceptance = accumulation.accepted / w.max(1e-30);
        stats.invalid = accumulation.invalid;
        Rendered {
            width,
            height,
            rgb: accumulation.image.iter().map(|v| (v * scale) as f32).collect(),
            stats,
            accumulation,
            bootstrap,
        }
    }
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
    /// The backend is about to prepare its kernels (which may take a while on first use).
    fn compiling(&mut self) {}
    /// The kernels are ready.
    fn compiled(&mut self) {}
}

impl<F: FnMut(f64)> Observer for F {
    fn progress(&mut self, fraction: f64) {
        self(fraction)
    }
}

/// Iterations between drains of the backend's image and tallies.
pub const DRAIN_EVERY: u64 = 8;

/// What a render in progress iterates: the path tracer's rounds or the chains.
enum Progress {
    /// The path tracer's rounds' parameters.
    PathTracer(PathTracerParams),
    /// The chains' dispatch parameters, and the pixel importance Ĩ (None with
    /// `--no-pixel-importance`), which the drained sums are multiplied by, with the
    /// accumulation they are drained into first.
    Metropolis { base: RenderParams, importance: Option<(Vec<f32>, Accumulation)> },
}

/// A render in progress: bootstrapped chains (or the path tracer) on a backend, advanced an
/// iteration at a time, so that several methods can be advanced in turns (the bench
/// interleaves them).
pub struct Renderer<'a> {
    backend: &'a mut dyn Backend,
    settings: Settings,
    progress: Progress,
    /// The bootstrap samples' moments (none for the path tracer).
    bootstrap: Moments,
    acc: Accumulation,
    stats: Stats,
    pending: u64,
}

impl<'a> Renderer<'a> {
    /// Prepares the backend's kernels (telling `observer`), makes the pixel importance and
    /// bootstraps (on the host: the same for every shard and device) and starts
    /// this shard's chains. None of it counts as render time. The path tracer only prepares
    /// its kernel.
    pub fn start(
        scene: &SceneData,
        s: &Settings,
        backend: &'a mut dyn Backend,
        observer: &mut dyn Observer,
    ) -> Result<Self, RenderError> {
        Self::start_with(scene, s, backend, observer, Preparation::Reproducible)
    }

    /// [`Renderer::start`], with the chains' preparation casting through `preparation`'s
    /// traversal.
    pub fn start_with(
        scene: &SceneData,
        s: &Settings,
        backend: &'a mut dyn Backend,
        observer: &mut dyn Observer,
        preparation: Preparation<'_>,
    ) -> Result<Self, RenderError> {
        let compile_seconds =
            |backend: &mut dyn Backend,
             observer: &mut dyn Observer,
             warm_up: &dyn Fn(&mut dyn Backend) -> Result<(), RenderError>| {
                if !backend.compiles_kernels() {
                    return Ok(None);
                }
                let compile = Instant::now();
                observer.compiling();
                warm_up(backend)?;
                observer.compiled();
                Ok::<_, RenderError>(Some(compile.elapsed().as_secs_f64()))
            };
        let pixels = s.width as usize * s.height as usize;
        let mut stats = Stats::default();
        let (progress, bootstrap_moments) = match &s.integrator {
            Integrator::PathTracer => {
                let params = path_params(scene, s);
                stats.compile_seconds =
                    compile_seconds(backend, observer, &|b| b.warm_up_path_tracer(&params))?;
                (Progress::PathTracer(params), Moments::default())
            }
            Integrator::Metropolis(m) => {
                let base = base_params(scene, s);
                stats.compile_seconds = compile_seconds(backend, observer, &|b| b.warm_up(&base))?;
                // On the backend's pool: the pixel importance (ones without it), then the
                // bootstrap that uses it.
                let prepare = || -> Result<(Bootstrap, Vec<f32>, Option<f64>), RenderError> {
                    let begin = Instant::now();
                    let (weights, seconds) = if m.chains.pixel_importance {
                        (
                            estimate_pixel_importance(scene, s, m, preparation),
                            Some(begin.elapsed().as_secs_f64()),
                        )
                    } else {
                        (vec![1.0; pixels], None)
                    };
                    Ok((bootstrap(scene, s, m, &weights, preparation)?, weights, seconds))
                };
                let (boot, weights, importance_seconds) = match backend.thread_pool() {
                    Some(pool) => pool.install(prepare)?,
                    None => prepare()?,
                };
                backend.start(&boot.chain_u, &boot.chains, &weights)?;
                stats.chains = base.chains;
                stats.bootstrap_seconds = boot.seconds;
                stats.importance_seconds = importance_seconds;
                let importance = m.chains.pixel_importance.then(|| (weights, Accumulation::new(pixels)));
                (Progress::Metropolis { base, importance }, boot.moments)
            }
        };
        Ok(Self {
            backend,
            settings: s.clone(),
            progress,
            bootstrap: bootstrap_moments,
            acc: Accumulation::new(pixels),
            stats,
            pending: 0,
        })
    }

    /// One iteration of every chain (or one round of the path tracer); its wall time is added
    /// to the render time.
    pub fn iterate(&mut self) -> Result<(), RenderError> {
        let start = Instant::now();
        match &self.progress {
            &Progress::PathTracer(p) => {
                let round = self.settings.round(self.stats.iterations);
                self.backend.trace_path_tracer_round(&PathTracerParams { round, ..p })?;
                // Every path is a sample of weight one: W counts them.
                let paths = p.samples as u64 * p.width as u64 * p.height as u64;
                self.acc.candidates += paths;
                self.acc.weight += paths as f64;
                self.acc.accepted += paths as f64;
            }
            Progress::Metropolis { base, .. } => {
                let params = RenderParams { iteration: self.stats.iterations as u32, ..*base };
                self.backend.iterate(&params)?;
                self.acc.candidates += base.candidates as u64;
            }
        }
        self.stats.iterations += 1;
        self.pending += 1;
        if self.pending >= DRAIN_EVERY {
            self.drain()?;
        }
        self.stats.render_seconds += start.elapsed().as_secs_f64();
        Ok(())
    }

    /// Moves the backend's splats and tallies into the accumulation (the sums times each
    /// pixel's Ĩ).
    fn drain(&mut self) -> Result<(), RenderError> {
        match &mut self.progress {
            Progress::Metropolis { importance: Some((importance, drained)), .. } => {
                self.backend.drain(drained)?;
                self.acc.merge_weighted(drained, importance);
            }
            _ => self.backend.drain(&mut self.acc)?,
        }
        self.pending = 0;
        Ok(())
    }

    /// Iterations, render time and the other timings so far (b, steps and counts are filled
    /// in by [`Renderer::snapshot`]).
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// The image so far, with b, acceptance and NaN/Inf counts (drains the backend; its time
    /// counts as render time).
    pub fn snapshot(&mut self) -> Result<Rendered, RenderError> {
        let start = Instant::now();
        self.drain()?;
        self.stats.render_seconds += start.elapsed().as_secs_f64();
        Ok(Rendered::from_accumulation(&self.settings, self.bootstrap, self.acc.clone(), self.stats.clone()))
    }
}

/// Renders `scene` on `backend`, reporting to `observer`.
pub fn render(
    scene: &SceneData,
    s: &Settings,
    backend: &mut dyn Backend,
    observer: impl Observer,
) -> Result<Rendered, RenderError> {
    render_with(scene, s, backend, observer, Preparation::Reproducible)
}

/// [`render`], with the chains' preparation casting through `preparation`'s traversal.
pub fn render_with(
    scene: &SceneData,
    s: &Settings,
    backend: &mut dyn Backend,
    mut observer: impl Observer,
    preparation: Preparation<'_>,
) -> Result<Rendered, RenderError> {
    let mut r = Renderer::start_with(scene, s, backend, &mut observer, preparation)?;
    let iterations = match s.budget {
        Budget::MutationsPerPixel(m) => s.iterations_for(m),
        Budget::Seconds(_) => u64::MAX,
    };
    // The fraction of the budget used (a path tracer's shard may have no round of its own:
    // more shards than rounds).
    let used = |stats: &Stats| match s.budget {
        Budget::Seconds(t) => stats.render_seconds / t,
        Budget::MutationsPerPixel(_) if iterations == 0 => 1.0,
        Budget::MutationsPerPixel(_) => stats.iterations as f64 / iterations as f64,
    };
    while used(r.stats()) < 1.0 && !observer.stop_requested() {
        r.iterate()?;
        let stats = r.stats();
        // The last iteration's image is the result, not a checkpoint.
        if used(stats) >= 1.0 || observer.stop_requested() {
            break;
        }
        if stats.iterations.is_multiple_of(DRAIN_EVERY) {
            observer.progress(used(stats).min(1.0));
            if observer.checkpoint_due(stats.render_seconds) {
                let image = r.snapshot()?;
                observer.checkpoint(&image);
            }
        }
    }
    observer.progress(1.0);
    r.snapshot()
}
