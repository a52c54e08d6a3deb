//! The bench's look inside an iteration, per method: the device time of each pass (timestamp
//! queries, `crate::timing`), and the ray-casting ceiling (`crate::raycast`): rays cast per
//! candidate, the bare rays/s of replaying exactly those rays, and how close the measured
//! mutation throughput comes to `rays/s ÷ rays per candidate`.
//!
//! Trace and connect time per candidate shows what the candidates' coherence buys; select's
//! time shows what fewer chains (one select thread per chain) buy.

use std::fmt::Write as _;

use crate::passes::Stage;
use crate::raycast::{log_candidates, replay};
use crate::render::gpu::GpuBackend;
use crate::render::RenderError;
use crate::scene::SceneData;
use crate::timing::Clock;
use shared::mmlt::RenderParams;

/// Iterations timed per method.
pub const TIMED_ITERATIONS: u32 = 16;
/// Replays of the logged rays timed per method.
pub const REPLAYS: u32 = 4;

/// One method's profile on one scene view.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    /// Scene name.
    pub scene: String,
    /// View.
    pub view: u32,
    /// Method.
    pub method: String,
    /// Candidates per iteration.
    pub candidates: u32,
    /// How the passes were timed.
    pub clock: Clock,
    /// Mean device milliseconds of each stage per iteration ([`Stage::ITERATION`] order).
    pub pass_ms: [f64; 5],
    /// Rays cast per candidate (trace and connect).
    pub rays_per_candidate: f64,
    /// Rays/s of the bare replay of those rays.
    pub bare_rays_per_s: f64,
    /// Candidates/s measured in the equal-time run.
    pub mutations_per_s: f64,
    /// MiB of the render's device buffers (`render::gpu::device_bytes`).
    pub device_mib: f64,
}

impl Profile {
    /// Candidates/s if the device did nothing but cast their rays.
    pub fn ceiling_mutations_per_s(&self) -> f64 {
        self.bare_rays_per_s / self.rays_per_candidate
    }

    /// Measured over ceiling mutation throughput.
    pub fn ceiling_fraction(&self) -> f64 {
        self.mutations_per_s / self.ceiling_mutations_per_s()
    }

    /// Mean device milliseconds of `stage` per iteration.
    pub fn ms(&self, stage: Stage) -> f64 {
        self.pass_ms[stage.index()]
    }

    /// Device milliseconds of a whole iteration (the passes' sum).
    pub fn iteration_ms(&self) -> f64 {
        self.pass_ms.iter().sum()
    }

    /// Trace and connect nanoseconds per candidate.
    pub fn trace_connect_ns(&self) -> f64 {
        (self.ms(Stage::Trace) + self.ms(Stage::Connect)) * 1e6 / self.candidates as f64
    }

    /// The profile as CSV.
    pub fn csv(&self) -> String {
        let stages: Vec<String> = self.pass_ms.iter().map(|ms| format!("{ms:.4}")).collect();
        format!(
            "{},{},{},{},{},{},{:.4},{:.1},{:.1},{:.1},{:.4},{:.2}",
            self.scene,
            self.view,
            self.method,
            self.candidates,
            self.clock,
            stages.join(","),
            self.rays_per_candidate,
            self.bare_rays_per_s,
            self.ceiling_mutations_per_s(),
            self.mutations_per_s,
            self.ceiling_fraction(),
            self.device_mib
        )
    }
}

/// The CSV header of `passes.csv`: a `<stage>_ms` column per stage.
pub fn csv_header() -> String {
    let stages: Vec<String> = Stage::ITERATION.iter().map(|s| format!("{}_ms", s.name())).collect();
    format!(
        "scene,view,method,candidates,clock,{},rays_per_candidate,bare_rays_per_s,ceiling_mutations_per_s,\
         mutations_per_s,ceiling_fraction,device_mib",
        stages.join(",")
    )
}

