//! The path tracer (`--method pt`, and the ground truth of `smlt reference`): unidirectional path tracing with next-event estimation and
//! multiple importance sampling (power heuristic) between light sampling and BSDF sampling.
//! It shares the scene's primitives (camera, BSDFs, lights, BVH) with the renderer but none of
//! the MMLT path code, so agreement between the two is evidence for both.
//!
//! Path depth as pbrt's `maxdepth`: emission reached after v segments counts when v − 1 ≤
//! max_depth, a light sample from the v-th vertex when v ≤ max_depth. From the fifth bounce on
//! a path continues with probability [`continuation_probability`] (Russian roulette, as
//! Mitsuba 3's and pbrt's path tracers do), so deep bounces that carry little light cost little. Pixel values are the
//! mean radiance over the pixel's area (uniform jitter), the same measure as the MMLT image.
//! Random numbers are keyed by (seed, pixel, sample, vertex), so the device and the CPU compute
//! the same estimate. The path itself ([`trace_path`]) takes its uniforms from a
//! [`PathSamples`] source, so that a Metropolis chain can drive the same estimator
//! (`crate::pssmlt`). It is a [`PathState`] stepped from one ray query to the next, so that a
//! driver may also advance many paths together and cast a bounce's rays of all of them at once
//! (the CPU backend's wavefront, `host/src/passes/path_tracer.rs`).

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use glam::{Vec2, Vec3};

use crate::bsdf::Material;
use crate::bsdf::{bsdf_eval_pdf, bsdf_sample, medium_coefficient, transmittance};
use crate::camera::Camera;
use crate::cutout::blend_key;
use crate::light::emitted;
use crate::light::{is_environment, is_punctual, punctual_index, sample_light};
use crate::normals::scattering_cosine;
use crate::normals::Normals;
use crate::ray_caster::spawn;
use crate::ray_caster::{Hit, RayCaster};
use crate::rng::{self, RngKey};
use crate::scene::Scene;
use crate::surface::{material_at, normals_at};
use crate::triangle::NO_HIT;

/// What the path tracer's kernel knows (uploaded before each of its rounds: a round adds
/// `samples` samples to every pixel, and the rounds' spread estimates a reference's noise).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PathTracerParams {
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

/// The first vertex after which a path plays Russian roulette ([`continuation_probability`]):
/// the fifth bounce, Mitsuba 3's default `rr_depth`, so that the first bounces, where most of
/// an interior's light is, keep every path.
pub const ROULETTE_DEPTH: u32 = 5;

/// The probability that Russian roulette continues a path whose throughput is `beta`: its
/// largest component, at most 0.95 (Mitsuba 3's rule; a path that survives divides its
/// throughput by it, which keeps the estimate unbiased). Zero or NaN throughput ends the path.
#[inline]
pub fn continuation_probability(beta: Vec3) -> f32 {
    let largest = beta.max_element();
    if largest > 0.0 {
        largest.min(0.95)
    } else {
        0.0
    }
}

/// Where a path's uniforms come from: the path tracer's random numbers ([`KeyedSamples`]), or a
/// Metropolis chain's primary sample vector (`crate::pssmlt`). One path tracer, two sources.
pub trait PathSamples {
    /// The two uniforms of the raster position (vertex 0).
    fn raster(&self) -> Vec2;
    /// The six uniforms of vertex `v` ≥ 1: the light pick, the point on the light (2), the
    /// BSDF direction (2) and the Russian roulette (read from [`ROULETTE_DEPTH`] on).
    fn vertex(&self, v: u32) -> [f32; 6];
}

/// The path tracer's uniforms: counter-based random numbers keyed by (seed, pixel, sample,
/// vertex).
#[derive(Clone, Copy)]
pub struct KeyedSamples {
    key: RngKey,
}

impl KeyedSamples {
    /// The uniforms of sample `sample` of `pixel`.
    #[inline]
    pub fn new(seed: u32, pixel: u32, sample: u32) -> Self {
        Self { key: RngKey { seed, chain: pixel, iteration: sample, dimension: 0 } }
    }
}

impl PathSamples for KeyedSamples {
    #[inline]
    fn raster(&self) -> Vec2 {
        let a = rng::uniform4(self.key, rng::STREAM_PATH_TRACER, 0);
        Vec2::new(a[0], a[1])
    }

    #[inline]
    fn vertex(&self, v: u32) -> [f32; 6] {
        let a = rng::uniform4(self.key, rng::STREAM_PATH_TRACER, 2 * v);
        let b = rng::uniform4(self.key, rng::STREAM_PATH_TRACER, 2 * v + 1);
        [a[0], a[1], a[2], a[3], b[0], b[1]]
    }
}

