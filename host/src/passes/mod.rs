//! One file a pass: which buffers the kernel binds (in binding order, and whether it only
//! reads them), and the same kernel body run on the CPU. [`Pass`] is a compute pipeline with
//! its bind group.

pub mod buffers;
pub mod connect;
pub mod mutate;
pub mod raycast;
pub mod reference;
pub mod select;
pub mod selftest;
pub mod splat;
pub mod trace;

use shared::mmlt::RenderParams;

use crate::gpu::{Gpu, GpuError};

/// A stage of an iteration: one kernel run as one pass, found by the same name in three places
/// — its math in `shared`, its body and `<name>_cs` entry point in `kernels/src/<name>.rs`, its
/// bindings and CPU loop in `host/src/passes/<name>.rs`. The device backend, the CPU backend,
/// the per-pass timings and their CSV all walk [`Stage::ITERATION`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stage {
    /// One invocation per candidate builds its primary samples.
    Mutate,
    /// One invocation per candidate traces its two subpaths.
    Trace,
    /// One invocation per candidate connects them and weighs the path.
    Connect,
    /// One invocation per chain accepts, weighs and moves.
    Select,
    /// One invocation per splat record adds it to the image.
    Splat,
}

impl Stage {
    /// How many there are.
    pub const COUNT: usize = 5;

    /// The stages of one iteration, in order.
    pub const ITERATION: [Stage; Stage::COUNT] =
        [Stage::Mutate, Stage::Trace, Stage::Connect, Stage::Select, Stage::Splat];

    /// The stage's name (its file names in `kernels/src` and `host/src/passes`).
    pub fn name(self) -> &'static str {
        match self {
            Stage::Mutate => "mutate",
            Stage::Trace => "trace",
            Stage::Connect => "connect",
            Stage::Select => "select",
            Stage::Splat => "splat",
        }
    }

    /// The kernel's entry point.
    pub fn entry_point(self) -> &'static str {
        match self {
            Stage::Mutate => "mutate_cs",
            Stage::Trace => "trace_cs",
            Stage::Connect => "connect_cs",
            Stage::Select => "select_cs",
            Stage::Splat => "splat_cs",
        }
    }

    /// The stage's compute pass over a render's device buffers.
    pub fn pass(self, gpu: &Gpu, b: &buffers::GpuBuffers) -> Result<Pass, GpuError> {
        match self {
            Stage::Mutate => mutate::gpu(gpu, b),
            Stage::Trace => trace::gpu(gpu, b),
            Stage::Connect => connect::gpu(gpu, b),
            Stage::Select => select::gpu(gpu, b),
            Stage::Splat => splat::gpu(gpu, b),
        }
    }

    /// Its position in [`Stage::ITERATION`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// Invocations of the stage in a dispatch with `params`: one per candidate, per chain or
    /// per splat record.
    pub fn invocations(self, params: &RenderParams) -> u32 {
        match self {
            Stage::Mutate | Stage::Trace | Stage::Connect => params.candidates,
            Stage::Select => params.chains,
            Stage::Splat => kernels::splat::splat_records(params),
        }
    }
}

/// How a kernel uses a storage buffer it binds (binding i is the i-th of the list).
#[derive(Clone, Copy)]
pub enum Binding<'a> {
    /// The kernel only reads it.
    Read(&'a wgpu::Buffer),
    /// The kernel writes it (and may read it).
    Write(&'a wgpu::Buffer),
}

/// A kernel ready to dispatch: its pipeline and its buffers bound.
pub struct Pass {
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    writable: Vec<bool>,
}

impl Pass {
    /// Creates the pipeline for `entry` and binds `bindings` at 0...
    pub fn new(gpu: &Gpu, entry: &str, bindings: &[Binding]) -> Result<Self, GpuError> {
        let read_only: Vec<bool> = bindings.iter().map(|b| matches!(b, Binding::Read(_))).collect();
        let (pipeline, layout) = gpu.pipeline(entry, &read_only)?;
        let list: Vec<&wgpu::Buffer> = bindings
            .iter()
            .map(|b| match b {
                Binding::Read(b) | Binding::Write(b) => *b,
            })
            .collect();
        let bind_group = gpu.bind(&layout, &list);
        let writable = read_only.iter().map(|r| !r).collect();
        Ok(Self { pipeline, bind_group, writable })
    }

    /// Whether the kernel may write each binding, in binding order (as its layout declares).
    pub fn writable(&self) -> &[bool] {
        &self.writable
    }

    /// Records a dispatch of `threads` invocations.
    pub fn encode(&self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, threads: u32) {
        self.encode_timed(gpu, encoder, threads, None);
    }

    /// Records a dispatch of `threads` invocations whose compute pass writes `timestamps`.
    pub fn encode_timed(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        threads: u32,
        timestamps: Option<wgpu::ComputePassTimestampWrites>,
    ) {
        if threads > 0 {
            gpu.dispatch(encoder, &self.pipeline, &self.bind_group, threads, timestamps);
        } else if timestamps.is_some() {
            // Nothing to run, but the queries must still be written.
            encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: None,
                timestamp_writes: timestamps,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every stage's entry point is one the kernels module declares, named after the stage.
    #[test]
    fn stages_name_their_kernels() {
        for (i, stage) in Stage::ITERATION.iter().enumerate() {
            assert_eq!(stage.index(), i);
            assert_eq!(stage.entry_point(), format!("{}_cs", stage.name()));
            assert!(kernels::ENTRY_POINTS.contains(&stage.entry_point()));
        }
    }
}
