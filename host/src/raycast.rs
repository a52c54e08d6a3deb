//! The ray-casting ceiling of the bench: the rays that one iteration's candidates cast, logged
//! on the host by running the same `trace` and `connect` bodies over the device's candidate
//! buffer (`shared::rays::logged`), then replayed bare on the device by the `raycast` kernel.
//! Rays per candidate and bare rays/s give the most candidates a second the device could trace
//! if casting rays were all it did: `rays/s ÷ rays per candidate`.

use glam::Vec4;
use shared::mmlt::{vertex_slots, PathInfo, PathVertex, RenderParams};
use shared::rays::{logged, Ray};

use crate::gpu::Gpu;
use crate::passes;
use crate::render::RenderError;
use crate::scene::SceneData;
use crate::timing::{time_passes, Clock};

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
    /// Rays cast per candidate.
    pub fn per_candidate(&self) -> f64 {
        self.count as f64 / self.candidates.max(1) as f64
    }
}

/// Logs the rays that `trace` and then `connect` cast for every candidate of `cand_u` and
/// `cand_depth` (as the device holds them after a `mutate` pass) under `params`.
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
    let mut per_candidate: Vec<Vec<Ray>> = Vec::with_capacity(c);
    for k in 0..c {
        let ((), rays) = logged(|| {
            kernels::trace::trace(k, params, cand_depth, cand_u, scene.shared(), &mut vertices, &mut paths);
            kernels::connect::connect(
                k,
                params,
                cand_u,
                scene.shared(),
                &vertices,
                &paths,
                &mut contributions,
            );
        });
        per_candidate.push(rays);
    }
    let most = per_candidate.iter().map(Vec::len).max().unwrap_or(0);
    let mut rays = vec![Ray::default(); most * c];
    for (k, list) in per_candidate.iter().enumerate() {
        for (j, ray) in list.iter().enumerate() {
            rays[k + j * c] = *ray;
        }
    }
    RayLog { candidates: c as u32, rays, count: per_candidate.iter().map(|l| l.len() as u64).sum() }
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

/// Replays `log` on `gpu` `repeats` times (plus one warm-up) with nothing but the ray queries.
pub fn replay(gpu: &Gpu, scene: &SceneData, log: &RayLog, repeats: u32) -> Result<Replay, RenderError> {
    let limit = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
    let bytes = std::mem::size_of_val(&log.rays[..]) as u64;
    if bytes > limit {
        return Err(RenderError::TooLarge(format!(
            "the replayed rays need {:.1} MiB but the device allows {:.1} MiB per storage buffer; \
             lower --candidates",
            bytes as f64 / 1048576.0,
            limit as f64 / 1048576.0
        )));
    }
    let params = RenderParams { candidates: log.candidates, ..Default::default() };
    let params_buffer = gpu.storage_from("raycast params", &[params]);
    let nodes = gpu.storage_from("BVH nodes", &scene.nodes);
    let triangles = gpu.storage_from("triangles", &scene.triangles);
    let rays = gpu.storage_from("replayed rays", &log.rays);
    let answers = gpu.storage_zeroed::<u32>("ray answers", log.candidates as usize);
    let pass = passes::raycast::gpu(gpu, [&params_buffer, &nodes, &triangles, &rays, &answers])?;
    let (_, clock) = time_passes(gpu, &[(&pass, log.candidates)])?;
    let mut seconds = 0.0;
    for _ in 0..repeats.max(1) {
        seconds += time_passes(gpu, &[(&pass, log.candidates)])?.0[0];
    }
    // Every replay writes the same answers; read the last.
    let answers = gpu.read(&answers, log.candidates as usize)?;
    Ok(Replay { seconds: seconds / repeats.max(1) as f64, clock, answers })
}
