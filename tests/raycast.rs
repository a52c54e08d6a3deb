//! The bench's ray-casting ceiling: the host's log of the rays a candidate casts is exactly the
//! rays `trace` and `connect` cast (counted against the path they built, in a closed furnace
//! where no ray can miss), the replay layout keeps each candidate's rays in order, the device
//! replays them with the same answers as the host, and the passes are timed.

mod common;

use kernels::connect::ConnectIo;
use kernels::mutate::MutateIo;
use kernels::trace::TraceIo;
use shared::mmlt::{vertex_slot, PathInfo, PathVertex};
use shared::params::{RenderParams, MODE_BOOTSTRAP};
use shared::rays::{Ray, RAY_CLOSEST, RAY_NONE, RAY_OCCLUSION};
use smlt::passes;
use smlt::passes::buffers::{OnDevice, SceneBuffers, Storage};
use smlt::render::{self, Budget, ChainSettings, Integrator, Method, Settings};
use smlt::scene::SceneData;
use smlt::timing::{time_passes, Clock};
use smlt_bench::raycast::{log_candidates, log_paths, replay, RayLog, LOGGED_PATHS};

/// Fresh (bootstrap) candidates of `scene`: their parameters, samples and depths.
fn candidates(scene: &SceneData, count: u32, max_depth: u32) -> (RenderParams, Vec<f32>, Vec<u32>) {
    let s = Settings {
        width: 32,
        height: 24,
        max_depth,
        seed: 7,
        integrator: Integrator::new(
            Method::NAIVE,
            ChainSettings { bootstrap_samples: count, ..Default::default() },
        ),
        budget: Budget::MutationsPerPixel(1.0),
        candidates: count,
        ..Default::default()
    };
    let params = RenderParams { mode: MODE_BOOTSTRAP, ..render::base_params(scene, &s) };
    let c = params.candidates as usize;
    let mut cand_u = vec![0.0; c * params.dims as usize];
    let mut cand_depth = vec![0; c];
    let io = MutateIo {
        params: &params,
        chains: &[],
        chain_u: &[],
        cand_u: &mut cand_u,
        cand_depth: &mut cand_depth,
    };
    io.run(c);
    (params, cand_u, cand_depth)
}

/// Candidate k's rays, in order, from the replay layout.
fn rays_of(log: &RayLog, k: usize) -> Vec<Ray> {
    let c = log.candidates as usize;
    log.rays.iter().skip(k).step_by(c).copied().take_while(|r| r.kind != RAY_NONE).collect()
}

