//! The stages on the host: [`Stage`] walks a render's five, [`Pass`] is any kernel's compute
//! pipeline with its buffers bound by the names its declaration gives (`kernels::stage`), and
//! [`buffers`] lays out the render's buffers once for every backend.

pub mod buffers;
pub mod path_tracer;
pub mod raycast;
pub mod selftest;

use kernels::stage::{Binding, Kernel, SCENE_BINDINGS};
use shared::params::RenderParams;

use crate::gpu::{Gpu, GpuError};

/// A stage of an iteration: one kernel run as one pass, its math in `shared` and its
/// declaration (bindings, entry point `<name>_cs`) and body in `kernels/src/<name>.rs`, from
/// which both backends bind and run it. The device backend, the CPU backend, the per-pass
/// timings and their CSV all walk [`Stage::ITERATION`].
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

    /// The stage's name (its file's in `kernels/src`).
    pub fn name(self) -> &'static str {
        match self {
            Stage::Mutate => "mutate",
            Stage::Trace => "trace",
            Stage::Connect => "connect",
            Stage::Select => "select",
            Stage::Splat => "splat",
        }
    }

    /// The stage's kernel, as its declaration gives it.
    pub fn kernel(self) -> Kernel {
        use kernels::{connect, mutate, select, splat, trace};
        match self {
            Stage::Mutate => Kernel::of(mutate::ENTRY_POINT, mutate::BINDINGS, mutate::BINDS_SCENE),
            Stage::Trace => Kernel::of(trace::ENTRY_POINT, trace::BINDINGS, trace::BINDS_SCENE),
            Stage::Connect => Kernel::of(connect::ENTRY_POINT, connect::BINDINGS, connect::BINDS_SCENE),
            Stage::Select => Kernel::of(select::ENTRY_POINT, select::BINDINGS, select::BINDS_SCENE),
            Stage::Splat => Kernel::of(splat::ENTRY_POINT, splat::BINDINGS, splat::BINDS_SCENE),
        }
    }

    /// The kernel's entry point.
    pub fn entry_point(self) -> &'static str {
        self.kernel().entry_point
    }

    /// The stage's compute pass over a render's device buffers.
    pub fn pass(self, gpu: &Gpu, b: &buffers::GpuBuffers) -> Result<Pass, GpuError> {
        let k = self.kernel();
        Pass::new(gpu, k.entry_point, k.bindings, k.binds_scene, &|name| b.named(name))
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

/// A device buffer found by the name a kernel binds it by, with its element type's name.
#[derive(Clone, Copy)]
pub struct Named<'a> {
    #[allow(missing_docs)] // the buffer
    pub buffer: &'a wgpu::Buffer,
    /// `std::any::type_name` of its element.
    pub element: &'static str,
}

/// A kernel ready to dispatch: its pipeline and its buffers bound.
pub struct Pass {
    pipeline: wgpu::ComputePipeline,
    bind_groups: Vec<wgpu::BindGroup>,
    writable: Vec<bool>,
}

impl Pass {
    /// Creates the pipeline for `entry` with `bindings` in set 0 (and the scene's in set 1 when
    /// `binds_scene`), each bound to the buffer `find` gives for its name; refuses a binding
    /// with no such buffer or one whose element type is not the declared one.
    pub fn new<'b>(
        gpu: &Gpu,
        entry: &str,
        bindings: &[Binding],
        binds_scene: bool,
        find: &dyn Fn(&str) -> Option<Named<'b>>,
    ) -> Result<Self, GpuError> {
        let mut sets = vec![bindings];
        if binds_scene {
            sets.push(SCENE_BINDINGS);
        }
        let mut buffers: Vec<Vec<&'b wgpu::Buffer>> = Vec::new();
        for set in &sets {
            let mut list = Vec::new();
            for b in set.iter() {
                let problem = |problem: String| GpuError::Binding {
                    entry: entry.to_string(),
                    binding: b.name.to_string(),
                    problem,
                };
                let named = find(b.name).ok_or_else(|| problem("no buffer has that name".to_string()))?;
                if named.element != (b.element)() {
                    return Err(problem(format!(
                        "its buffer holds {} where the kernel reads {}",
                        named.element,
                        (b.element)()
                    )));
                }
                list.push(named.buffer);
            }
            buffers.push(list);
        }
        let read_only: Vec<Vec<bool>> =
            sets.iter().map(|set| set.iter().map(|b| b.access.read_only()).collect()).collect();
        let (pipeline, layouts) = gpu.pipeline(entry, &read_only)?;
        let bind_groups = layouts.iter().zip(&buffers).map(|(layout, list)| gpu.bind(layout, list)).collect();
        let writable = bindings.iter().map(|b| !b.access.read_only()).collect();
        Ok(Self { pipeline, bind_groups, writable })
    }

    /// Whether the kernel may write each of its own bindings (set 0), in binding order.
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
            gpu.dispatch(encoder, &self.pipeline, &self.bind_groups, threads, timestamps);
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
