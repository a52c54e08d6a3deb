//! The device backend: the render's buffers on the GPU and the five passes over them, or the
//! path tracer's pass over the scene and the same image.

use shared::mmlt::ChainState;
use shared::params::RenderParams;
use shared::path_tracer::PathTracerParams;

use super::{Accumulation, Backend, RenderError};
use crate::gpu::Gpu;
use crate::passes::buffers::{buffer_sizes, GpuBuffers, OnDevice, SceneBuffers, Sizes};
use crate::passes::{Pass, Stage};
use crate::scene::SceneData;
use crate::timing::{time_passes, Clock};

/// The device backend.
pub struct GpuBackend {
    gpu: Gpu,
    buffers: GpuBuffers,
    /// One pass per stage, in [`Stage::ITERATION`] order.
    passes: Vec<Pass>,
    /// The `path_tracer` pass and its parameters (made at its first use).
    path_tracer: Option<(wgpu::Buffer, Pass)>,
    pixels: usize,
    chains: u32,
    dims: u32,
}

impl GpuBackend {
    /// Allocates the buffers for `params` (checking them against the device's limits first)
    /// and builds the passes.
    pub fn new(gpu: Gpu, scene: &SceneData, params: &RenderParams) -> Result<Self, RenderError> {
        let limit = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
        for buffer in buffer_sizes(scene, params) {
            let (name, size) = (buffer.label, buffer.bytes);
            if size > limit {
                let remedy = if SceneBuffers::<Sizes>::holds(buffer.name) {
                    format!(
                        "the scene ({} triangles) is too large for this device: render it with --device cpu",
                        scene.triangles.len()
                    )
                } else {
                    "lower --candidates, --max-depth or the resolution".to_string()
                };
                return Err(RenderError::TooLarge(format!(
                    "the {name} buffer needs {:.1} MiB but the device allows {:.1} MiB per storage buffer \
                     (max_storage_buffer_binding_size); {remedy}",
                    size as f64 / 1048576.0,
                    limit as f64 / 1048576.0
                )));
            }
        }
        let groups = params.candidates.div_ceil(kernels::WORKGROUP_SIZE);
        if groups > gpu.limits.max_compute_workgroups_per_dimension {
            return Err(RenderError::TooLarge(format!(
                "{} candidates need {groups} workgroups, more than the device's \
                 max_compute_workgroups_per_dimension ({}); lower --candidates",
                params.candidates, gpu.limits.max_compute_workgroups_per_dimension
            )));
        }
        let pixels = (params.width * params.height) as usize;
        let buffers = GpuBuffers::new(&mut OnDevice::new(gpu.clone()), scene, params);
        let passes = Stage::ITERATION.iter().map(|s| s.pass(&gpu, &buffers)).collect::<Result<_, _>>()?;
        Ok(Self { gpu, buffers, passes, path_tracer: None, pixels, chains: params.chains, dims: params.dims })
    }

    /// Runs the path tracer's pass over `pixels` invocations with `params`, and waits.
    fn dispatch_path_tracer(&mut self, params: &PathTracerParams, pixels: u32) -> Result<(), RenderError> {
        if self.path_tracer.is_none() {
            let buffer = self.gpu.storage_from("path tracer params", &[*params]);
            let pass = crate::passes::path_tracer::gpu(&self.gpu, &buffer, &self.buffers)?;
            self.path_tracer = Some((buffer, pass));
        }
        let (buffer, pass) = self.path_tracer.as_ref().expect("made above");
        self.gpu.queue.write_buffer(buffer, 0, bytemuck::bytes_of(params));
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        pass.encode(&self.gpu, &mut encoder, pixels);
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.wait()?;
        Ok(())
    }

    #[allow(missing_docs)] // named for what it returns
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// The buffers (for difftests).
    pub fn buffers(&self) -> &GpuBuffers {
        &self.buffers
    }

    /// Runs `stages` in order, each with its invocations for `params`, and waits.
    pub fn run(&mut self, params: &RenderParams, stages: &[Stage]) -> Result<(), RenderError> {
        let counts: Vec<(Stage, u32)> = stages.iter().map(|s| (*s, s.invocations(params))).collect();
        self.dispatch(params, &counts)
    }