/// In the furnace every ray hits: a camera subpath of t vertices casts t − 1 closest-hit rays,
/// one for each vertex after the pinhole, each landing on that vertex's triangle; a light
/// subpath of s vertices casts s − 1; the connection casts at most one occlusion ray, none for
/// s = 0. The log holds exactly these, and its count is their sum.
#[test]
fn the_log_holds_the_rays_of_each_candidates_path() {
    let scene = common::scenes::furnace(0.5, 0.5);
    let max_depth = 6;
    let (params, cand_u, cand_depth) = candidates(&scene, 700, max_depth);
    let c = params.candidates as usize;
    let log = log_candidates(&scene, &params, &cand_u, &cand_depth);
    // The paths themselves, from the same body.
    let mut vertices = vec![PathVertex::default(); c * shared::mmlt::vertex_slots(max_depth) as usize];
    let mut paths = vec![PathInfo::default(); c];
    let io = TraceIo {
        params: &params,
        cand_depth: &cand_depth,
        cand_u: &cand_u,
        vertices: &mut vertices,
        paths: &mut paths,
        scene: scene.shared(),
    };
    io.run(c);
    let vertex = |k: usize, side: u32, i: u32| vertices[k + vertex_slot(side, i, max_depth) as usize * c];
    let (mut total, mut shadow) = (0u64, 0u64);
    for (k, path) in paths.iter().enumerate() {
        let rays = rays_of(&log, k);
        total += rays.len() as u64;
        let closest: Vec<&Ray> = rays.iter().filter(|r| r.kind == RAY_CLOSEST).collect();
        let occlusion = rays.iter().filter(|r| r.kind == RAY_OCCLUSION).count();
        assert_eq!(path.camera_vertices, path.t.max(1), "candidate {k}: no miss in a furnace");
        let camera_rays = path.camera_vertices - 1;
        let light_rays = path.light_vertices.saturating_sub(1);
        assert_eq!(closest.len() as u32, camera_rays + light_rays, "candidate {k}: {path:?}");
        assert!(occlusion <= 1 && (path.s > 0 || occlusion == 0), "candidate {k}: {path:?}");
        shadow += occlusion as u64;
        // The closest-hit rays, in order, find the camera subpath's vertices, then the light's.
        let answers: Vec<u32> =
            closest.iter().map(|r| shared::rays::cast(&scene.shared().caster, r)).collect();
        let expected: Vec<u32> = (1..path.camera_vertices)
            .map(|i| vertex(k, 0, i).triangle + 1)
            .chain((1..path.light_vertices).map(|i| vertex(k, 1, i).triangle + 1))
            .collect();
        assert_eq!(answers, expected, "candidate {k}");
        // The shadow ray, if any, is the last ray: connect runs after trace.
        assert!(occlusion == 0 || rays.last().unwrap().kind == RAY_OCCLUSION);
    }
    assert_eq!(log.count, total);
    assert!((log.per_candidate() - total as f64 / c as f64).abs() < 1e-12);
    // A connection casts its ray unless it carries nothing: two points on one face of the cube
    // (cosine 0), or, for t = 1, a light point outside the camera's view.
    let surface = paths.iter().filter(|p| p.s > 0 && p.t >= 2).count() as u64;
    let to_camera = paths.iter().filter(|p| p.s > 0 && p.t == 1).count() as u64;
    println!("{c} candidates: {total} rays, {shadow} shadow rays for {surface} + {to_camera} connections");
    assert!(shadow * 10 >= surface * 7, "most connections between surfaces cast their shadow ray");
    assert!(
        log.rays.len().is_multiple_of(c)
            && log.rays.len() / c == (0..c).map(|k| rays_of(&log, k).len()).max().unwrap()
    );
}

/// The path tracer's log holds each path's own rays, in order: in the furnace (every ray hits,
/// every face a light) a path casts one closest-hit ray for each vertex whose uniforms it read,
/// one more if it reached the depth limit, and at most one shadow ray a vertex; the groups
/// cover every stride-th pixel once, in order, [`LOGGED_PATHS`] at most.
#[test]
fn the_path_tracers_log_holds_each_paths_rays() {
    let scene = common::scenes::furnace(0.5, 0.5);
    let max_depth = 6;
    // More pixels than the log takes, so that it strides.
    let (width, height) = (512, 160);
    let params = render::path_tracer_params(&scene, (width, height), max_depth, 3, 1);
    let logs = log_paths(&scene, &params, 5);
    let pixels = width * height;
    let stride = pixels.div_ceil(LOGGED_PATHS);
    assert!(stride > 1);
    assert_eq!(logs.len(), 5);
    let chosen: Vec<u32> = (0..pixels).step_by(stride as usize).collect();
    assert_eq!(logs.iter().map(|l| l.candidates as usize).sum::<usize>(), chosen.len());
    assert!(chosen.len() as u32 <= LOGGED_PATHS);
    let caster = scene.shared().caster;
    let (mut paths, mut at_limit, mut shadow) = (0usize, 0usize, 0usize);
    let logged = logs.iter().flat_map(|log| (0..log.candidates as usize).map(move |k| (log, k)));
    for ((log, k), &pixel) in logged.zip(&chosen) {
        let rays = rays_of(log, k);
        let closest: Vec<&Ray> = rays.iter().filter(|r| r.kind == RAY_CLOSEST).collect();
        let occlusion = rays.iter().filter(|r| r.kind == RAY_OCCLUSION).count();
        // The same path, from its own uniforms.
        let samples = shared::path_tracer::KeyedSamples::new(params.seed, pixel, 0);
        let jitter = shared::path_tracer::PathSamples::raster(&samples);
        let at = ((pixel % width) as f32 + jitter.x, (pixel / width) as f32 + jitter.y);
        let settings = shared::path_tracer::PathSettings::from(&params);
        let path = shared::path_tracer::trace_path(&settings, scene.shared(), at, &samples);
        let v = path.vertices as usize;
        assert!(
            closest.len() == v || closest.len() == v + 1,
            "pixel {pixel}: {} rays, {v} vertices",
            closest.len()
        );
        assert!(closest.len() <= v || v == max_depth as usize, "pixel {pixel}: a ray past the last vertex");
        assert!(occlusion <= v, "pixel {pixel}");
        // The first ray is the path's camera ray, from the pinhole.
        assert_eq!(rays[0].kind, RAY_CLOSEST, "pixel {pixel}");
        assert_eq!(glam::Vec3::from_array(rays[0].origin), params.camera.origin(), "pixel {pixel}");
        assert!(closest.iter().all(|r| shared::rays::cast(&caster, r) > 0), "pixel {pixel}: a ray missed");
        at_limit += (closest.len() > v) as usize;
        shadow += occlusion;
        paths += 1;
    }
    let count: u64 = logs.iter().map(|l| l.count).sum();
    println!("{paths} paths, {count} rays, {shadow} shadow rays, {at_limit} at the depth limit");
    assert!(at_limit > 0 && shadow > paths, "the furnace's paths reach the limit and see lights");
}

