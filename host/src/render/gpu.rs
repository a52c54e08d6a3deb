//! The device backend: the render's buffers on the GPU and the five passes over them.

use glam::Vec4;
use shared::mmlt::{vertex_slots, ChainState, PathInfo, PathVertex, RenderParams};

use super::{Accumulation, Backend, RenderError};
use crate::gpu::Gpu;
use crate::passes::{self, Pass, Stage};
use crate::scene::SceneData;
use crate::timing::{time_passes, Clock};

/// The device buffers of a render.
pub struct GpuBuffers {
    /// One `RenderParams`, rewritten before each dispatch.
    pub params: wgpu::Buffer,
    /// Chain samples, SoA (`p + i·N`).
    pub chain_u: wgpu::Buffer,
    /// Chain states.
    pub chains: wgpu::Buffer,
    /// Candidate samples, SoA (`k + i·C`).
    pub cand_u: wgpu::Buffer,
    /// Candidate path depths.
    pub cand_depth: wgpu::Buffer,
    /// BVH nodes.
    pub nodes: wgpu::Buffer,
    /// Triangles.
    pub triangles: wgpu::Buffer,
    /// Materials.
    pub materials: wgpu::Buffer,
    /// Light CDF.
    pub lights: wgpu::Buffer,
    /// Subpath vertices, SoA (`k + slot·C`).
    pub vertices: wgpu::Buffer,
    /// Path infos.
    pub paths: wgpu::Buffer,
    /// Packed contributions (float4).
    pub contributions: wgpu::Buffer,
    /// Splat records (float4), one per distinct state of each chain.
    pub splats: wgpu::Buffer,
    /// The f32 image as bits, rgb per pixel.
    pub image: wgpu::Buffer,
}

/// The device backend.
pub struct GpuBackend {
    gpu: Gpu,
    buffers: GpuBuffers,
    /// One pass per stage, in [`Stage::ITERATION`] order.
    passes: [Pass; 5],
    pixels: usize,
    chains: u32,
    dims: u32,
}

/// Total bytes of the render's device buffers (what `smlt render` reports as device memory).
pub fn device_bytes(scene: &SceneData, p: &RenderParams) -> u64 {
    buffer_sizes(scene, p).iter().map(|(_, b)| b).sum::<u64>()
        + std::mem::size_of_val(&scene.materials[..]) as u64
}

/// Byte sizes of the render's buffers, by name, for a limits check before allocating.
pub fn buffer_sizes(scene: &SceneData, p: &RenderParams) -> Vec<(&'static str, u64)> {
    let c = p.candidates as u64;
    let n = p.chains as u64;
    vec![
        ("chain samples", n * p.dims as u64 * 4),
        ("chain states", n * std::mem::size_of::<ChainState>() as u64),
        ("candidate samples", c * p.dims as u64 * 4),
        ("candidate depths", c * 4),
        ("BVH nodes", std::mem::size_of_val(&scene.nodes[..]) as u64),
        ("triangles", std::mem::size_of_val(&scene.triangles[..]) as u64),
        ("vertices", c * vertex_slots(p.max_depth) as u64 * std::mem::size_of::<PathVertex>() as u64),
        ("path infos", c * std::mem::size_of::<PathInfo>() as u64),
        ("contributions", c * 16),
        ("splat records", n * p.states_per_chain() as u64 * 16),
        ("image", p.width as u64 * p.height as u64 * 12),
    ]
}

