//! Multiplexed MLT path sampling (Hachisuka et al. 2014, as pbrt-v3's `MLTIntegrator`): a chain
//! of fixed path depth k (bounces; k + 1 segments) maps its primary samples u to one of the
//! k + 2 ways of splitting the path into a light subpath of s vertices and a camera subpath of
//! t = k + 2 − s vertices, traces both, connects only their end points, and weighs the result
//! with the balance heuristic over all k + 2 techniques:
//!
//! `F(u) = f(x̄) · w_s(x̄) · (k + 2) / p_s(x̄)`, scalar target `c(u) = luminance(F)`.
//!
//! The technique is chosen by u[0] (so mutations can change it). s = 1 resamples the light
//! point with its own samples and t = 1 connects to the pinhole, landing on the pixel the
//! light subpath projects to. t = 0 is impossible with a pinhole and is excluded.
//!
//! The stages of the wavefront live here as plain functions: [`trace_candidate`] builds both
//! subpaths into the vertex buffer (kernel `trace`), [`connect_candidate`] makes the connection
//! and the MIS weight (kernel `connect`).
//!
//! **Vertex densities.** Each vertex stores `pdf_fwd`, the area density with which its own
//! subpath generated it, and `pdf_rev`, the area density with which the other subpath would
//! have; the balance heuristic is `1 / (1 + Σ_{s'≠s} p_{s'}/p_s)`, the ratios being running
//! products of `pdf_rev/pdf_fwd` along each subpath (pbrt-v3's `MISWeight`, here without the
//! delta remapping since no material or light is a delta distribution). The connection changes
//! `pdf_rev` of the two last vertices of each subpath; they are recomputed in the connection.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use core::f32::consts::PI;
use glam::{Vec2, Vec3, Vec4};

use crate::bsdf::{bsdf_eval, bsdf_pdf, bsdf_sample, cosine_hemisphere, Material};
use crate::bvh::{closest_hit, occluded, BvhNode, Triangle};
use crate::camera::Camera;
use crate::layout::{pack_contribution, soa_index};
use crate::light::{emitted, pick_light, uniform_triangle, LightEntry};
use crate::mutation::MutationParams;

/// Vertex kind: the pinhole.
pub const KIND_CAMERA: u32 = 0;
/// Vertex kind: a point on a light, as the origin of a light subpath.
pub const KIND_LIGHT: u32 = 1;
/// Vertex kind: a scattering surface point (which may also emit).
pub const KIND_SURFACE: u32 = 2;

/// Dimension of u that picks the technique.
pub const DIM_TECHNIQUE: u32 = 0;
/// Dimensions (2) of the raster position.
pub const DIM_RASTER: u32 = 1;
/// Dimension picking the light of a light subpath.
pub const DIM_LIGHT_PICK: u32 = 3;
/// Dimensions (2) of the point on it.
pub const DIM_LIGHT_POINT: u32 = 4;
/// Dimensions (2) of the direction leaving it.
pub const DIM_LIGHT_DIRECTION: u32 = 6;
/// Dimension picking the light resampled for s = 1.
pub const DIM_CONNECT_PICK: u32 = 8;
/// Dimensions (2) of the point on it.
pub const DIM_CONNECT_POINT: u32 = 9;
/// First dimension of the per-bounce samples.
pub const DIM_BOUNCES: u32 = 11;

/// Number of primary sample dimensions for paths of up to `max_depth` bounces: the fixed
/// ones plus two per bounce on each subpath.
#[inline]
pub fn sample_dimensions(max_depth: u32) -> u32 {
    DIM_BOUNCES + 4 * max_depth
}

/// Whether a path of `depth` bounces reads any of dimensions `first .. first + count`: the
/// fixed dimensions, and two per bounce on each subpath up to `depth` (a camera subpath of t ≤
/// depth + 2 vertices samples at most depth bounces, a light subpath of s ≤ depth + 1 fewer).
/// Small steps keep a chain's depth and a large step draws every dimension afresh, so mutating
/// the dimensions that a candidate's depth never reads changes nothing the chain can see; the
/// `mutate` pass skips them.
#[inline]
pub fn dimensions_used(first: u32, count: u32, depth: u32, max_depth: u32) -> bool {
    let end = first + count;
    let camera_end = DIM_BOUNCES + 2 * depth;
    let light_start = DIM_BOUNCES + 2 * max_depth;
    first < camera_end || (end > light_start && first < light_start + 2 * depth)
}