/// What a path needs besides the scene and its uniforms.
#[derive(Clone, Copy)]
pub struct PathSettings {
    #[allow(missing_docs)] // named for what it is
    pub camera: Camera,
    /// Maximum number of bounces (pbrt's maxdepth).
    pub max_depth: u32,
    /// Entries of the light CDF.
    pub light_count: u32,
    /// Ray-origin offset, relative to the scene's size.
    pub epsilon: f32,
}

impl From<&PathTracerParams> for PathSettings {
    #[inline]
    fn from(p: &PathTracerParams) -> Self {
        Self { camera: p.camera, max_depth: p.max_depth, light_count: p.light_count, epsilon: p.epsilon }
    }
}

/// What [`trace_path`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathEstimate {
    /// The radiance estimate.
    pub radiance: Vec3,
    /// How many vertices' uniforms the path read ([`PathSamples::vertex`] of 1..=vertices):
    /// the uniforms of later vertices did not change the estimate.
    pub vertices: u32,
}

/// A path between two of its ray queries: the segment it casts next, and what it carries from
/// vertex to vertex. [`trace_path`] drives one path through its queries one at a time; the CPU
/// backend drives many at once (`host::passes::path_tracer`), casting a bounce's rays of all of
/// them together, with the same arithmetic for each path in the same order.
#[derive(Clone, Copy)]
pub struct PathState {
    /// Origin of the segment to cast next.
    pub origin: Vec3,
    /// Unit direction of the segment to cast next.
    pub direction: Vec3,
    /// The key of the segment's cut-out draws: from the uniforms that chose its direction.
    pub key: u32,
    /// Whether the path goes on (a segment to cast).
    pub alive: bool,
    beta: Vec3,
    radiance: Vec3,
    pdf_bsdf_prev: f32,
    // The last bounce was a delta lobe: its emission reached is not light sampling's too.
    delta_prev: bool,
    // Beer–Lambert coefficient of the medium the current segment runs through.
    sigma: Vec3,
    vertices: u32,
    v: u32,
}

/// A light sample's shadow ray from a path's vertex, and what it adds to the path's radiance when
/// nothing blocks it ([`PathState::resolve`]): the light sample's whole contribution, weighed
/// by the power heuristic against the BSDF's density of it (1 for a delta light) as it is cast.
#[derive(Clone, Copy)]
pub struct ShadowRay {
    /// Whether there is a ray to cast (false: the light sample adds nothing).
    pub cast: bool,
    #[allow(missing_docs)] // with direction and tmax: the segment o + t·d, 0 < t < tmax
    pub origin: Vec3,
    #[allow(missing_docs)]
    pub direction: Vec3,
    #[allow(missing_docs)]
    pub tmax: f32,
    /// The key of its cut-out draws.
    pub key: u32,
    // The radiance it adds where nothing blocks it.
    light: Vec3,
}

impl ShadowRay {
    /// No shadow ray.
    #[inline]
    pub fn none() -> Self {
        ShadowRay {
            cast: false,
            origin: Vec3::ZERO,
            direction: Vec3::Z,
            tmax: 0.0,
            key: 0,
            light: Vec3::ZERO,
        }
    }
}

impl PathState {
    /// A path from the camera through raster point (`x`, `y`).
    #[inline]
    pub fn start(settings: &PathSettings, (x, y): (f32, f32)) -> Self {
        let cam = settings.camera;
        PathState {
            origin: cam.origin(),
            direction: cam.direction(x, y),
            key: blend_key(Vec2::new(x, y)),
            alive: true,
            beta: Vec3::ONE,
            radiance: Vec3::ZERO,
            pdf_bsdf_prev: 0.0,
            delta_prev: false,
            sigma: Vec3::ZERO,
            vertices: 0,
            v: 1,
        }
    }

    /// What the path found so far.
    #[inline]
    pub fn estimate(&self) -> PathEstimate {
        PathEstimate { radiance: self.radiance, vertices: self.vertices }
    }