impl GpuBackend {
    /// Allocates the buffers for `params` (checking them against the device's limits first)
    /// and builds the passes.
    pub fn new(gpu: Gpu, scene: &SceneData, params: &RenderParams) -> Result<Self, RenderError> {
        let limit = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
        for (name, size) in buffer_sizes(scene, params) {
            if size > limit {
                return Err(RenderError::TooLarge(format!(
                    "the {name} buffer needs {:.1} MiB but the device allows {:.1} MiB per storage buffer \
                     (max_storage_buffer_binding_size); lower --candidates, --max-depth or the resolution",
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
        let c = params.candidates as usize;
        let n = params.chains as usize;
        let dims = params.dims as usize;
        let pixels = (params.width * params.height) as usize;
        let buffers = GpuBuffers {
            params: gpu.storage_from("params", &[*params]),
            chain_u: gpu.storage_zeroed::<f32>("chain samples", n * dims),
            chains: gpu.storage_zeroed::<ChainState>("chain states", n),
            cand_u: gpu.storage_zeroed::<f32>("candidate samples", c * dims),
            cand_depth: gpu.storage_zeroed::<u32>("candidate depths", c),
            nodes: gpu.storage_from("BVH nodes", &scene.nodes),
            triangles: gpu.storage_from("triangles", &scene.triangles),
            materials: gpu.storage_from("materials", &scene.materials),
            lights: gpu.storage_from("lights", &scene.lights),
            vertices: gpu
                .storage_zeroed::<PathVertex>("vertices", c * vertex_slots(params.max_depth) as usize),
            paths: gpu.storage_zeroed::<PathInfo>("path infos", c),
            contributions: gpu.storage_zeroed::<Vec4>("contributions", c),
            splats: gpu.storage_zeroed::<Vec4>("splat records", Stage::Splat.invocations(params) as usize),
            image: gpu.storage_zeroed::<u32>("image", pixels * 3),
        };
        let passes = [
            passes::mutate::gpu(&gpu, &buffers)?,
            passes::trace::gpu(&gpu, &buffers)?,
            passes::connect::gpu(&gpu, &buffers)?,
            passes::select::gpu(&gpu, &buffers)?,
            passes::splat::gpu(&gpu, &buffers)?,
        ];
        Ok(Self { gpu, buffers, passes, pixels, chains: params.chains, dims: params.dims })
    }

    /// The device.
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
        self.gpu
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| crate::gpu::GpuError::Readback(e.to_string()))?;
        Ok(())
    }

    /// One iteration of every chain, as [`Backend::iterate`], with each stage timed
    /// (`crate::timing`): device seconds per stage, in [`Stage::ITERATION`] order.
    pub fn iterate_timed(&mut self, params: &RenderParams) -> Result<(PassTimes, Clock), RenderError> {
        self.gpu.queue.write_buffer(&self.buffers.params, 0, bytemuck::bytes_of(params));
        let timed: Vec<(&Pass, u32)> =
            Stage::ITERATION.iter().map(|s| (&self.passes[s.index()], s.invocations(params))).collect();
        let (seconds, clock) = time_passes(&self.gpu, &timed)?;
        let mut times = [0.0; 5];
        times.copy_from_slice(&seconds);
        Ok((times, clock))
    }
}

/// Device seconds of each stage of one iteration, in [`Stage::ITERATION`] order.
pub type PassTimes = [f64; 5];

impl GpuBackend {
    /// Traces `params.candidates` bootstrap samples on the device (mutate, trace and connect in
    /// bootstrap mode) and returns their contributions. Renders bootstrap on the host
    /// (`render::bootstrap`); this serves the difftests of the passes in bootstrap mode.
    pub fn bootstrap(&mut self, params: &RenderParams) -> Result<Vec<Vec4>, RenderError> {
        self.run(params, &[Stage::Mutate, Stage::Trace, Stage::Connect])?;
        Ok(self.gpu.read(&self.buffers.contributions, params.candidates as usize)?)
    }
}

impl Backend for GpuBackend {
    /// Runs every pass once with no work (one workgroup whose invocations all return at once):
    /// drivers such as lavapipe compile a pipeline's machine code at its first dispatch.
    fn warm_up(&mut self, params: &RenderParams) -> Result<(), RenderError> {
        let idle = RenderParams { candidates: 0, chains: 0, ..*params };
        let all: Vec<(Stage, u32)> = Stage::ITERATION.iter().map(|s| (*s, 1)).collect();
        self.dispatch(&idle, &all)?;
        self.gpu.save_pipeline_cache();
        Ok(())
    }

    fn start(&mut self, chain_u: &[f32], chains: &[ChainState]) -> Result<(), RenderError> {
        assert_eq!(chain_u.len(), (self.chains * self.dims) as usize);
        self.gpu.queue.write_buffer(&self.buffers.chain_u, 0, bytemuck::cast_slice(chain_u));
        self.gpu.queue.write_buffer(&self.buffers.chains, 0, bytemuck::cast_slice(chains));
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
        let mut chains: Vec<ChainState> = self.gpu.read(&self.buffers.chains, self.chains as usize)?;
        for chain in &mut chains {
            acc.drain_chain(chain);
        }
        self.gpu.queue.write_buffer(&self.buffers.chains, 0, bytemuck::cast_slice(&chains));
        Ok(())
    }

    fn describe(&self) -> String {
        self.gpu.describe()
    }
}
