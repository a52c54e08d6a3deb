//! One file a pass: which buffers the kernel binds (in binding order, and whether it only
//! reads them), and the same kernel body run on the CPU. [`Pass`] is a compute pipeline with
//! its bind group.

pub mod connect;
pub mod mutate;
pub mod raycast;
pub mod reference;
pub mod select;
pub mod selftest;
pub mod splat;
pub mod trace;

use crate::gpu::{Gpu, GpuError};

/// A kernel ready to dispatch: its pipeline and its buffers bound.
pub struct Pass {
    entry: &'static str,
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
}

impl Pass {
    /// Creates the pipeline for `entry` and binds `buffers` (buffer, read-only) at 0...
    pub fn new(gpu: &Gpu, entry: &'static str, buffers: &[(&wgpu::Buffer, bool)]) -> Result<Self, GpuError> {
        let read_only: Vec<bool> = buffers.iter().map(|(_, r)| *r).collect();
        let (pipeline, layout) = gpu.pipeline(entry, &read_only)?;
        let list: Vec<&wgpu::Buffer> = buffers.iter().map(|(b, _)| *b).collect();
        let bind_group = gpu.bind(&layout, &list);
        Ok(Self { entry, pipeline, bind_group })
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

    /// The kernel's entry point.
    pub fn entry(&self) -> &'static str {
        self.entry
    }
}