    /// Takes the answer to the path's segment (`hit`, its closest hit): adds the emission it
    /// reached, then at the vertex samples a light (the shadow ray returned, for
    /// [`PathState::resolve`]) and the BSDF for the next segment, or ends the path
    /// ([`PathState::alive`] false).
    #[inline]
    pub fn scatter<R: RayCaster, S: PathSamples>(
        &mut self,
        settings: &PathSettings,
        scene: &Scene<R>,
        hit: Hit,
        samples: &S,
    ) -> ShadowRay {
        let (origin, d, v) = (self.origin, self.direction, self.v);
        if !hit.found() {
            // The environment, reached by this segment (not from inside a medium, whose
            // transmittance over an unbounded distance is 0); after a BSDF sample it competes
            // with the previous vertex's light sample.
            let env = scene.environment;
            if env.is_present() && !(self.sigma.max_element() > 0.0) {
                let le = env.radiance(scene.environment_map, d);
                let weight = if v == 1 || self.delta_prev {
                    1.0
                } else {
                    power_heuristic(self.pdf_bsdf_prev, env.pick * env.pdf(scene.environment_map, d))
                };
                self.radiance += self.beta * le * weight;
            }
            self.alive = false;
            return ShadowRay::none();
        }
        let tri = scene.triangles[hit.triangle as usize];
        let p = origin + d * hit.t;
        let m = material_at(scene, hit.triangle, p);
        let normals = normals_at(scene, hit.triangle, p);
        // The geometric normal: emission, offsets, media (`crate::normals`); the BSDF and its
        // cosine take both.
        let n = normals.geometric;
        let wo = -d;
        if self.sigma.max_element() > 0.0 {
            self.beta *= transmittance(self.sigma, hit.t);
        }
        // Emission reached by this segment; after a BSDF sample it competes with the previous
        // vertex's light sample.
        if m.is_emissive() {
            let le = emitted(Vec3::from_array(m.emission), n, wo);
            let weight = if v == 1 || self.delta_prev {
                1.0
            } else {
                let cos_l = n.dot(wo).abs();
                let pdf_light = if cos_l > 0.0 { tri.light_area_pdf * hit.t * hit.t / cos_l } else { 0.0 };
                power_heuristic(self.pdf_bsdf_prev, pdf_light)
            };
            self.radiance += self.beta * le * weight;
        }
        if v > settings.max_depth {
            self.alive = false;
            return ShadowRay::none();
        }
        let u = samples.vertex(v);
        self.vertices = v;
        let shadow = self.light_sample(settings, scene, (p, m, normals, wo), u);
        // Continue by sampling the BSDF.
        let bs = bsdf_sample(&m, normals, wo, Vec2::new(u[3], u[4]), true);
        if !(bs.pdf > 0.0) {
            self.alive = false;
            return shadow;
        }
        self.beta *= bs.f * (scattering_cosine(normals, wo, bs.wi, true) / bs.pdf);
        if v >= ROULETTE_DEPTH {
            let q = continuation_probability(self.beta);
            if !(u[5] < q) {
                self.alive = false;
                return shadow;
            }
            self.beta /= q;
        }
        self.pdf_bsdf_prev = bs.pdf;
        self.delta_prev = bs.delta;
        self.sigma = medium_coefficient(&m, n, bs.wi);
        self.origin = spawn(p, n, bs.wi, settings.epsilon);
        self.direction = bs.wi;
        self.key = blend_key(Vec2::new(u[3], u[4]));
        self.v = v + 1;
        shadow
    }

    /// Next-event estimation from the vertex at `p` (material `m`, `normals`, towards the
    /// previous vertex `wo`): one light sample with the uniforms `u`, and its shadow ray.
    #[inline]
    fn light_sample<R: RayCaster>(
        &self,
        settings: &PathSettings,
        scene: &Scene<R>,
        (p, m, normals, wo): (Vec3, Material, Normals, Vec3),
        u: [f32; 6],
    ) -> ShadowRay {
        let n = normals.geometric;
        let ls = sample_light(scene, settings.light_count, u[0], Vec2::new(u[1], u[2]));
        let key = blend_key(Vec2::new(u[1], u[2]));
        // The light's direction, what arrives along it, its density (a delta light's: the
        // pick) and where the shadow ray ends: out of the scene's bounds towards the
        // environment, else at `target`.
        let (wi, arriving, pdf, weighted, target, beyond) = if is_environment(ls.light) {
            (-ls.n, ls.emission, ls.pdf_area, true, Vec3::ZERO, true)
        } else if is_punctual(ls.light) {
            // A delta light: no BSDF sample finds it, so the light sample takes it all.
            let inc = scene.punctual[punctual_index(ls.light) as usize].incident(p);
            (inc.wi, inc.radiance, ls.pick, false, inc.from, false)
        } else {
            let (q, nq) = (ls.p, ls.n);
            let to_light = q - p;
            let dist2 = to_light.length_squared();
            if !(dist2 > 0.0 && ls.pdf_area > 0.0) {
                return ShadowRay::none();
            }
            let wl = to_light / dist2.sqrt();
            let cos_l = nq.dot(wl).abs();
            if !(cos_l > 0.0) {
                return ShadowRay::none();
            }
            let target = spawn(q, nq, -wl, settings.epsilon);
            (wl, emitted(ls.emission, nq, -wl), ls.pdf_area * dist2 / cos_l, true, target, false)
        };
        if !(arriving.max_element() > 0.0 && pdf > 0.0) {
            return ShadowRay::none();
        }
        // One evaluation for every kind of light: each call is a copy of the material code in
        // the device's compiled stage. The BSDF's density with it, for the weight: computed for
        // every shadow ray (most of an interior's are blocked) costs less than carrying the
        // material and both directions to the blocked test, and shares the evaluation's work.
        let (f, pdf_bsdf) = bsdf_eval_pdf(&m, normals, wo, wi, true);
        if !(f.max_element() > 0.0) {
            return ShadowRay::none();
        }
        let weight = if weighted { power_heuristic(pdf, pdf_bsdf) } else { 1.0 };
        let light = self.beta * f * arriving * (scattering_cosine(normals, wo, wi, true) * weight / pdf);
        let from = spawn(p, n, wi, settings.epsilon);
        let (direction, tmax) = if beyond {
            (wi, (scene.environment.beyond(from, wi) - from).length())
        } else {
            let span = target - from;
            let len = span.length();
            if !(len > 0.0) {
                return ShadowRay::none();
            }
            (span / len, len)
        };
        ShadowRay { cast: true, origin: from, direction, tmax, key, light }
    }