/// Profiles `method`'s render of `scene` (named `label`, view `view`) on `backend` from
/// `params` (the next iteration's), whose equal-time run measured `mutations_per_s`: times
/// [`TIMED_ITERATIONS`] iterations pass by pass, then logs the rays of the last iteration's
/// candidates on the host and replays them bare on the device.
pub fn profile(
    backend: &mut GpuBackend,
    scene: &SceneData,
    (label, view, method): (&str, u32, &str),
    params: RenderParams,
    mutations_per_s: f64,
) -> Result<Profile, RenderError> {
    let mut total = [0.0f64; 5];
    let mut clock = Clock::Wall;
    let mut last = params;
    for i in 0..TIMED_ITERATIONS {
        last = RenderParams { iteration: params.iteration + i, ..params };
        let (seconds, c) = backend.iterate_timed(&last)?;
        clock = c;
        for (sum, s) in total.iter_mut().zip(seconds) {
            *sum += s;
        }
    }
    let gpu = backend.gpu().clone();
    let c = last.candidates as usize;
    let cand_u: Vec<f32> = gpu.read(&backend.buffers().cand_u, c * last.dims as usize)?;
    let cand_depth: Vec<u32> = gpu.read(&backend.buffers().cand_depth, c)?;
    let log = log_candidates(scene, &last, &cand_u, &cand_depth);
    let replayed = replay(&gpu, scene, &log, REPLAYS)?;
    Ok(Profile {
        scene: label.to_string(),
        view,
        method: method.to_string(),
        candidates: last.candidates,
        clock,
        pass_ms: total.map(|s| s * 1e3 / TIMED_ITERATIONS as f64),
        rays_per_candidate: log.per_candidate(),
        bare_rays_per_s: replayed.rays_per_s(&log),
        mutations_per_s,
        device_mib: crate::render::gpu::device_bytes(scene, &last) as f64 / 1048576.0,
    })
}

/// Markdown tables of `profiles`, one per scene view: each pass's device time per iteration,
/// and the ray-casting ceiling.
pub fn tables(profiles: &[Profile]) -> String {
    let mut out = String::new();
    let mut views: Vec<(String, u32)> = Vec::new();
    for p in profiles {
        if !views.contains(&(p.scene.clone(), p.view)) {
            views.push((p.scene.clone(), p.view));
        }
    }
    for (scene, view) in views {
        let rows: Vec<&Profile> = profiles.iter().filter(|p| p.scene == scene && p.view == view).collect();
        let clock = rows.first().map(|p| p.clock).unwrap_or(Clock::Wall);
        let names: Vec<&str> = Stage::ITERATION.iter().map(|s| s.name()).collect();
        let _ = writeln!(
            out,
            "### Inside an iteration: {scene} v{view} (device ms per iteration, {clock} clock)\n\n\
             | method | candidates | {} | total | trace+connect ns/candidate \
             | rays/candidate | bare M rays/s | ceiling M mut/s | measured M mut/s | of ceiling | device MiB |\n\
             |---|---|{}---|---|---|---|---|---|---|---|",
            names.join(" | "),
            "---|".repeat(names.len())
        );
        for p in rows {
            let stages: Vec<String> = p.pass_ms.iter().map(|ms| format!("{ms:.2}")).collect();
            let _ = writeln!(
                out,
                "| {} | {} | {} | {:.2} | {:.1} | {:.2} | {:.1} | {:.2} | {:.2} | {:.0} % | {:.1} |",
                p.method,
                p.candidates,
                stages.join(" | "),
                p.iteration_ms(),
                p.trace_connect_ns(),
                p.rays_per_candidate,
                p.bare_rays_per_s / 1e6,
                p.ceiling_mutations_per_s() / 1e6,
                p.mutations_per_s / 1e6,
                100.0 * p.ceiling_fraction(),
                p.device_mib
            );
        }
        out.push('\n');
    }
    out
}
