//! The `path_tracer` pass (`--method pt`, `smlt reference`): one invocation per pixel adds `params.samples` path-traced samples
//! (`shared::path_tracer`, round `params.round`) to its own pixel of an f32 image, which the
//! host drains into f64 after every pass.

use shared::path_tracer::{pixel_round, PathTracerParams};
use shared::ray_caster::RayCaster;

stage! {
    /// What `path_tracer` binds.
    pub struct PathTracerIo<'a> over scene R {
        0 params: uniform PathTracerParams,
        /// The round's f32 rgb image, three values a pixel.
        1 image: write f32,
    }
    entry "path_tracer_cs" (threads 64) => path_tracer;
}

/// The kernel body for pixel `i`.
pub fn path_tracer<R: RayCaster>(i: usize, io: PathTracerIo<R>) {
    let PathTracerIo { params, scene, image } = io;
    if i as u32 >= params.width * params.height {
        return;
    }
    let sum = pixel_round(params, scene, i as u32);
    image[i * 3] += sum.x;
    image[i * 3 + 1] += sum.y;
    image[i * 3 + 2] += sum.z;
}
