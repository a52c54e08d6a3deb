//! Device time of each pass: timestamp queries written at the start and end of every compute
//! pass where the device has them (`wgpu::Features::TIMESTAMP_QUERY`; lavapipe and NVIDIA's
//! driver both do), and otherwise the wall time of each pass submitted alone and waited for.

use crate::gpu::{Gpu, GpuError};
use crate::passes::Pass;

/// How the times were taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clock {
    /// The device's timestamps around each compute pass.
    Timestamp,
    /// Host wall time around each pass, submitted alone and waited for (includes submission).
    Wall,
}

impl std::fmt::Display for Clock {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Clock::Timestamp => "timestamp",
            Clock::Wall => "wall",
        })
    }
}

/// Runs `passes` (each with its invocation count) once, in order, and returns the seconds each
/// one took on the device, and how they were measured.
pub fn time_passes(gpu: &Gpu, passes: &[(&Pass, u32)]) -> Result<(Vec<f64>, Clock), GpuError> {
    if !gpu.features.contains(wgpu::Features::TIMESTAMP_QUERY) {
        let mut seconds = Vec::with_capacity(passes.len());
        for &(pass, threads) in passes {
            let start = std::time::Instant::now();
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            pass.encode(gpu, &mut encoder, threads);
            gpu.queue.submit([encoder.finish()]);
            gpu.wait()?;
            seconds.push(start.elapsed().as_secs_f64());
        }
        return Ok((seconds, Clock::Wall));
    }
    let count = 2 * passes.len() as u32;
    let queries = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
        label: Some("pass timestamps"),
        ty: wgpu::QueryType::Timestamp,
        count,
    });
    let resolved = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("resolved timestamps"),
        size: count as u64 * 8,
        usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    for (i, &(pass, threads)) in passes.iter().enumerate() {
        let writes = wgpu::ComputePassTimestampWrites {
            query_set: &queries,
            beginning_of_pass_write_index: Some(2 * i as u32),
            end_of_pass_write_index: Some(2 * i as u32 + 1),
        };
        pass.encode_timed(gpu, &mut encoder, threads, Some(writes));
    }
    encoder.resolve_query_set(&queries, 0..count, &resolved, 0);
    gpu.queue.submit([encoder.finish()]);
    let ticks: Vec<u64> = gpu.read(&resolved, count as usize)?;
    let period = gpu.queue.get_timestamp_period() as f64 * 1e-9;
    Ok((ticks.chunks(2).map(|t| t[1].wrapping_sub(t[0]) as f64 * period).collect(), Clock::Timestamp))
}
