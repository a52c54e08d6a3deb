//! The ray-casting ceiling of the bench: the rays that one iteration's candidates cast, logged
//! on the host by running the same `trace` and `connect` bodies over the device's candidate
//! buffer through a [`Logged`] ray caster, then replayed bare by the `raycast` kernel, on the
//! device or on the CPU backend's threads.
//! Rays per candidate and bare rays/s give the most candidates a second the device could trace
//! if casting rays were all it did: `rays/s ÷ rays per candidate`. The path tracer's paths are
//! logged the same way ([`log_paths`]), a path standing for a candidate.

use std::cell::RefCell;

use glam::{Vec3, Vec4};
use shared::mmlt::{vertex_slots, PathInfo, PathVertex};
use shared::params::RenderParams;
use shared::path_tracer::PathTracerParams;
use shared::ray_caster::{Hit, RayCaster};
use shared::rays::{Ray, RAY_CLOSEST, RAY_OCCLUSION};

use kernels::connect::ConnectIo;
use kernels::trace::TraceIo;
use smlt::gpu::Gpu;
use smlt::passes;

use smlt::passes::buffers::{OnDevice, SceneBuffers, Storage};
use smlt::render::RenderError;
use smlt::scene::SceneData;
use smlt::timing::{time_passes, Clock};

/// A ray caster that records every query it answers, in order, and forwards it to `inner`.
pub struct Logged<R> {
    inner: R,
    rays: RefCell<Vec<Ray>>,
}

impl<R> Logged<R> {
    /// An empty log around `inner`.
    pub fn new(inner: R) -> Self {
        Self { inner, rays: RefCell::new(Vec::new()) }
    }

    /// The queries answered so far.
    pub fn into_rays(self) -> Vec<Ray> {
        self.rays.into_inner()
    }
}

