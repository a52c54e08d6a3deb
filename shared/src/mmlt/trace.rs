//! The `trace` stage: the light subpath's first vertex, the random walk
//! that extends a subpath, and [`trace_candidate`], which builds both subpaths of a candidate.

use core::f32::consts::PI;
use glam::{Vec2, Vec3};

use crate::bsdf::{bsdf_pdf, bsdf_sample, cosine_hemisphere, medium_coefficient, transmittance};
use crate::cutout::blend_key;
use crate::layout::soa_index;
use crate::light::{is_environment, is_punctual, punctual_index, sample_light, LightPoint, ENVIRONMENT};
use crate::normals::scattering_cosine;
use crate::ray_caster::RayCaster;
use crate::scene::Scene;
use crate::surface::{material_at, normals_at};

use crate::params::RenderParams;
use crate::ray_caster::spawn;

use super::*;

/// The light subpath's first vertex at the light point `ls` (kind LIGHT, beta = emission /
/// area density, pdf_fwd = area density; `triangle` holds the light's id,
/// `LightEntry::light`).
#[inline]
pub fn light_vertex(ls: &LightPoint) -> PathVertex {
    let beta = if ls.pdf_area > 0.0 { ls.emission / ls.pdf_area } else { Vec3::ZERO };
    PathVertex {
        p: ls.p.to_array(),
        kind: KIND_LIGHT,
        n: ls.n.to_array(),
        material: ls.material,
        beta: beta.to_array(),
        pdf_fwd: ls.pdf_area,
        pdf_rev: 0.0,
        triangle: ls.light,
        delta: 0,
        _pad: 0,
    }
}

/// Extends a subpath from its first vertex (already stored) to at most `max_vertices`
/// vertices by tracing rays and sampling BSDFs, storing each vertex and the reverse density of
/// its predecessor. Returns the number of vertices the subpath has. `pdf_direction` is the
/// solid-angle density of `direction`, or with `parallel` (a directional light's ray, a delta
/// direction from a point on its disk) the disk's area density, which the first vertex takes
/// projected along the ray, without the inverse square.
#[allow(clippy::too_many_arguments)]
#[inline]
fn random_walk<R: RayCaster>(
    params: &RenderParams,
    scene: Scene<R>,
    u: &[f32],
    samples: Samples,
    side: u32,
    first: PathVertex,
    direction: Vec3,
    throughput: Vec3,
    pdf_direction: f32,
    parallel: bool,
    max_vertices: u32,
    vertices: &mut [PathVertex],
) -> u32 {
    let max_depth = params.max_depth;
    let mut prev = first;
    let mut count = 1u32;
    let mut d = direction;
    let mut beta = throughput;
    let mut pdf_dir = pdf_direction;
    let mut parallel_segment = parallel;
    // Beer–Lambert coefficient of the medium the current segment runs through.
    let mut sigma = Vec3::ZERO;
    let mut origin = if first.kind == KIND_CAMERA {
        first.position()
    } else {
        spawn(first.position(), first.normal(), d, params.epsilon)
    };
    // The key of the segment's cut-out draws: from the uniforms that chose its direction (the
    // raster position, the light's direction, then each BSDF sample's).
    let first = if side == 0 { DIM_RASTER } else { DIM_LIGHT_DIRECTION };
    let mut key = blend_key(samples.get2(u, first));
    while count < max_vertices {
        let hit = scene.caster.closest_hit(origin, d, 0.0, crate::triangle::NO_HIT, key);
        if !hit.found() {
            // A camera subpath that leaves the scene ends on the environment (not from inside
            // a medium): a light vertex at infinity, its forward density the direction's, in
            // solid angle (pbrt's BDPT), its normal the direction the light travels.
            let env = scene.environment;
            if side == 0 && env.is_present() && !(sigma.max_element() > 0.0) {
                let v = PathVertex {
                    p: env.beyond(origin, d).to_array(),
                    kind: KIND_LIGHT,
                    n: (-d).to_array(),
                    material: 0,
                    beta: beta.to_array(),
                    pdf_fwd: pdf_dir,
                    pdf_rev: 0.0,
                    triangle: ENVIRONMENT,
                    delta: 0,
                    _pad: 0,
                };
                vertices[soa_index(samples.candidate, vertex_slot(side, count, max_depth), samples.count)] =
                    v;
                count += 1;
            }
            break;
        }
        let tri = scene.triangles[hit.triangle as usize];
        let p = origin + d * hit.t;
        let n = tri.normal();
        if sigma.max_element() > 0.0 {
            beta *= transmittance(sigma, hit.t);
        }
        // The forward density converts onto the new vertex, which always lies on a surface.
        let pdf_fwd = if parallel_segment {
            pdf_dir * n.dot(d).abs()
        } else {
            convert_density(pdf_dir, prev.position(), p, n, true)
        };
        parallel_segment = false;
        let mut v = PathVertex {
            p: p.to_array(),
            kind: KIND_SURFACE,
            n: n.to_array(),
            material: tri.material,
            beta: beta.to_array(),
            pdf_fwd,
            pdf_rev: 0.0,
            triangle: hit.triangle,
            delta: 0,
            _pad: 0,
        };
        let slot = soa_index(samples.candidate, vertex_slot(side, count, max_depth), samples.count);
        vertices[slot] = v;
        count += 1;
        if count >= max_vertices {
            break;
        }
        let m = material_at(&scene, hit.triangle, p);
        let normals = normals_at(&scene, hit.triangle, p);
        let wo = -d;
        let bounce = count - 2;
        let radiance = side == 0;
        let bounce_u = samples.get2(u, bounce_dimension(side, bounce, max_depth));
        let bs = bsdf_sample(&m, normals, wo, bounce_u, radiance);
        if !(bs.pdf > 0.0) {
            break;
        }
        // The camera subpath carries radiance, the light subpath importance (the adjoint's
        // cosine, `crate::normals`).
        beta *= bs.f * (scattering_cosine(normals, wo, bs.wi, radiance) / bs.pdf);
        // A delta lobe: no other technique generates its neighbours through it (their
        // densities from it are 0, remapped in the weights as pbrt-v4's BDPT does).
        if bs.delta {
            v.delta = 1;
            vertices[slot] = v;
        }
        // The density of the reverse walk arriving at the predecessor (at the environment, in
        // solid angle).
        let pdf_back = if bs.delta { 0.0 } else { bsdf_pdf(&m, normals, bs.wi, wo) };
        prev.pdf_rev = if is_at_infinity(&prev) {
            pdf_back
        } else {
            convert_density(pdf_back, p, prev.position(), prev.normal(), prev.kind != KIND_CAMERA)
        };
        vertices[soa_index(samples.candidate, vertex_slot(side, count - 2, max_depth), samples.count)] = prev;
        prev = v;
        d = bs.wi;
        key = blend_key(bounce_u);
        pdf_dir = if bs.delta { 0.0 } else { bs.pdf };
        sigma = medium_coefficient(&m, n, d);
        origin = spawn(p, n, d, params.epsilon);
    }
    count
}

