//! The `splat` pass: binds params and the splat records, and adds them to the f32 image (as
//! bits, with a compare-and-swap loop). On the CPU the records go straight into the f64 image.

use glam::Vec4;
use shared::layout::unpack_contribution;
use shared::mmlt::RenderParams;

use super::Pass;
use crate::gpu::{Gpu, GpuError};
use crate::render::gpu::GpuBuffers;

/// The GPU pass.
pub fn gpu(gpu: &Gpu, b: &GpuBuffers) -> Result<Pass, GpuError> {
    Pass::new(gpu, "splat_cs", &[(&b.params, true), (&b.splats, true), (&b.image, false)])
}

/// Adds the records to an f64 rgb image (what the GPU pass does, without the f32 stage).
pub fn cpu(params: &RenderParams, splats: &[Vec4], image: &mut [f64]) {
    let records = kernels::splat::splat_records(params) as usize;
    let pixels = (params.width * params.height) as usize;
    for s in &splats[..records] {
        let (rgb, pixel) = unpack_contribution(*s);
        if (pixel as usize) < pixels {
            let i = pixel as usize * 3;
            image[i] += rgb.x as f64;
            image[i + 1] += rgb.y as f64;
            image[i + 2] += rgb.z as f64;
        }
    }
}