impl<R: RayCaster> RayCaster for &Logged<R> {
    fn closest_hit(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> Hit {
        self.rays.borrow_mut().push(Ray::new(RAY_CLOSEST, o, d, tmin, tmax, key));
        self.inner.closest_hit(o, d, tmin, tmax, key)
    }

    fn occluded(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> bool {
        self.rays.borrow_mut().push(Ray::new(RAY_OCCLUSION, o, d, tmin, tmax, key));
        self.inner.occluded(o, d, tmin, tmax, key)
    }
}

/// The rays of one iteration's candidates, laid out for the `raycast` kernel.
#[derive(Clone, Debug)]
pub struct RayLog {
    /// Candidates C.
    pub candidates: u32,
    /// Ray j of candidate k at `k + j·C`; candidates with fewer rays are padded with `RAY_NONE`.
    pub rays: Vec<Ray>,
    /// Rays cast (the padding not counted).
    pub count: u64,
}

impl RayLog {
    /// The log of `lists`, candidate k's rays in `lists[k]`, laid out for the `raycast` kernel.
    pub fn from_lists(lists: &[Vec<Ray>]) -> Self {
        let c = lists.len();
        let most = lists.iter().map(Vec::len).max().unwrap_or(0);
        let mut rays = vec![Ray::default(); most * c];
        for (k, list) in lists.iter().enumerate() {
            for (j, ray) in list.iter().enumerate() {
                rays[k + j * c] = *ray;
            }
        }
        RayLog { candidates: c as u32, rays, count: lists.iter().map(|l| l.len() as u64).sum() }
    }

    /// Rays cast per candidate.
    pub fn per_candidate(&self) -> f64 {
        self.count as f64 / self.candidates.max(1) as f64
    }
}

/// Logs the rays that `trace` and then `connect` cast for every candidate of `cand_u` and
/// `cand_depth` (as the device holds them after a `mutate` pass; the path estimator's
/// `connect` then writes its own depths, to a copy) under `params`.
pub fn log_candidates(
    scene: &SceneData,
    params: &RenderParams,
    cand_u: &[f32],
    cand_depth: &[u32],
) -> RayLog {
    let c = params.candidates as usize;
    let mut vertices = vec![PathVertex::default(); c * vertex_slots(params.max_depth) as usize];
    let mut paths = vec![PathInfo::default(); c];
    let mut contributions = vec![Vec4::ZERO; c];
    // The path estimator's connect writes each path's vertex count here; the log needs none.
    let mut cand_depth_out = cand_depth.to_vec();
    let mut per_candidate: Vec<Vec<Ray>> = Vec::with_capacity(c);
    // The pixel importance scales contributions, never rays.
    let importance = vec![1.0f32; (params.width * params.height) as usize];
    let caster = scene.shared().caster;
    for k in 0..c {
        let log = Logged::new(caster);
        let logging = scene.with_caster(&log);
        let trace = TraceIo {
            params,
            cand_depth,
            cand_u,
            vertices: &mut vertices,
            paths: &mut paths,
            scene: logging,
        };
        kernels::trace::trace(k, trace);
        let connect = ConnectIo {
            params,
            cand_u,
            vertices: &vertices,
            paths: &paths,
            importance: &importance,
            contributions: &mut contributions,
            cand_depth: &mut cand_depth_out,
            scene: logging,
        };
        kernels::connect::connect(k, connect);
        per_candidate.push(log.into_rays());
    }
    RayLog::from_lists(&per_candidate)
}

/// Paths whose rays [`log_paths`] logs at most: enough for a steady replay, few enough that
/// a 1080p render's log stays small.
pub const LOGGED_PATHS: u32 = 1 << 16;

/// Logs the rays of one sample of the path tracer (`shared::path_tracer::pixel_sample` under
/// `params`, sample number `params.round · params.samples_per_round`) through every `stride`-th
/// pixel, [`LOGGED_PATHS`] at most, the pixels spread evenly over the image, as `groups` logs
/// of consecutive pixels (the CPU backend's replay runs the logs in parallel).
pub fn log_paths(scene: &SceneData, params: &PathTracerParams, groups: u32) -> Vec<RayLog> {
    let pixels = params.width * params.height;
    let stride = pixels.div_ceil(LOGGED_PATHS).max(1);
    let chosen: Vec<u32> = (0..pixels).step_by(stride as usize).collect();
    let caster = scene.shared().caster;
    let sample = params.round * params.samples_per_round;
    let per_group = chosen.len().div_ceil(groups.max(1) as usize).max(1);
    chosen
        .chunks(per_group)
        .map(|pixels| {
            let lists: Vec<Vec<Ray>> = pixels
                .iter()
                .map(|&pixel| {
                    let log = Logged::new(caster);
                    shared::path_tracer::pixel_sample(params, scene.with_caster(&log), pixel, sample);
                    log.into_rays()
                })
                .collect();
            RayLog::from_lists(&lists)
        })
        .collect()
}

/// A timed replay of a [`RayLog`] on the device.
#[derive(Clone, Debug)]
pub struct Replay {
    /// Mean device seconds of one replay of every ray (after a warm-up replay).
    pub seconds: f64,
    /// How it was timed.
    pub clock: Clock,
    /// Each candidate's summed answers (`shared::rays::cast`), for checking against the host.
    pub answers: Vec<u32>,
}

impl Replay {
    /// Rays cast per second.
    pub fn rays_per_s(&self, log: &RayLog) -> f64 {
        log.count as f64 / self.seconds
    }
}

/// The `raycast` pass over `rays` (ray j of invocation k at `k + j·candidates`), its buffers
/// made, and the buffer of its answers.
fn replay_pass(
    gpu: &Gpu,
    scene: &SceneData,
    rays: &[Ray],
    candidates: u32,
) -> Result<(passes::Pass, wgpu::Buffer), RenderError> {
    let limit = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
    let bytes = std::mem::size_of_val(rays) as u64;
    if bytes > limit {
        return Err(RenderError::TooLarge(format!(
            "the replayed rays need {:.1} MiB but the device allows {:.1} MiB per storage buffer; \
             lower --candidates",
            bytes as f64 / 1048576.0,
            limit as f64 / 1048576.0
        )));
    }
    let params = RenderParams { candidates, ..Default::default() };
    let params_buffer = gpu.storage_from("raycast params", &[params]);
    let mut storage = OnDevice::new(gpu.clone());
    SceneBuffers::new(&mut storage, scene);
    let scene_buffers = storage.registry();
    let rays = gpu.storage_from("replayed rays", rays);
    let answers = gpu.storage_zeroed::<u32>("ray answers", candidates as usize);
    let pass = passes::raycast::gpu(gpu, [&params_buffer, &rays, &answers], &scene_buffers)?;
    Ok((pass, answers))
}

/// Casts `rays` once on `gpu` (laid out for `candidates` invocations) and returns each
/// invocation's summed answers.
pub fn replay_rays(
    gpu: &Gpu,
    scene: &SceneData,
    rays: &[Ray],
    candidates: u32,
) -> Result<Vec<u32>, RenderError> {
    let (pass, answers) = replay_pass(gpu, scene, rays, candidates)?;
    time_passes(gpu, &[(&pass, candidates)])?;
    Ok(gpu.read(&answers, candidates as usize)?)
}

/// Replays `log` on `gpu` `repeats` times (plus one warm-up) with nothing but the ray queries.
pub fn replay(gpu: &Gpu, scene: &SceneData, log: &RayLog, repeats: u32) -> Result<Replay, RenderError> {
    let (pass, answers) = replay_pass(gpu, scene, &log.rays, log.candidates)?;
    let (_, clock) = time_passes(gpu, &[(&pass, log.candidates)])?;
    let mut seconds = 0.0;
    for _ in 0..repeats.max(1) {
        seconds += time_passes(gpu, &[(&pass, log.candidates)])?.0[0];
    }
    // Every replay writes the same answers; read the last.
    let answers = gpu.read(&answers, log.candidates as usize)?;
    Ok(Replay { seconds: seconds / repeats.max(1) as f64, clock, answers })
}

/// Replays `logs` (one a group of chains) on the CPU backend's `pool` `repeats` times (plus one
/// warm-up) through the CPU backend's ray caster, the groups in parallel as in a render, with
/// nothing but the ray queries. Rays/s counts every thread together.
pub fn replay_on_host(pool: &rayon::ThreadPool, scene: &SceneData, logs: &[RayLog], repeats: u32) -> Replay {
    use rayon::prelude::*;
    let shared = scene.shared();
    let once = || -> Vec<Vec<u32>> {
        pool.install(|| {
            logs.par_iter()
                .map(|log| {
                    let params = RenderParams { candidates: log.candidates, ..Default::default() };
                    let mut answers = vec![0u32; log.candidates as usize];
                    passes::raycast::cpu(&params, shared, &log.rays, &mut answers);
                    answers
                })
                .collect()
        })
    };
    once();
    let start = std::time::Instant::now();
    let mut answers = Vec::new();
    for _ in 0..repeats.max(1) {
        answers = once();
    }
    let seconds = start.elapsed().as_secs_f64() / repeats.max(1) as f64;
    Replay { seconds, clock: Clock::Wall, answers: answers.concat() }
}