/// First of the two dimensions of bounce `i` (0-based) on the camera (side 0) or light
/// (side 1) subpath.
#[inline]
pub fn bounce_dimension(side: u32, bounce: u32, max_depth: u32) -> u32 {
    DIM_BOUNCES + side * 2 * max_depth + 2 * bounce
}

/// The technique for u[0] at depth k: `s = min(⌊u·(k+2)⌋, k+1)` light vertices, t = k + 2 − s.
#[inline]
pub fn technique(u0: f32, depth: u32) -> (u32, u32) {
    let n = depth + 2;
    let s = ((u0 * n as f32) as u32).min(n - 1);
    (s, n - s)
}

/// Luminance (Rec. 709) of a linear RGB value: the scalar target c.
#[inline]
pub fn luminance(rgb: Vec3) -> f32 {
    0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z
}

/// Mode of a render dispatch: advancing chains.
pub const MODE_CHAINS: u32 = 0;
/// Mode of a render dispatch: bootstrap (fresh samples, depth = sample index mod (k_max + 1)).
pub const MODE_BOOTSTRAP: u32 = 1;
/// Iteration word of the random keys of bootstrap samples.
pub const BOOTSTRAP_ITERATION: u32 = u32::MAX;

/// Dimension `dim` of bootstrap sample `sample`: a fresh uniform (the host regenerates the
/// chosen samples' vectors with this same function to start the chains).
#[inline]
pub fn bootstrap_sample(seed: u32, sample: u32, dim: u32) -> f32 {
    crate::rng::uniform_dim(bootstrap_key(seed, sample), crate::rng::STREAM_LARGE_STEP, dim)
}

/// The random key of bootstrap sample `sample`.
#[inline]
pub fn bootstrap_key(seed: u32, sample: u32) -> crate::rng::RngKey {
    crate::rng::RngKey { seed, chain: sample, iteration: BOOTSTRAP_ITERATION, dimension: 0 }
}

/// Everything a pass needs to know about the render (uploaded before each dispatch).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct RenderParams {
    /// The camera.
    pub camera: Camera,
    /// The mutation schedule.
    pub mutation: MutationParams,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Maximum number of bounces (pbrt's maxdepth).
    pub max_depth: u32,
    /// Primary sample dimensions, [`sample_dimensions`] of `max_depth`.
    pub dims: u32,
    /// Number of chains N.
    pub chains: u32,
    /// Number of candidates in this dispatch (N · candidates per chain, or bootstrap samples).
    pub candidates: u32,
    /// Speculative tree depth d (1 = naive parallel MMLT).
    pub tree_depth: u32,
    /// Iteration of the chains.
    pub iteration: u32,
    /// The user's seed.
    pub seed: u32,
    /// Entries of the light CDF.
    pub light_count: u32,
    /// [`MODE_CHAINS`] or [`MODE_BOOTSTRAP`].
    pub mode: u32,
    /// Global index of the first bootstrap sample of this dispatch.
    pub sample_offset: u32,
    /// Ray-origin offset, relative to the scene's size.
    pub epsilon: f32,
    /// [`METHOD_TREE`] or [`METHOD_REJECT_CHAIN`].
    pub method: u32,
    /// Reject-chain length l (proposals per chain and iteration).
    pub reject_length: u32,
    /// Padding.
    pub _pad: u32,
}

/// Chains evaluate a speculative tree of depth `tree_depth` (1: the naive method).
pub const METHOD_TREE: u32 = 0;
/// Chains evaluate a reject chain of `reject_length` proposals.
pub const METHOD_REJECT_CHAIN: u32 = 1;

impl RenderParams {
    /// Candidates traced per chain and iteration: 2^d − 1 or l.
    #[inline]
    pub fn candidates_per_chain(&self) -> u32 {
        if self.method == METHOD_REJECT_CHAIN {
            self.reject_length
        } else {
            crate::tree::candidate_count(self.tree_depth)
        }
    }

    /// Distinct states (splat records) per chain: the current state and every candidate.
    #[inline]
    pub fn states_per_chain(&self) -> u32 {
        self.candidates_per_chain() + 1
    }
}

