//! The `connect` stage: the densities each vertex would have under the other techniques, the
//! balance-heuristic MIS weight, and [`connect_candidate`], which joins the end points of a
//! candidate's subpaths with one shadow ray and weighs the path.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use core::f32::consts::PI;
use glam::Vec3;

use crate::bsdf::{bsdf_eval, bsdf_pdf, Material, Normals};
use crate::camera::Camera;
use crate::cutout::blend_key;
use crate::layout::soa_index;
use crate::light::{emitted, is_environment, is_punctual, punctual_index};
use crate::normals::scattering_cosine;
use crate::ray_caster::RayCaster;
use crate::scene::Scene;
use crate::surface::{material_at, normals_at};

use crate::light::sample_light;
use crate::params::RenderParams;
use crate::ray_caster::spawn;

use super::*;

/// The density of `from` (with predecessor `before`, or a light origin when `from` is a
/// light endpoint; `material` and `normals` its own where it is a surface vertex) generating
/// `to`, as an area density at `to`.
#[inline]
fn vertex_pdf<R: RayCaster>(
    scene: Scene<R>,
    camera: &Camera,
    before: Vec3,
    from: &PathVertex,
    material: &Material,
    normals: Normals,
    to: &PathVertex,
) -> f32 {
    let p = from.position();
    if is_at_infinity(from) {
        // The environment's rays are parallel: its disk's density, projected onto `to`.
        let cos = if to.kind != KIND_CAMERA { to.normal().dot(from.normal()).abs() } else { 1.0 };
        return scene.environment.pdf_origin() * cos;
    }
    // Towards the environment, the direction's density in solid angle, not converted.
    let infinite = is_at_infinity(to);
    let w = if infinite { -to.normal() } else { (to.position() - p).normalize_or_zero() };
    let pdf_dir = if from.kind == KIND_CAMERA {
        camera.pdf_direction(w)
    } else if from.kind == KIND_LIGHT && is_punctual(from.triangle) {
        let light = scene.punctual[punctual_index(from.triangle) as usize];
        if light.is_directional() {
            // Its rays are parallel: the disk's density, projected onto `to`.
            let cos = if to.kind != KIND_CAMERA { to.normal().dot(w).abs() } else { 1.0 };
            return light.pdf_origin() * cos;
        }
        light.pdf_direction(w)
    } else if from.kind == KIND_LIGHT {
        from.normal().dot(w).max(0.0) / PI
    } else {
        bsdf_pdf(material, normals, (before - p).normalize_or_zero(), w)
    };
    if infinite {
        return pdf_dir;
    }
    convert_density(pdf_dir, p, to.position(), to.normal(), to.kind != KIND_CAMERA)
}

/// The material and normals at a surface vertex (`crate::surface`: its textures and shading
/// normal at the vertex's position); a default material and the vertex's normal for any other
/// vertex. Looked up once a vertex in the stage (each lookup is a copy of the texture code in
/// the device module).
#[inline]
fn surface_at<R: RayCaster>(scene: Scene<R>, v: &PathVertex) -> (Material, Normals) {
    if v.kind == KIND_SURFACE {
        (material_at(&scene, v.triangle, v.position()), normals_at(&scene, v.triangle, v.position()))
    } else {
        (Material::default(), Normals::flat(v.normal()))
    }
}