/// The device replays the default scene's logged rays with the same answers as the host (the
/// same `raycast` body), timed with timestamp queries where the device has them.
#[test]
fn the_device_replays_the_rays_like_the_host() {
    let Some(gpu) = common::gpu_or_skip("the_device_replays_the_rays_like_the_host") else {
        return;
    };
    let scene = SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell")
        .expect("the default scene");
    let (params, cand_u, cand_depth) = candidates(&scene, 3000, 8);
    let log = log_candidates(&scene, &params, &cand_u, &cand_depth);
    let replayed = replay(&gpu, &scene, &log, 2).expect("replay");
    let mut host = vec![0u32; log.candidates as usize];
    let p = RenderParams { candidates: log.candidates, ..Default::default() };
    passes::raycast::cpu(&p, scene.shared(), &log.rays, &mut host);
    let differ = host.iter().zip(&replayed.answers).filter(|(a, b)| a != b).count();
    println!(
        "{} rays ({:.2} per candidate) in {:.3} ms ({} clock): {:.2} M rays/s; {differ} of {} answers differ",
        log.count,
        log.per_candidate(),
        replayed.seconds * 1e3,
        replayed.clock,
        replayed.rays_per_s(&log) / 1e6,
        host.len()
    );
    // A grazing ray may flip on a 1-ulp difference in the device's arithmetic.
    assert!(differ <= host.len() / 200, "{differ} answers differ");
    assert!(host.iter().any(|&a| a > 0));
    assert!(replayed.seconds > 0.0 && replayed.rays_per_s(&log).is_finite());
    if gpu.features.contains(wgpu::Features::TIMESTAMP_QUERY) {
        assert_eq!(replayed.clock, Clock::Timestamp);
    }
}