/// The state of one chain besides its primary samples (uploaded and updated on the device).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ChainState {
    /// The current state's contribution F (rgb) and pixel (bits of w).
    pub contribution: [f32; 4],
    /// Path depth k of the chain.
    pub depth: u32,
    /// Expected number of accepted steps so far.
    pub accepted: f32,
    /// Candidates rejected because their contribution was NaN or infinite.
    pub invalid: u32,
    /// Expected Markov steps advanced since the host last drained the image (the splat weight
    /// written: d per iteration for a tree, Σ R_i for a reject chain).
    pub steps: f32,
}

/// One subpath vertex (stored SoA: slot i of candidate k at `k + i·C`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PathVertex {
    /// Position.
    pub p: [f32; 3],
    /// [`KIND_CAMERA`], [`KIND_LIGHT`] or [`KIND_SURFACE`].
    pub kind: u32,
    /// Geometric normal (the camera's: its view direction).
    pub n: [f32; 3],
    /// Material index.
    pub material: u32,
    /// Throughput of the subpath up to this vertex.
    pub beta: [f32; 3],
    /// Area density with which this vertex's own subpath generated it.
    pub pdf_fwd: f32,
    /// Area density with which the other subpath would generate it.
    pub pdf_rev: f32,
    /// Triangle slot the vertex lies on.
    pub triangle: u32,
    /// Padding.
    pub _pad: [u32; 2],
}

impl PathVertex {
    fn position(&self) -> Vec3 {
        Vec3::from_array(self.p)
    }
    fn normal(&self) -> Vec3 {
        Vec3::from_array(self.n)
    }
    fn throughput(&self) -> Vec3 {
        Vec3::from_array(self.beta)
    }
}

/// What tracing a candidate produced.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PathInfo {
    /// Light subpath vertices of the technique.
    pub s: u32,
    /// Camera subpath vertices of the technique.
    pub t: u32,
    /// Camera vertices actually generated (fewer when the path left the scene).
    pub camera_vertices: u32,
    /// Light vertices actually generated (0 for s ≤ 1: s = 1 is resampled at the connection).
    pub light_vertices: u32,
    /// Pixel of the raster sample.
    pub pixel: u32,
    /// Path depth k.
    pub depth: u32,
    /// Padding.
    pub _pad: [u32; 2],
}

/// Slot of vertex `i` of a subpath in a candidate's `max_depth + 2` slots: camera vertices
/// from the front, light vertices from the back (s + t ≤ max_depth + 2, so they never meet).
#[inline]
pub fn vertex_slot(side: u32, i: u32, max_depth: u32) -> u32 {
    if side == 0 {
        i
    } else {
        max_depth + 1 - i
    }
}

/// Slots per candidate in the vertex buffer.
#[inline]
pub fn vertex_slots(max_depth: u32) -> u32 {
    max_depth + 2
}

/// A ray origin moved off the surface at `p` (normal `n`) to the side `d` leaves on.
#[inline]
pub fn spawn(p: Vec3, n: Vec3, d: Vec3, epsilon: f32) -> Vec3 {
    let scale = epsilon * (1.0 + p.abs().max_element());
    if n.dot(d) >= 0.0 {
        p + n * scale
    } else {
        p - n * scale
    }
}

/// Converts a solid-angle density at `from` into an area density at `to` (with normal `n`,
/// whose cosine is used only when `to` lies on a surface).
#[inline]
pub fn convert_density(pdf: f32, from: Vec3, to: Vec3, n: Vec3, on_surface: bool) -> f32 {
    let w = to - from;
    let d2 = w.length_squared();
    if !(d2 > 0.0) {
        return 0.0;
    }
    let mut out = pdf / d2;
    if on_surface {
        out *= n.dot(w).abs() / d2.sqrt();
    }
    out
}

/// Read access to one candidate's primary samples in the SoA candidate buffer.
#[derive(Clone, Copy)]
pub struct Samples {
    /// The candidate.
    pub candidate: u32,
    /// Candidates in the buffer (the SoA stride).
    pub count: u32,
}

impl Samples {
    /// u[dim].
    #[inline]
    pub fn get(&self, u: &[f32], dim: u32) -> f32 {
        u[soa_index(self.candidate, dim, self.count)]
    }

