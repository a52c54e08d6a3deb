//! The `reference` pass: binds params, the scene and the f32 image; on the CPU the same body
//! runs over the pixels in parallel (each pixel is its own output).

use rayon::prelude::*;
use shared::path_tracer::ReferenceParams;
use shared::ray_caster::RayCaster;
use shared::scene::Scene;

use super::{Binding, Pass};
use crate::gpu::{Gpu, GpuError};

/// The GPU pass over `buffers` = [params, nodes, triangles, materials, lights, image].
pub fn gpu(gpu: &Gpu, buffers: [&wgpu::Buffer; 6]) -> Result<Pass, GpuError> {
    let [params, nodes, triangles, materials, lights, image] = buffers;
    Pass::new(
        gpu,
        "reference_cs",
        &[
            Binding::Read(params),
            Binding::Read(nodes),
            Binding::Read(triangles),
            Binding::Read(materials),
            Binding::Read(lights),
            Binding::Write(image),
        ],
    )
}

/// The same body on the CPU: adds one round of samples to every pixel of `image` (rgb).
pub fn cpu<R: RayCaster + Sync>(params: &ReferenceParams, scene: Scene<R>, image: &mut [f32]) {
    image.par_chunks_mut(3).enumerate().for_each(|(i, px)| {
        let sum = shared::path_tracer::pixel_round(params, scene, i as u32);
        px[0] += sum.x;
        px[1] += sum.y;
        px[2] += sum.z;
    });
}
