//! The `path_tracer` pass: binds its params, the scene and the f32 image; on
//! the CPU the same per-pixel round runs over the pixels in parallel (each pixel is its own
//! output, so the pixels are split among threads rather than walked in order).

use rayon::prelude::*;
use shared::path_tracer::PathTracerParams;
use shared::ray_caster::RayCaster;
use shared::scene::Scene;

use super::buffers::GpuBuffers;
use super::{Named, Pass};
use crate::gpu::{Gpu, GpuError};

/// The GPU pass: `params` (one `PathTracerParams`) and the render's scene and image.
pub fn gpu(gpu: &Gpu, params: &wgpu::Buffer, b: &GpuBuffers) -> Result<Pass, GpuError> {
    use kernels::path_tracer::{BINDINGS, BINDS_SCENE, ENTRY_POINT};
    let find = |name: &str| match name {
        "params" => Some(Named { buffer: params, element: std::any::type_name::<PathTracerParams>() }),
        _ => b.named(name),
    };
    Pass::new(gpu, ENTRY_POINT, BINDINGS, BINDS_SCENE, &find)
}

/// The same round on the CPU: adds one round of samples to every pixel of `image` (rgb).
pub fn cpu<R: RayCaster + Sync>(params: &PathTracerParams, scene: Scene<R>, image: &mut [f32]) {
    image.par_chunks_mut(3).enumerate().for_each(|(i, px)| {
        let sum = shared::path_tracer::pixel_round(params, scene, i as u32);
        px[0] += sum.x;
        px[1] += sum.y;
        px[2] += sum.z;
    });
}