    /// Takes the answer to `shadow`'s ray: its light when nothing blocks it.
    #[inline]
    pub fn resolve(&mut self, shadow: &ShadowRay, occluded: bool) {
        if shadow.cast && !occluded {
            self.radiance += shadow.light;
        }
    }
}

/// One path-traced estimate of the radiance arriving through raster point (`x`, `y`), with
/// the vertices' uniforms from `samples`: the path's queries one at a time.
#[inline]
pub fn trace_path<R: RayCaster, S: PathSamples>(
    settings: &PathSettings,
    scene: Scene<R>,
    at: (f32, f32),
    samples: &S,
) -> PathEstimate {
    let mut path = PathState::start(settings, at);
    while path.alive {
        let hit = scene.caster.closest_hit(path.origin, path.direction, 0.0, NO_HIT, path.key);
        let shadow = path.scatter(settings, &scene, hit, samples);
        if shadow.cast {
            let occluded =
                scene.caster.occluded(shadow.origin, shadow.direction, 0.0, shadow.tmax, shadow.key);
            path.resolve(&shadow, occluded);
        }
    }
    path.estimate()
}

/// One path-traced estimate of the radiance through a uniform point of pixel `pixel`.
#[inline]
pub fn pixel_sample<R: RayCaster>(
    params: &PathTracerParams,
    scene: Scene<R>,
    pixel: u32,
    sample: u32,
) -> Vec3 {
    let settings = PathSettings::from(params);
    let samples = KeyedSamples::new(params.seed, pixel, sample);
    let jitter = samples.raster();
    let x = (pixel % params.width) as f32 + jitter.x;
    let y = (pixel / params.width) as f32 + jitter.y;
    trace_path(&settings, scene, (x, y), &samples).radiance
}

/// `params.samples` samples of pixel `pixel` for round `params.round`, summed.
#[inline]
pub fn pixel_round<R: RayCaster>(params: &PathTracerParams, scene: Scene<R>, pixel: u32) -> Vec3 {
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

    /// Roulette keeps a bright path almost surely (at most 0.95), a dim one in proportion to
    /// its throughput, and ends a black or NaN one; the surviving path's 1/q keeps E[β] = β.
    #[test]
    fn continuation_follows_the_throughput() {
        assert_eq!(continuation_probability(Vec3::new(2.0, 0.1, 0.0)), 0.95);
        assert_eq!(continuation_probability(Vec3::new(0.2, 0.5, 0.1)), 0.5);
        assert_eq!(continuation_probability(Vec3::ZERO), 0.0);
        assert_eq!(continuation_probability(Vec3::splat(f32::NAN)), 0.0);
        let beta = Vec3::new(0.3, 0.2, 0.1);
        let q = continuation_probability(beta);
        let n = 100_000;
        let mut mean = Vec3::ZERO;
        for i in 0..n {
            let u = rng::uniform(RngKey { seed: 9, chain: i, iteration: 0, dimension: 0 });
            if u < q {
                mean += beta / q;
            }
        }
        let mean = mean / n as f32;
        assert!((mean - beta).abs().max_element() < 0.01 * beta.max_element(), "{mean} {beta}");
    }
}
