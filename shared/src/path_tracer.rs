//! The reference estimator: unidirectional path tracing with next-event estimation and
//! multiple importance sampling (power heuristic) between light sampling and BSDF sampling.
//! It shares the scene's primitives (camera, BSDFs, lights, BVH) with the renderer but none of
//! the MMLT path code, so agreement between the two is evidence for both.
//!
//! Path depth as pbrt's `maxdepth`: emission reached after v segments counts when v − 1 ≤
//! max_depth, a light sample from the v-th vertex when v ≤ max_depth. Pixel values are the
//! mean radiance over the pixel's area (uniform jitter), the same measure as the MMLT image.
//! Random numbers are keyed by (seed, pixel, sample, vertex), so the device and the CPU compute
//! the same estimate.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use glam::{Vec2, Vec3};

use crate::bsdf::{bsdf_eval, bsdf_pdf, bsdf_sample};
use crate::camera::Camera;
use crate::light::emitted;
use crate::mmlt::{sample_light, spawn};
use crate::ray_caster::RayCaster;
use crate::rng::{self, RngKey};
use crate::scene::Scene;
use crate::triangle::NO_HIT;

/// What the reference kernel knows (uploaded before each of its rounds: a round adds
/// `samples` samples to every pixel, and the rounds' spread estimates the reference's noise).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ReferenceParams {
    #[allow(missing_docs)] // named for what it is
    pub camera: Camera,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Maximum number of bounces (pbrt's maxdepth).
    pub max_depth: u32,
    /// The `seed` word of every random key.
    pub seed: u32,
    /// Entries of the light CDF.
    pub light_count: u32,
    /// Ray-origin offset, relative to the scene's size.
    pub epsilon: f32,
    /// Samples per pixel in this round.
    pub samples: u32,
    /// The round: its samples are numbers `round · samples_per_round + i`.
    pub round: u32,
    /// Samples per pixel of a full round (the numbering stride).
    pub samples_per_round: u32,
}

/// Power heuristic weight of a technique with density `a` against one with density `b`.
#[inline]
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 {
        a2 / (a2 + b2)
    } else {
        0.0
    }
}

/// The eight uniforms of vertex `v` of sample `sample` of `pixel`.
#[inline]
fn vertex_uniforms(params: &ReferenceParams, pixel: u32, sample: u32, v: u32) -> [f32; 8] {
    let key = RngKey { seed: params.seed, chain: pixel, iteration: sample, dimension: 0 };
    let a = rng::uniform4(key, rng::STREAM_REFERENCE, 2 * v);
    let b = rng::uniform4(key, rng::STREAM_REFERENCE, 2 * v + 1);
    [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]]
}

/// One path-traced estimate of the radiance through a uniform point of pixel `pixel`.
#[inline]
pub fn pixel_sample<R: RayCaster>(
    params: &ReferenceParams,
    scene: Scene<R>,
    pixel: u32,
    sample: u32,
) -> Vec3 {
    let cam = params.camera;
    let width = params.width;
    let u0 = vertex_uniforms(params, pixel, sample, 0);
    let x = (pixel % width) as f32 + u0[0];
    let y = (pixel / width) as f32 + u0[1];
    let mut d = cam.direction(x, y);
    let mut origin = cam.origin();
    let mut beta = Vec3::ONE;
    let mut radiance = Vec3::ZERO;
    let mut pdf_bsdf_prev = 0.0f32;
    let mut v = 1u32;
    while v <= params.max_depth + 1 {
        let hit = scene.caster.closest_hit(origin, d, 0.0, NO_HIT);
        if !hit.found() {
            break;
        }
        let tri = scene.triangles[hit.triangle as usize];
        let m = scene.materials[tri.material as usize];
        let p = origin + d * hit.t;
        let n = tri.normal();
        let wo = -d;
        // Emission reached by this segment; after a BSDF sample it competes with the previous
        // vertex's light sample.
        if m.is_emissive() {
            let le = emitted(Vec3::from_array(m.emission), n, wo);
            let weight = if v == 1 {
                1.0
            } else {
                let cos_l = n.dot(wo).abs();
                let pdf_light = if cos_l > 0.0 { tri.light_area_pdf * hit.t * hit.t / cos_l } else { 0.0 };
                power_heuristic(pdf_bsdf_prev, pdf_light)
            };
            radiance += beta * le * weight;
        }
        if v > params.max_depth {
            break;
        }
        let u = vertex_uniforms(params, pixel, sample, v);
        // Next-event estimation: one light sample from this vertex.
        let ls = sample_light(
            scene.lights,
            params.light_count,
            scene.triangles,
            scene.materials,
            u[0],
            Vec2::new(u[1], u[2]),
        );
        let q = Vec3::from_array(ls.vertex.p);
        let nq = Vec3::from_array(ls.vertex.n);
        let to_light = q - p;
        let dist2 = to_light.length_squared();
        if dist2 > 0.0 && ls.vertex.pdf_fwd > 0.0 {
            let dist = dist2.sqrt();
            let wl = to_light / dist;
            let le = emitted(ls.emission, nq, -wl);
            let f = bsdf_eval(&m, n, wo, wl);
            let cos_l = nq.dot(wl).abs();
            if le.max_element() > 0.0 && f.max_element() > 0.0 && cos_l > 0.0 {
                let pdf_light = ls.vertex.pdf_fwd * dist2 / cos_l;
                let from = spawn(p, n, wl, params.epsilon);
                let target = spawn(q, nq, -wl, params.epsilon);
                let span = target - from;
                let len = span.length();
                if !scene.caster.occluded(from, span / len, 0.0, len) {
                    let weight = power_heuristic(pdf_light, bsdf_pdf(&m, n, wo, wl));
                    radiance += beta * f * le * (n.dot(wl).abs() * weight / pdf_light);
                }
            }
        }
        // Continue by sampling the BSDF.
        let bs = bsdf_sample(&m, n, wo, Vec2::new(u[3], u[4]));
        if !(bs.pdf > 0.0) {
            break;
        }
        beta *= bs.f * (bs.wi.dot(n).abs() / bs.pdf);
        pdf_bsdf_prev = bs.pdf;
        origin = spawn(p, n, bs.wi, params.epsilon);
        d = bs.wi;
        v += 1;
    }
    radiance
}

/// `params.samples` samples of pixel `pixel` for round `params.round`, summed.
#[inline]
pub fn pixel_round<R: RayCaster>(params: &ReferenceParams, scene: Scene<R>, pixel: u32) -> Vec3 {
    let mut sum = Vec3::ZERO;
    let mut i = 0;
    while i < params.samples {
        let l = pixel_sample(params, scene, pixel, params.round * params.samples_per_round + i);
        // A NaN or infinite sample is dropped, not averaged in.
        if l.is_finite() {
            sum += l;
        }
        i += 1;
    }
    sum
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    #[test]
    fn power_heuristic_weights_sum_to_one() {
        for (a, b) in [(1.0f32, 1.0f32), (2.0, 0.5), (1e-20, 3.0), (5.0, 0.0)] {
            assert!((power_heuristic(a, b) + power_heuristic(b, a) - 1.0).abs() < 1e-6);
        }
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
        assert_eq!(power_heuristic(2.0, 0.0), 1.0);
    }
}