    /// Runs each stage with the given number of invocations, in order, and waits.
    fn dispatch(&mut self, params: &RenderParams, stages: &[(Stage, u32)]) -> Result<(), RenderError> {
        self.gpu.queue.write_buffer(&self.buffers.params, 0, bytemuck::bytes_of(params));
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        for &(stage, threads) in stages {
            self.passes[stage.index()].encode(&self.gpu, &mut encoder, threads);
        }
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.wait()?;
        Ok(())
    }

    /// One iteration of every chain, as [`Backend::iterate`], with each stage timed
    /// (`crate::timing`): device seconds per stage, in [`Stage::ITERATION`] order.
    pub fn iterate_timed(&mut self, params: &RenderParams) -> Result<(PassTimes, Clock), RenderError> {
        self.gpu.queue.write_buffer(&self.buffers.params, 0, bytemuck::bytes_of(params));
        let timed: Vec<(&Pass, u32)> =
            Stage::ITERATION.iter().map(|s| (&self.passes[s.index()], s.invocations(params))).collect();
        let (seconds, clock) = time_passes(&self.gpu, &timed)?;
        let mut times = [0.0; Stage::COUNT];
        times.copy_from_slice(&seconds);
        Ok((times, clock))
    }
}

/// Device seconds of each stage of one iteration, in [`Stage::ITERATION`] order.
pub type PassTimes = [f64; Stage::COUNT];

impl Backend for GpuBackend {
    /// Runs every pass once with no work (one workgroup whose invocations all return at once):
    /// drivers such as lavapipe compile a pipeline's machine code at its first dispatch.
    fn compiles_kernels(&self) -> bool {
        true
    }

    fn warm_up(&mut self, params: &RenderParams) -> Result<(), RenderError> {
        let idle = RenderParams { candidates: 0, chains: 0, ..*params };
        let all: Vec<(Stage, u32)> = Stage::ITERATION.iter().map(|s| (*s, 1)).collect();
        self.dispatch(&idle, &all)?;
        self.gpu.save_pipeline_cache();
        Ok(())
    }

    /// One workgroup over an empty image (its invocations return at once).
    fn warm_up_path_tracer(&mut self, params: &PathTracerParams) -> Result<(), RenderError> {
        self.dispatch_path_tracer(&PathTracerParams { width: 0, height: 0, ..*params }, 1)?;
        self.gpu.save_pipeline_cache();
        Ok(())
    }

    /// The path tracer's pass adds each pixel's samples to the image's f32 (no atomics: one
    /// invocation a pixel).
    fn trace_path_tracer_round(&mut self, params: &PathTracerParams) -> Result<(), RenderError> {
        self.dispatch_path_tracer(params, params.width * params.height)
    }

    fn start(
        &mut self,
        chain_u: &[f32],
        chains: &[ChainState],
        importance: &[f32],
    ) -> Result<(), RenderError> {
        assert_eq!(chain_u.len(), (self.chains * self.dims) as usize);
        assert_eq!(importance.len(), self.pixels);
        self.gpu.queue.write_buffer(&self.buffers.importance, 0, bytemuck::cast_slice(importance));
        self.gpu.queue.write_buffer(&self.buffers.iteration.chain_u, 0, bytemuck::cast_slice(chain_u));
        self.gpu.queue.write_buffer(&self.buffers.iteration.chains, 0, bytemuck::cast_slice(chains));
        Ok(())
    }

    fn iterate(&mut self, params: &RenderParams) -> Result<(), RenderError> {
        self.run(params, &Stage::ITERATION)
    }

    fn drain(&mut self, acc: &mut Accumulation) -> Result<(), RenderError> {
        let bits: Vec<u32> = self.gpu.read(&self.buffers.image, self.pixels * 3)?;
        for (a, b) in acc.image.iter_mut().zip(&bits) {
            *a += f32::from_bits(*b) as f64;
        }
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        encoder.clear_buffer(&self.buffers.image, 0, None);
        self.gpu.queue.submit([encoder.finish()]);
        // The chains' tallies since the last drain, then reset (no kernel runs meanwhile).
        let mut chains: Vec<ChainState> =
            self.gpu.read(&self.buffers.iteration.chains, self.chains as usize)?;
        for chain in &mut chains {
            acc.drain_chain(chain);
        }
        self.gpu.queue.write_buffer(&self.buffers.iteration.chains, 0, bytemuck::cast_slice(&chains));
        Ok(())
    }

    fn describe(&self) -> String {
        self.gpu.describe()
    }
}