    /// (u[dim], u[dim + 1]).
    #[inline]
    pub fn get2(&self, u: &[f32], dim: u32) -> Vec2 {
        Vec2::new(self.get(u, dim), self.get(u, dim + 1))
    }
}

/// A point sampled on the lights.
#[derive(Clone, Copy, Debug, Default)]
pub struct LightSample {
    /// The vertex (kind LIGHT, beta = emission / area density, pdf_fwd = area density).
    pub vertex: PathVertex,
    /// Its emission.
    pub emission: Vec3,
}

/// Picks a light point from `u_pick` and `u_point` (area density `triangle.light_area_pdf`).
#[inline]
pub fn sample_light(
    lights: &[LightEntry],
    light_count: u32,
    tris: &[Triangle],
    materials: &[Material],
    u_pick: f32,
    u_point: Vec2,
) -> LightSample {
    let entry = lights[pick_light(lights, light_count, u_pick) as usize];
    let tri = tris[entry.triangle as usize];
    let b = uniform_triangle(u_point);
    let emission = Vec3::from_array(materials[tri.material as usize].emission);
    let pdf = tri.light_area_pdf;
    let beta = if pdf > 0.0 { emission / pdf } else { Vec3::ZERO };
    LightSample {
        vertex: PathVertex {
            p: tri.point(b.x, b.y).to_array(),
            kind: KIND_LIGHT,
            n: tri.normal().to_array(),
            material: tri.material,
            beta: beta.to_array(),
            pdf_fwd: pdf,
            pdf_rev: 0.0,
            triangle: entry.triangle,
            _pad: [0; 2],
        },
        emission,
    }
}

/// The scene as the passes see it (all slices are device buffers).
#[derive(Clone, Copy)]
pub struct Scene<'a> {
    /// BVH nodes.
    pub nodes: &'a [BvhNode],
    /// Triangles in BVH order.
    pub triangles: &'a [Triangle],
    /// Materials.
    pub materials: &'a [Material],
    /// Light-selection CDF.
    pub lights: &'a [LightEntry],
}

/// Extends a subpath from its first vertex (already stored) to at most `max_vertices`
/// vertices by tracing rays and sampling BSDFs, storing each vertex and the reverse density of
/// its predecessor. Returns the number of vertices the subpath has.
#[allow(clippy::too_many_arguments)]
#[inline]
fn random_walk(
    params: &RenderParams,
    scene: Scene,
    u: &[f32],
    samples: Samples,
    side: u32,
    first: PathVertex,
    direction: Vec3,
    throughput: Vec3,
    pdf_direction: f32,
    max_vertices: u32,
    vertices: &mut [PathVertex],
) -> u32 {
    let k = params.max_depth;
    let mut prev = first;
    let mut count = 1u32;
    let mut d = direction;
    let mut beta = throughput;
    let mut pdf_dir = pdf_direction;
    let mut origin = if first.kind == KIND_CAMERA {
        first.position()
    } else {
        spawn(first.position(), first.normal(), d, params.epsilon)
    };
    while count < max_vertices {
        let hit = closest_hit(scene.nodes, scene.triangles, origin, d, 0.0, crate::bvh::NO_HIT);
        if !hit.found() {
            break;
        }
        let tri = scene.triangles[hit.triangle as usize];
        let p = origin + d * hit.t;
        let n = tri.normal();
        // The forward density converts onto the new vertex, which always lies on a surface.
        let v = PathVertex {
            p: p.to_array(),
            kind: KIND_SURFACE,
            n: n.to_array(),
            material: tri.material,
            beta: beta.to_array(),
            pdf_fwd: convert_density(pdf_dir, prev.position(), p, n, true),
            pdf_rev: 0.0,
            triangle: hit.triangle,
            _pad: [0; 2],
        };
        vertices[soa_index(samples.candidate, vertex_slot(side, count, k), samples.count)] = v;
        count += 1;
        if count >= max_vertices {
            break;
        }
        let m = scene.materials[tri.material as usize];
        let wo = -d;
        let bounce = count - 2;
        let bs = bsdf_sample(&m, n, wo, samples.get2(u, bounce_dimension(side, bounce, k)));
        if !(bs.pdf > 0.0) {
            break;
        }
        beta *= bs.f * (bs.wi.dot(n).abs() / bs.pdf);
        // The density of the reverse walk arriving at the predecessor.
        let pdf_back = bsdf_pdf(&m, n, bs.wi, wo);
        prev.pdf_rev = convert_density(pdf_back, p, prev.position(), prev.normal(), prev.kind != KIND_CAMERA);
        vertices[soa_index(samples.candidate, vertex_slot(side, count - 2, k), samples.count)] = prev;
        prev = v;
        d = bs.wi;
        pdf_dir = bs.pdf;
        origin = spawn(p, n, d, params.epsilon);
    }
    count
}