/// The `trace` stage for one candidate: picks the technique, then builds the camera subpath
/// (t vertices, the pinhole first) and, for s ≥ 2, the light subpath (s vertices, a light
/// point first) into the vertex buffer.
#[inline]
pub fn trace_candidate<R: RayCaster>(
    params: &RenderParams,
    scene: Scene<R>,
    u: &[f32],
    samples: Samples,
    depth: u32,
    vertices: &mut [PathVertex],
) -> PathInfo {
    let max_depth = params.max_depth;
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
    vertices[soa_index(samples.candidate, vertex_slot(0, 0, max_depth), samples.count)] = camera_vertex;
    let mut camera_vertices = 1;
    if t >= 2 {
        let d = cam.direction(raster.x, raster.y);
        let pdf = cam.pdf_direction(d);
        camera_vertices =
            random_walk(params, scene, u, samples, 0, camera_vertex, d, Vec3::ONE, pdf, false, t, vertices);
    }
    let mut light_vertices = 0;
    if s >= 2 {
        let ls = sample_light(
            &scene,
            params.light_count,
            samples.get(u, DIM_LIGHT_PICK),
            samples.get2(u, DIM_LIGHT_POINT),
        );
        let v0 = light_vertex(&ls);
        vertices[soa_index(samples.candidate, vertex_slot(1, 0, max_depth), samples.count)] = v0;
        light_vertices = 1;
        if v0.pdf_fwd > 0.0 && is_environment(ls.light) {
            // A direction towards the environment (the light point's samples), then the disk's
            // point: beta = L / (p_ω · p_A), p_ω with the pick, p_A on the disk.
            let env = scene.environment;
            let origin = env.sample_origin(v0.normal(), samples.get2(u, DIM_LIGHT_DIRECTION));
            let v0 = PathVertex { p: origin.to_array(), ..v0 };
            vertices[soa_index(samples.candidate, vertex_slot(1, 0, max_depth), samples.count)] = v0;
            let beta = v0.throughput() / env.pdf_origin();
            light_vertices = random_walk(
                params,
                scene,
                u,
                samples,
                1,
                v0,
                v0.normal(),
                beta,
                env.pdf_origin(),
                true,
                s,
                vertices,
            );
        } else if v0.pdf_fwd > 0.0 && is_punctual(ls.light) {
            let light = scene.punctual[punctual_index(ls.light) as usize];
            let e = light.sample_direction(samples.get2(u, DIM_LIGHT_DIRECTION));
            let le = light.emitted(e.w);
            if e.pdf > 0.0 && le.max_element() > 0.0 {
                // beta = I(w) / (p_A · p_ω) for point and spot (p_A the pick, a delta position);
                // E / p_A for a directional light (p_A on its disk, a delta direction).
                let beta = le / (v0.pdf_fwd * e.pdf);
                let (pdf, parallel) =
                    if light.is_directional() { (light.pdf_origin(), true) } else { (e.pdf, false) };
                light_vertices =
                    random_walk(params, scene, u, samples, 1, v0, e.w, beta, pdf, parallel, s, vertices);
            }
        } else if v0.pdf_fwd > 0.0 {
            let n = v0.normal();
            let d = cosine_hemisphere(n, samples.get2(u, DIM_LIGHT_DIRECTION));
            let pdf = n.dot(d).max(0.0) / PI;
            if pdf > 0.0 {
                // beta = Le · cos / (p_A · p_dir) = Le · π / p_A.
                let beta = ls.emission * (PI / v0.pdf_fwd);
                light_vertices =
                    random_walk(params, scene, u, samples, 1, v0, d, beta, pdf, false, s, vertices);
            }
        }
    }
    PathInfo { s, t, camera_vertices, light_vertices, pixel, depth, _pad: [0; 2] }
}
