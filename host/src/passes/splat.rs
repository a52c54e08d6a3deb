//! The `splat` pass: binds params and the splat records, and adds them to the f32 image (as
//! bits, with a compare-and-swap loop). On the CPU the same body adds them to the f64 image.

use glam::Vec4;
use kernels::splat::splat;
use shared::mmlt::RenderParams;

use super::buffers::GpuBuffers;
use super::{Binding, Pass, Stage};
use crate::gpu::{Gpu, GpuError};

/// The pass on `gpu`, binding the buffers of `b` that the module doc lists.
pub fn gpu(gpu: &Gpu, b: &GpuBuffers) -> Result<Pass, GpuError> {
    Pass::new(
        gpu,
        Stage::Splat.entry_point(),
        &[Binding::Read(&b.params), Binding::Read(&b.iteration.splats), Binding::Write(&b.image)],
    )
}

/// The same body on the CPU, over every record, into an f64 rgb image.
pub fn cpu(params: &RenderParams, splats: &[Vec4], image: &mut [f64]) {
    for i in 0..Stage::Splat.invocations(params) as usize {
        splat(i, params, splats, image);
    }
}