/// The `trace` stage for one candidate: picks the technique, then builds the camera subpath
/// (t vertices, the pinhole first) and, for s ≥ 2, the light subpath (s vertices, a light
/// point first) into the vertex buffer.
#[inline]
pub fn trace_candidate(
    params: &RenderParams,
    scene: Scene,
    u: &[f32],
    samples: Samples,
    depth: u32,
    vertices: &mut [PathVertex],
) -> PathInfo {
    let k = params.max_depth;
    let cam = params.camera;
    let (s, t) = technique(samples.get(u, DIM_TECHNIQUE), depth);
    let raster = samples.get2(u, DIM_RASTER) * Vec2::new(cam.width, cam.height);
    let pixel = cam.pixel(raster.x, raster.y);
    let camera_vertex = PathVertex {
        p: cam.position,
        kind: KIND_CAMERA,
        n: cam.forward,
        beta: [1.0; 3],
        pdf_fwd: 1.0,
        ..Default::default()
    };
    vertices[soa_index(samples.candidate, vertex_slot(0, 0, k), samples.count)] = camera_vertex;
    let mut camera_vertices = 1;
    if t >= 2 {
        let d = cam.direction(raster.x, raster.y);
        let pdf = cam.pdf_direction(d);
        camera_vertices =
            random_walk(params, scene, u, samples, 0, camera_vertex, d, Vec3::ONE, pdf, t, vertices);
    }
    let mut light_vertices = 0;
    if s >= 2 {
        let ls = sample_light(
            scene.lights,
            params.light_count,
            scene.triangles,
            scene.materials,
            samples.get(u, DIM_LIGHT_PICK),
            samples.get2(u, DIM_LIGHT_POINT),
        );
        let v0 = ls.vertex;
        vertices[soa_index(samples.candidate, vertex_slot(1, 0, k), samples.count)] = v0;
        light_vertices = 1;
        if v0.pdf_fwd > 0.0 {
            let n = v0.normal();
            let d = cosine_hemisphere(n, samples.get2(u, DIM_LIGHT_DIRECTION));
            let pdf = n.dot(d).max(0.0) / PI;
            if pdf > 0.0 {
                // beta = Le · cos / (p_A · p_dir) = Le · π / p_A.
                let beta = ls.emission * (PI / v0.pdf_fwd);
                light_vertices = random_walk(params, scene, u, samples, 1, v0, d, beta, pdf, s, vertices);
            }
        }
    }
    PathInfo { s, t, camera_vertices, light_vertices, pixel, depth, _pad: [0; 2] }
}

/// The density of `from` (with predecessor `before`, or a light origin when `from` is a
/// light endpoint) generating `to`, as an area density at `to`.
#[inline]
fn vertex_pdf(scene: Scene, camera: &Camera, before: Vec3, from: &PathVertex, to: &PathVertex) -> f32 {
    let p = from.position();
    let w = (to.position() - p).normalize_or_zero();
    let pdf_dir = if from.kind == KIND_CAMERA {
        camera.pdf_direction(w)
    } else if from.kind == KIND_LIGHT {
        from.normal().dot(w).max(0.0) / PI
    } else {
        let m = scene.materials[from.material as usize];
        bsdf_pdf(&m, from.normal(), (before - p).normalize_or_zero(), w)
    };
    convert_density(pdf_dir, p, to.position(), to.normal(), to.kind != KIND_CAMERA)
}

/// Density of a camera-subpath end point `pt` that lies on a light being the light's origin.
#[inline]
fn light_origin_pdf(scene: Scene, v: &PathVertex) -> f32 {
    scene.triangles[v.triangle as usize].light_area_pdf
}

/// Ratio p_rev / p_fwd of one vertex, 0 when it has no forward density.
#[inline]
fn density_ratio(rev: f32, fwd: f32) -> f32 {
    if fwd > 0.0 {
        rev / fwd
    } else {
        0.0
    }
}

