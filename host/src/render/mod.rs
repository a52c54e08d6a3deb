//! Rendering: the [`Settings`] of a render, its host-side [`bootstrap`], the [`Renderer`] loop
//! over a [`Backend`] (the device, or the same kernel bodies on CPU threads), and the
//! mergeable [`Accumulation`] that a render, a shard or a thread group produces.

pub mod accumulation;
pub mod auto;
pub mod blind_spot;
pub mod bootstrap;
pub mod cpu;
pub mod estimator;
pub mod gpu;
pub mod host_memory;
pub mod importance;
pub mod method;
pub mod renderer;
pub mod settings;

pub use accumulation::Accumulation;
pub use blind_spot::blind_spot;
pub use bootstrap::Preparation;
pub use estimator::Estimator;
pub use method::{Method, MethodChoice, Schedule};
pub use renderer::{normalisation, render, render_with, Observer, Rendered, Renderer, Stats, DRAIN_EVERY};
pub use settings::{
    base_params, default_candidates, path_params, path_tracer_params, Budget, ChainSettings, Integrator,
    Metropolis, Settings, Shard, DEFAULT_BOOTSTRAP, DEFAULT_IMAGE_STEP, DEFAULT_MAX_DEPTH,
    DEFAULT_MUTATIONS_PER_PIXEL, DEFAULT_WIDTH,
};

use shared::mmlt::ChainState;
use shared::params::RenderParams;
use shared::path_tracer::PathTracerParams;

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
    /// The CPU backend's threads could not be started.
    #[error("cannot start the CPU threads: {0}")]
    Threads(String),
}

/// A backend for a render with `params` of `scene`: the kernels on `gpu`, or on `threads` CPU
/// threads where there is none.
pub fn new_backend<'a>(
    gpu: Option<&crate::gpu::Gpu>,
    scene: &'a crate::scene::SceneData,
    params: &RenderParams,
    threads: usize,
) -> Result<Box<dyn Backend + 'a>, RenderError> {
    Ok(match gpu {
        Some(g) => Box::new(gpu::GpuBackend::new(g.clone(), scene, params)?),
        None => Box::new(cpu::CpuBackend::new(scene, params, threads)?),
    })
}

/// Where the passes run: the same kernels on the device or on CPU threads — the five stages
/// of the Metropolis methods' iterations, or the path tracer's rounds.
pub trait Backend {
    /// Whether the backend compiles its kernels at run time (a Vulkan driver does; the CPU
    /// backend's kernels are compiled Rust).
    fn compiles_kernels(&self) -> bool {
        false
    }
    /// Prepares every kernel a render with `params` runs (compiles them, on drivers that
    /// compile at first use), so that no compilation falls into the render's time.
    fn warm_up(&mut self, _params: &RenderParams) -> Result<(), RenderError> {
        Ok(())
    }
    /// Prepares the path tracer's kernel (`--method pt`), as [`Backend::warm_up`] the chains'.
    fn warm_up_path_tracer(&mut self, _params: &PathTracerParams) -> Result<(), RenderError> {
        Ok(())
    }
    /// One round of the path tracer: `params.samples` paths through every pixel, added to the
    /// image that the next [`Backend::drain`] moves.
    fn trace_path_tracer_round(&mut self, params: &PathTracerParams) -> Result<(), RenderError>;
    /// Sets the chains' samples (SoA) and states, and the pixel importance Ĩ their contributions
    /// are divided by (ones with `--no-pixel-importance`).
    fn start(
        &mut self,
        chain_u: &[f32],
        chains: &[ChainState],
        importance: &[f32],
    ) -> Result<(), RenderError>;
    /// One iteration of every chain.
    fn iterate(&mut self, params: &RenderParams) -> Result<(), RenderError>;
    /// Moves the splats accumulated since the last drain and the chains' tallies (steps,
    /// acceptances, NaN/Inf candidates, large-step targets) into `acc`, and clears them.
    fn drain(&mut self, acc: &mut Accumulation) -> Result<(), RenderError>;
    /// A description of the device.
    fn describe(&self) -> String;
    /// The thread pool the host-side work of a render (the pixel importance, the bootstrap)
    /// runs on; None: rayon's global pool.
    fn thread_pool(&self) -> Option<&rayon::ThreadPool> {
        None
    }
}
