//! The `path_tracer` pass: binds its params, the scene and the f32 image. On the CPU the same
//! round runs as a wavefront ([`round_batch`]): each thread advances [`BATCH`] paths together,
//! casting a bounce's rays of all of them at once (Embree's 16-wide packets), each path with the
//! device's arithmetic in the device's order (`shared::path_tracer::PathState`), so that the
//! image is the one the per-pixel body (`pixel_round`) makes.

use glam::Vec3;
use rayon::prelude::*;
use shared::path_tracer::{KeyedSamples, PathSamples, PathSettings, PathState, PathTracerParams, ShadowRay};
use shared::ray_caster::Hit;
use shared::scene::Scene;
use shared::triangle::NO_HIT;

use super::buffers::GpuBuffers;
use super::{Named, Pass};
use crate::caster::{HostCaster, Query};
use crate::gpu::{Gpu, GpuError};

/// Paths (pixels) a CPU thread advances together: enough to fill Embree's 16-wide packets while
/// paths end, few enough that their states stay in the core's caches.
pub const BATCH: usize = 64;

/// The GPU pass: `params` (one `PathTracerParams`) and the render's scene and image.
pub fn gpu(gpu: &Gpu, params: &wgpu::Buffer, b: &GpuBuffers) -> Result<Pass, GpuError> {
    use kernels::path_tracer::{BINDINGS, BINDS_SCENE, ENTRY_POINT};
    let find = |name: &str| match name {
        "params" => Some(Named { buffer: params, element: std::any::type_name::<PathTracerParams>() }),
        _ => b.named(name),
    };
    Pass::new(gpu, ENTRY_POINT, BINDINGS, BINDS_SCENE, &find)
}

/// The same round on the CPU: adds one round of samples to every pixel of `image` (rgb), the
/// pixels in batches of [`BATCH`] split among the threads.
pub fn cpu(params: &PathTracerParams, scene: Scene<HostCaster>, image: &mut [f32]) {
    image.par_chunks_mut(3 * BATCH).enumerate().for_each(|(b, px)| {
        round_batch(params, scene, (b * BATCH) as u32, px);
    });
}

/// Adds `params.samples` samples to each of the ≤ [`BATCH`] pixels of `image` (rgb), the
/// pixels from `first` on, summed per pixel as `shared::path_tracer::pixel_round` sums them:
/// sample by sample, each a wavefront over the pixels' paths — all their segments cast, then
/// all their shadow rays, then the next bounce of those that go on.
pub fn round_batch(params: &PathTracerParams, scene: Scene<HostCaster>, first: u32, image: &mut [f32]) {
    let count = image.len() / 3;
    assert!(count <= BATCH);
    let settings = PathSettings::from(params);
    let mut sums = [Vec3::ZERO; BATCH];
    // The batch's working set, on the thread's stack.
    let mut samples = [KeyedSamples::new(0, 0, 0); BATCH];
    let mut paths = [PathState::start(&settings, (0.0, 0.0)); BATCH];
    let mut alive = [0usize; BATCH];
    let mut queries = [Query::default(); BATCH];
    let mut hits = [Hit::NONE; BATCH];
    let mut shadows = [ShadowRay::none(); BATCH];
    let mut casting = [0usize; BATCH];
    let mut blocked = [false; BATCH];
    for i in 0..params.samples {
        let sample = params.round * params.samples_per_round + i;
        for k in 0..count {
            let pixel = first + k as u32;
            samples[k] = KeyedSamples::new(params.seed, pixel, sample);
            let jitter = samples[k].raster();
            let x = (pixel % params.width) as f32 + jitter.x;
            let y = (pixel / params.width) as f32 + jitter.y;
            paths[k] = PathState::start(&settings, (x, y));
            alive[k] = k;
        }
        let mut n = count;
        while n > 0 {
            for (q, &k) in queries.iter_mut().zip(&alive[..n]) {
                let p = &paths[k];
                *q = Query { origin: p.origin, direction: p.direction, tmin: 0.0, tmax: NO_HIT, key: p.key };
            }
            scene.caster.closest_hits(&queries[..n], &mut hits[..n]);
            let mut m = 0;
            for j in 0..n {
                let k = alive[j];
                shadows[j] = paths[k].scatter(&settings, &scene, hits[j], &samples[k]);
                if shadows[j].cast {
                    let s = &shadows[j];
                    queries[m] = Query {
                        origin: s.origin,
                        direction: s.direction,
                        tmin: 0.0,
                        tmax: s.tmax,
                        key: s.key,
                    };
                    casting[m] = j;
                    m += 1;
                }
            }
            scene.caster.occluded_all(&queries[..m], &mut blocked[..m]);
            for (&j, &blocked) in casting[..m].iter().zip(&blocked[..m]) {
                paths[alive[j]].resolve(&shadows[j], blocked);
            }
            let mut kept = 0;
            for j in 0..n {
                if paths[alive[j]].alive {
                    alive[kept] = alive[j];
                    kept += 1;
                }
            }
            n = kept;
        }
        for (sum, path) in sums.iter_mut().zip(&paths[..count]) {
            // A NaN or infinite sample is dropped, not averaged in.
            let l = path.estimate().radiance;
            if l.is_finite() {
                *sum += l;
            }
        }
    }
    for (px, sum) in image.as_chunks_mut::<3>().0.iter_mut().zip(sums) {
        px[0] += sum.x;
        px[1] += sum.y;
        px[2] += sum.z;
    }
}