/// The result of the `connect` stage for one candidate.
#[derive(Clone, Copy, Debug, Default)]
pub struct Connection {
    /// F = f · w_s · (k + 2) / p_s (rgb).
    pub contribution: Vec3,
    /// The pixel it lands on.
    pub pixel: u32,
    /// The balance-heuristic weight w_s.
    pub mis_weight: f32,
}

/// The `connect` stage for one candidate: connects the end points of the two subpaths (one
/// shadow ray), computes the unweighted contribution, the balance-heuristic weight over all
/// techniques, and F.
#[inline]
pub fn connect_candidate(
    params: &RenderParams,
    scene: Scene,
    u: &[f32],
    samples: Samples,
    info: &PathInfo,
    vertices: &[PathVertex],
) -> Connection {
    let k = params.max_depth;
    let cam = params.camera;
    let s = info.s;
    let t = info.t;
    let none = Connection { contribution: Vec3::ZERO, pixel: info.pixel, mis_weight: 0.0 };
    if t > info.camera_vertices || (s >= 2 && s > info.light_vertices) {
        return none;
    }
    let at =
        |side: u32, i: u32| vertices[soa_index(samples.candidate, vertex_slot(side, i, k), samples.count)];
    let mut pixel = info.pixel;
    let zero = PathVertex::default();
    // The four vertices around the connection (pt, pt−, qs, qs−), possibly resampled.
    let mut pt = if t >= 1 { at(0, t - 1) } else { zero };
    let pt_minus = if t >= 2 { at(0, t - 2) } else { zero };
    let mut qs = if s >= 2 { at(1, s - 1) } else { zero };
    let qs_minus = if s >= 2 { at(1, s - 2) } else { zero };
    let mut l = Vec3::ZERO;
    if s == 0 {
        // The camera subpath found a light by itself.
        let m = scene.materials[pt.material as usize];
        if pt.kind == KIND_SURFACE && m.is_emissive() {
            let w = (pt_minus.position() - pt.position()).normalize_or_zero();
            l = pt.throughput() * emitted(Vec3::from_array(m.emission), pt.normal(), w);
        }
    } else {
        if s == 1 {
            qs = sample_light(
                scene.lights,
                params.light_count,
                scene.triangles,
                scene.materials,
                samples.get(u, DIM_CONNECT_PICK),
                samples.get2(u, DIM_CONNECT_POINT),
            )
            .vertex;
        }
        let qp = qs.position();
        if t == 1 {
            // Connect the light subpath's end to the pinhole.
            let to_cam = cam.origin() - qp;
            let dist2 = to_cam.length_squared();
            let w = to_cam / dist2.sqrt();
            let r = cam.raster(-w);
            if r.inside && dist2 > 0.0 {
                pixel = cam.pixel(r.x, r.y);
                let f = if s == 1 {
                    if qs.normal().dot(w) > 0.0 {
                        Vec3::ONE
                    } else {
                        Vec3::ZERO
                    }
                } else {
                    let m = scene.materials[qs.material as usize];
                    bsdf_eval(&m, qs.normal(), (qs_minus.position() - qp).normalize_or_zero(), w)
                };
                let g = qs.normal().dot(w).abs() * r.cos_theta / dist2;
                l = qs.throughput() * f * (cam.importance(-w) * g);
            }
            pt = PathVertex {
                p: cam.position,
                kind: KIND_CAMERA,
                n: cam.forward,
                pdf_fwd: 1.0,
                ..Default::default()
            };
        } else if pt.kind == KIND_SURFACE {
            let pp = pt.position();
            let to_q = qp - pp;
            let dist2 = to_q.length_squared();
            if dist2 > 0.0 {
                let w = to_q / dist2.sqrt();
                let mp = scene.materials[pt.material as usize];
                let f_pt = bsdf_eval(&mp, pt.normal(), (pt_minus.position() - pp).normalize_or_zero(), w);
                let f_qs = if s == 1 {
                    if qs.normal().dot(-w) > 0.0 {
                        Vec3::ONE
                    } else {
                        Vec3::ZERO
                    }
                } else {
                    let mq = scene.materials[qs.material as usize];
                    bsdf_eval(&mq, qs.normal(), (qs_minus.position() - qp).normalize_or_zero(), -w)
                };
                let g = pt.normal().dot(w).abs() * qs.normal().dot(w).abs() / dist2;
                l = pt.throughput() * f_pt * f_qs * qs.throughput() * g;
            }
        }
        // One shadow ray between the end points.
        if l.max_element() > 0.0 {
            let from = spawn(qp, qs.normal(), pt.position() - qp, params.epsilon);
            let target = if pt.kind == KIND_CAMERA {
                pt.position()
            } else {
                spawn(pt.position(), pt.normal(), qp - pt.position(), params.epsilon)
            };
            let dir = target - from;
            let dist = dir.length();
            if dist > 0.0 && occluded(scene.nodes, scene.triangles, from, dir / dist, 0.0, dist) {
                l = Vec3::ZERO;
            }
        }
    }
    if !(l.max_element() > 0.0) && !l.is_nan() {
        return Connection { contribution: Vec3::ZERO, pixel, mis_weight: 0.0 };
    }
    let w = mis_weight(params, scene, samples, vertices, s, t, &pt, &pt_minus, &qs, &qs_minus);
    Connection { contribution: l * (w * (info.depth + 2) as f32), pixel, mis_weight: w }
}