/// Density of a camera-subpath end point `pt` that lies on a light being the light's origin:
/// an emissive triangle's area density, or the environment's pick times the solid-angle
/// density of the direction it is reached from.
#[inline]
fn light_origin_pdf<R: RayCaster>(scene: Scene<R>, v: &PathVertex) -> f32 {
    if is_at_infinity(v) {
        let env = scene.environment;
        return env.pick * env.pdf(scene.environment_map, -v.normal());
    }
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
pub fn connect_candidate<R: RayCaster>(
    params: &RenderParams,
    scene: Scene<R>,
    u: &[f32],
    samples: Samples,
    info: &PathInfo,
    vertices: &[PathVertex],
) -> Connection {
    let max_depth = params.max_depth;
    let cam = params.camera;
    let s = info.s;
    let t = info.t;
    let none = Connection { contribution: Vec3::ZERO, pixel: info.pixel, mis_weight: 0.0 };
    if t > info.camera_vertices || (s >= 2 && s > info.light_vertices) {
        return none;
    }
    let at = |side: u32, i: u32| {
        vertices[soa_index(samples.candidate, vertex_slot(side, i, max_depth), samples.count)]
    };
    let mut pixel = info.pixel;
    let zero = PathVertex::default();
    // The four vertices around the connection (pt, pt−, qs, qs−), possibly resampled.
    let mut pt = if t >= 1 { at(0, t - 1) } else { zero };
    let pt_minus = if t >= 2 { at(0, t - 2) } else { zero };
    let mut qs = if s >= 2 { at(1, s - 1) } else { zero };
    let qs_minus = if s >= 2 { at(1, s - 2) } else { zero };
    // The materials and normals at the two end points (s = 1 resamples qs on a light, which
    // has none).
    let surface_pt = surface_at(scene, &pt);
    let surface_qs = surface_at(scene, &qs);
    let (mat_pt, n_pt) = surface_pt;
    let (mat_qs, n_qs) = surface_qs;
    let mut l = Vec3::ZERO;
    // The directions (wo, wi) at each end point that scatters, whose BSDF multiplies `l` once
    // after the techniques' cases: each call is a copy of the material code in the device's
    // compiled stage.
    let (mut scatters_pt, mut wo_p, mut wi_p) = (false, Vec3::ZERO, Vec3::ZERO);
    let (mut scatters_qs, mut wo_q, mut wi_q) = (false, Vec3::ZERO, Vec3::ZERO);
    // The pick probability of the light resampled for s = 1.
    let mut pick = 0.0f32;
    if s == 0 {
        // The camera subpath found a light by itself: an emitter, or the environment.
        if is_at_infinity(&pt) {
            l = pt.throughput() * scene.environment.radiance(scene.environment_map, -pt.normal());
        } else if pt.kind == KIND_SURFACE && mat_pt.is_emissive() {
            let w = (pt_minus.position() - pt.position()).normalize_or_zero();
            l = pt.throughput() * emitted(Vec3::from_array(mat_pt.emission), pt.normal(), w);
        }
    } else {
        if s == 1 {
            let qs_point = sample_light(
                &scene,
                params.light_count,
                samples.get(u, DIM_CONNECT_PICK),
                samples.get2(u, DIM_CONNECT_POINT),
            );
            qs = light_vertex(&qs_point);
            pick = qs_point.pick;
        }
        let punctual_light = s == 1 && is_punctual(qs.triangle);
        let environment_light = s == 1 && is_environment(qs.triangle);
        let qp = qs.position();
        if t == 1 && (punctual_light || environment_light) {
            // The camera does not see a delta light, and sees the environment only by itself
            // (s = 0): this technique has density 0 for such a path.
            pt = PathVertex {
                p: cam.position,
                kind: KIND_CAMERA,
                n: cam.forward,
                pdf_fwd: 1.0,
                ..Default::default()
            };
        } else if t == 1 {
            // Connect the light subpath's end to the pinhole.
            let to_cam = cam.origin() - qp;
            let dist2 = to_cam.length_squared();
            let w = to_cam / dist2.sqrt();
            let r = cam.raster(-w);
            if r.inside && dist2 > 0.0 {
                pixel = cam.pixel(r.x, r.y);
                let wo = (qs_minus.position() - qp).normalize_or_zero();
                let (f, cos_q) = if s == 1 {
                    (if qs.normal().dot(w) > 0.0 { Vec3::ONE } else { Vec3::ZERO }, qs.normal().dot(w).abs())
                } else {
                    // The light subpath's end scatters importance: the adjoint's cosine.
                    (scatters_qs, wo_q, wi_q) = (true, wo, w);
                    (Vec3::ONE, scattering_cosine(n_qs, wo, w, false))
                };
                let g = cos_q * r.cos_theta / dist2;
                l = qs.throughput() * f * (cam.importance(-w) * g);
            }
            pt = PathVertex {
                p: cam.position,
                kind: KIND_CAMERA,
                n: cam.forward,
                pdf_fwd: 1.0,
                ..Default::default()
            };
        } else if pt.kind == KIND_SURFACE && environment_light {
            let pp = pt.position();
            let wi = -qs.normal();
            // The light's end of the connection: far along the direction (where the shadow ray
            // ends).
            qs.p = scene.environment.beyond(pp, wi).to_array();
            let wo = (pt_minus.position() - pp).normalize_or_zero();
            (scatters_pt, wo_p, wi_p) = (true, wo, wi);
            // qs.beta = L / (pick · p_ω).
            l = pt.throughput() * qs.throughput() * scattering_cosine(n_pt, wo, wi, true);
        } else if pt.kind == KIND_SURFACE && punctual_light {
            let pp = pt.position();
            let inc = scene.punctual[punctual_index(qs.triangle) as usize].incident(pp);
            // The light's end of the connection: its position, or far along a directional
            // light's direction (where the shadow ray ends and the reverse densities look from).
            qs.p = inc.from.to_array();
            let wo = (pt_minus.position() - pp).normalize_or_zero();
            if pick > 0.0 {
                (scatters_pt, wo_p, wi_p) = (true, wo, inc.wi);
                l = pt.throughput() * inc.radiance * (scattering_cosine(n_pt, wo, inc.wi, true) / pick);
            }
        } else if pt.kind == KIND_SURFACE {
            let pp = pt.position();
            let to_q = qp - pp;
            let dist2 = to_q.length_squared();
            if dist2 > 0.0 {
                let w = to_q / dist2.sqrt();
                let wo = (pt_minus.position() - pp).normalize_or_zero();
                (scatters_pt, wo_p, wi_p) = (true, wo, w);
                let (f_qs, cos_q) = if s == 1 {
                    (if qs.normal().dot(-w) > 0.0 { Vec3::ONE } else { Vec3::ZERO }, qs.normal().dot(w).abs())
                } else {
                    // The light subpath's end scatters importance: the adjoint's cosine.
                    let wo = (qs_minus.position() - qp).normalize_or_zero();
                    (scatters_qs, wo_q, wi_q) = (true, wo, -w);
                    (Vec3::ONE, scattering_cosine(n_qs, wo, -w, false))
                };
                let g = scattering_cosine(n_pt, wo, w, true) * cos_q / dist2;
                l = pt.throughput() * f_qs * qs.throughput() * g;
            }
        }
        if scatters_pt {
            l *= bsdf_eval(&mat_pt, n_pt, wo_p, wi_p, true);
        }
        if scatters_qs {
            l *= bsdf_eval(&mat_qs, n_qs, wo_q, wi_q, false);
        }
        // One shadow ray between the end points; its cut-outs drawn from the connection's own
        // uniforms (the resampled light point's, unused otherwise for s ≥ 2).
        if l.max_element() > 0.0 {
            let qp = qs.position();
            let from = spawn(qp, qs.normal(), pt.position() - qp, params.epsilon);
            let target = if pt.kind == KIND_CAMERA {
                pt.position()
            } else {
                spawn(pt.position(), pt.normal(), qp - pt.position(), params.epsilon)
            };
            let dir = target - from;
            let dist = dir.length();
            let key = blend_key(samples.get2(u, DIM_CONNECT_POINT));
            if dist > 0.0 && scene.caster.occluded(from, dir / dist, 0.0, dist, key) {
                l = Vec3::ZERO;
            }
        }
    }
    if !(l.max_element() > 0.0) && !l.is_nan() {
        return Connection { contribution: Vec3::ZERO, pixel, mis_weight: 0.0 };
    }
    let ends = [(pt, surface_pt), (qs, surface_qs)];
    let w = mis_weight(params, scene, samples, vertices, s, t, ends, &pt_minus, &qs_minus);
    Connection { contribution: l * (w * (info.depth + 2) as f32), pixel, mis_weight: w }
}

/// The balance-heuristic weight of technique (s, t) for the connected path.
#[allow(clippy::too_many_arguments)]
#[inline]
fn mis_weight<R: RayCaster>(
    params: &RenderParams,
    scene: Scene<R>,
    samples: Samples,
    vertices: &[PathVertex],
    s: u32,
    t: u32,
    ends: [(PathVertex, (Material, Normals)); 2],
    pt_minus: &PathVertex,
    qs_minus: &PathVertex,
) -> f32 {
    let max_depth = params.max_depth;
    let cam = params.camera;
    // The connection's end points and their materials and normals (each a local of its own:
    // a reference into a tuple is a pointer rust-gpu cannot pass to `bsdf_pdf`).
    let [(pt, (mat_pt, n_pt)), (qs, (mat_qs, n_qs))] = ends;
    let (pt, qs, mat_pt, mat_qs) = (&pt, &qs, &mat_pt, &mat_qs);
    // Reverse densities that the connection changes.
    let pt_rev = if s > 0 {
        vertex_pdf(scene, &cam, qs_minus.position(), qs, mat_qs, n_qs, pt)
    } else {
        light_origin_pdf(scene, pt)
    };
    let pt_minus_rev = if t >= 2 {
        if s > 0 {
            vertex_pdf(scene, &cam, qs.position(), pt, mat_pt, n_pt, pt_minus)
        } else {
            // pt lies on a light: its density of emitting towards pt−.
            let as_light = PathVertex { kind: KIND_LIGHT, ..*pt };
            vertex_pdf(scene, &cam, Vec3::ZERO, &as_light, mat_pt, n_pt, pt_minus)
        }
    } else {
        0.0
    };
    let qs_rev = if s > 0 { vertex_pdf(scene, &cam, pt_minus.position(), pt, mat_pt, n_pt, qs) } else { 0.0 };
    let qs_minus_rev =
        if s >= 2 { vertex_pdf(scene, &cam, pt.position(), qs, mat_qs, n_qs, qs_minus) } else { 0.0 };
    // A path that starts on a punctual light has no s = 0 technique (no ray hits a delta).
    let light_origin = if s == 1 {
        qs.triangle
    } else if s >= 2 {
        vertices[soa_index(samples.candidate, vertex_slot(1, 0, max_depth), samples.count)].triangle
    } else {
        0
    };
    let delta_origin = s >= 1 && is_punctual(light_origin);
    // A path that starts on the environment has no technique (1, 1): the camera sees the
    // environment only by itself.
    let environment_origin = if s == 0 { is_at_infinity(pt) } else { is_environment(light_origin) };
    let mut sum = 0.0f32;
    // Whether vertex j of a subpath left by a delta lobe. Its neighbours' densities through it
    // are 0, remapped to 1 (their ratios cancel), and a technique that would connect at it or
    // its predecessor is impossible: left out of the sum (pbrt-v4's `MISWeight`).
    let delta = |side: u32, j: u32| {
        vertices[soa_index(samples.candidate, vertex_slot(side, j, max_depth), samples.count)].delta != 0
    };
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
            let v = vertices[soa_index(samples.candidate, vertex_slot(0, i, max_depth), samples.count)];
            (v.pdf_fwd, v.pdf_rev)
        };
        // The connection's end points pt (i = t − 1) and qs count as non-delta: the
        // connection evaluates their non-delta lobes, and pt−'s reverse density is recomputed.
        let here = i + 1 < t && delta(0, i);
        let before = delta(0, i - 1);
        let after = i + 2 < t && delta(0, i + 1);
        ri *= density_ratio(if after { 1.0 } else { rev }, if before { 1.0 } else { fwd });
        let camera_sees_environment = i == 1 && s + t == 2 && environment_origin;
        if !(here || before || camera_sees_environment) {
            sum += ri;
        }
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
            let v = vertices[soa_index(samples.candidate, vertex_slot(1, i, max_depth), samples.count)];
            (v.pdf_fwd, v.pdf_rev)
        };
        let stored = s >= 2;
        let here = stored && i + 1 < s && delta(1, i);
        let before_bsdf = stored && i > 0 && delta(1, i - 1);
        let after = stored && i + 2 < s && delta(1, i + 1);
        ri *= density_ratio(if after { 1.0 } else { rev }, if before_bsdf { 1.0 } else { fwd });
        let before = if i > 0 { before_bsdf } else { delta_origin };
        if !(here || before) {
            sum += ri;
        }
    }
    1.0 / (1.0 + sum)
}