/// Per-pass timing: every pass gets a time, also one with nothing to run; a pass with work
/// takes some; and the passes' device times fit inside the wall time around them.
#[test]
fn passes_are_timed_on_the_device() {
    let Some(gpu) = common::gpu_or_skip("passes_are_timed_on_the_device") else {
        return;
    };
    let scene = SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell")
        .expect("the default scene");
    let (params, cand_u, cand_depth) = candidates(&scene, 4096, 8);
    let log = log_candidates(&scene, &params, &cand_u, &cand_depth);
    let p = gpu.storage_from("params", &[RenderParams { candidates: log.candidates, ..Default::default() }]);
    let mut storage = OnDevice::new(gpu.clone());
    SceneBuffers::new(&mut storage, &scene);
    let scene_buffers = storage.registry();
    let rays = gpu.storage_from("rays", &log.rays);
    let answers = gpu.storage_zeroed::<u32>("answers", log.candidates as usize);
    let pass = passes::raycast::gpu(&gpu, [&p, &rays, &answers], &scene_buffers).unwrap();
    time_passes(&gpu, &[(&pass, 64)]).unwrap(); // warm-up
    let wall = std::time::Instant::now();
    let (seconds, clock) = time_passes(&gpu, &[(&pass, 64), (&pass, log.candidates), (&pass, 0)]).unwrap();
    let wall = wall.elapsed().as_secs_f64();
    println!("{clock} clock: {seconds:?}");
    assert_eq!(seconds.len(), 3);
    assert!(seconds.iter().all(|s| s.is_finite() && *s >= 0.0));
    assert!(seconds[1] > 0.0, "{} candidates' rays took no time: {seconds:?}", log.candidates);
    assert!(seconds.iter().sum::<f64>() <= wall * 1.01 + 1e-4, "{seconds:?} within {wall} s of wall time");
}

/// A path reads only the dimensions that `dimensions_used` names for its depth (which lets
/// `mutate` skip the others): giving every other dimension new values changes none of the
/// rays a candidate casts nor its contribution.
#[test]
fn a_path_reads_only_the_dimensions_of_its_depth() {
    let scene = SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell")
        .expect("the default scene");
    let max_depth = 7;
    let (params, cand_u, cand_depth) = candidates(&scene, 2000, max_depth);
    let c = params.candidates as usize;
    let mut other = cand_u.clone();
    let mut changed = 0;
    for (k, &depth) in cand_depth.iter().enumerate() {
        for dim in 0..params.dims {
            if !shared::mmlt::dimensions_used(dim, 1, depth, max_depth) {
                let i = k + dim as usize * c;
                other[i] = (other[i] + 0.37).fract();
                changed += 1;
            }
        }
    }
    let run = |u: &[f32]| {
        let log = log_candidates(&scene, &params, u, &cand_depth);
        let mut vertices = vec![PathVertex::default(); c * shared::mmlt::vertex_slots(max_depth) as usize];
        let mut paths = vec![PathInfo::default(); c];
        let mut contributions = vec![glam::Vec4::ZERO; c];
        let trace = TraceIo {
            params: &params,
            cand_depth: &cand_depth,
            cand_u: u,
            vertices: &mut vertices,
            paths: &mut paths,
            scene: scene.shared(),
        };
        trace.run(c);
        let importance = vec![1.0f32; (params.width * params.height) as usize];
        let mut depth_out = cand_depth.clone();
        let connect = ConnectIo {
            params: &params,
            cand_u: u,
            vertices: &vertices,
            paths: &paths,
            importance: &importance,
            contributions: &mut contributions,
            cand_depth: &mut depth_out,
            scene: scene.shared(),
        };
        connect.run(c);
        (log.rays, contributions)
    };
    let (rays, contributions) = run(&cand_u);
    let (rays_other, contributions_other) = run(&other);
    println!("{changed} of {} samples changed", cand_u.len());
    assert!(changed > cand_u.len() / 4);
    assert!(rays == rays_other, "the rays changed");
    assert!(contributions
        .iter()
        .zip(&contributions_other)
        .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)));
    // And the claim is tight: the deepest bounce dimensions are read.
    assert!(shared::mmlt::dimensions_used(
        shared::mmlt::bounce_dimension(0, 2, max_depth) + 1,
        1,
        3,
        max_depth
    ));
    assert!(shared::mmlt::dimensions_used(
        shared::mmlt::bounce_dimension(1, 2, max_depth) + 1,
        1,
        3,
        max_depth
    ));
    assert!(!shared::mmlt::dimensions_used(shared::mmlt::bounce_dimension(0, 3, max_depth), 1, 3, max_depth));
    assert!(!shared::mmlt::dimensions_used(shared::mmlt::bounce_dimension(1, 3, max_depth), 1, 3, max_depth));
}