/// The balance-heuristic weight of technique (s, t) for the connected path.
#[allow(clippy::too_many_arguments)]
#[inline]
fn mis_weight(
    params: &RenderParams,
    scene: Scene,
    samples: Samples,
    vertices: &[PathVertex],
    s: u32,
    t: u32,
    pt: &PathVertex,
    pt_minus: &PathVertex,
    qs: &PathVertex,
    qs_minus: &PathVertex,
) -> f32 {
    let k = params.max_depth;
    let cam = params.camera;
    // Reverse densities that the connection changes.
    let pt_rev = if s > 0 {
        vertex_pdf(scene, &cam, qs_minus.position(), qs, pt)
    } else {
        light_origin_pdf(scene, pt)
    };
    let pt_minus_rev = if t >= 2 {
        if s > 0 {
            vertex_pdf(scene, &cam, qs.position(), pt, pt_minus)
        } else {
            // pt lies on a light: its density of emitting towards pt−.
            let as_light = PathVertex { kind: KIND_LIGHT, ..*pt };
            vertex_pdf(scene, &cam, Vec3::ZERO, &as_light, pt_minus)
        }
    } else {
        0.0
    };
    let qs_rev = if s > 0 { vertex_pdf(scene, &cam, pt_minus.position(), pt, qs) } else { 0.0 };
    let qs_minus_rev = if s >= 2 { vertex_pdf(scene, &cam, pt.position(), qs, qs_minus) } else { 0.0 };
    let mut sum = 0.0f32;
    // Techniques with more light vertices: walk the camera subpath back to vertex 1.
    let mut ri = 1.0f32;
    let mut i = t;
    while i > 1 {
        i -= 1;
        let (fwd, rev) = if i == t - 1 {
            (pt.pdf_fwd, pt_rev)
        } else if i + 2 == t {
            (pt_minus.pdf_fwd, pt_minus_rev)
        } else {
            let v = vertices[soa_index(samples.candidate, vertex_slot(0, i, k), samples.count)];
            (v.pdf_fwd, v.pdf_rev)
        };
        ri *= density_ratio(rev, fwd);
        sum += ri;
    }
    // Techniques with fewer light vertices: walk the light subpath back to vertex 0.
    ri = 1.0;
    i = s;
    while i > 0 {
        i -= 1;
        let (fwd, rev) = if i + 1 == s {
            (qs.pdf_fwd, qs_rev)
        } else if i + 2 == s {
            (qs_minus.pdf_fwd, qs_minus_rev)
        } else {
            let v = vertices[soa_index(samples.candidate, vertex_slot(1, i, k), samples.count)];
            (v.pdf_fwd, v.pdf_rev)
        };
        ri *= density_ratio(rev, fwd);
        sum += ri;
    }
    1.0 / (1.0 + sum)
}

/// Packs a connection for the contribution buffer: F (rgb) and the pixel's bits.
#[inline]
pub fn pack_connection(c: &Connection) -> Vec4 {
    pack_contribution(c.contribution, 1.0, c.pixel)
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests;
