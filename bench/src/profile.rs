//! The bench's look inside an iteration, per method: the time of each pass (timestamp queries
//! on a device, `smlt::timing`; wall time of each stage over all groups on the CPU backend),
//! and the ray-casting ceiling (`crate::raycast`): rays cast per candidate, the bare rays/s of
//! replaying exactly those rays (on the device, or on the CPU backend's threads through its
//! ray caster), and how close the measured mutation throughput comes to
//! `rays/s ÷ rays per candidate`.
//!
//! Trace and connect time per candidate shows what the candidates' coherence buys; select's
//! time shows what fewer chains (one select thread per chain) buy.

use std::fmt::Write as _;

use crate::raycast::{log_candidates, log_paths, replay, replay_on_host, RayLog};
use crate::results::first_seen;
use shared::params::RenderParams;
use shared::path_tracer::PathTracerParams;
use smlt::passes::Stage;
use smlt::render::cpu::CpuBackend;
use smlt::render::gpu::{GpuBackend, PassTimes};
use smlt::render::{Backend, RenderError};
use smlt::scene::SceneData;
use smlt::timing::Clock;

/// Iterations timed per method.
pub const TIMED_ITERATIONS: u32 = 16;
/// Replays of the logged rays timed per method.
pub const REPLAYS: u32 = 4;

/// One method's profile on one scene view.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    /// The scene's label: a generated scene's name or a glTF file's stem.
    pub scene: String,
    /// The view: 1-based index among the scene's cameras.
    pub view: u32,
    /// The method as printed: `naive`, `s<d>` or `rc<l>`.
    pub method: String,
    /// Candidates per iteration.
    pub candidates: u32,
    /// How the passes were timed.
    pub clock: Clock,
    /// Mean device milliseconds of each stage per iteration ([`Stage::ITERATION`] order).
    pub pass_ms: [f64; Stage::COUNT],
    /// Rays cast per candidate (trace and connect).
    pub rays_per_candidate: f64,
    /// Rays/s of the bare replay of those rays.
    pub bare_rays_per_s: f64,
    /// Candidates/s measured in the equal-time run.
    pub mutations_per_s: f64,
    /// MiB of the render's buffers on a device (`passes::buffers::device_bytes`; the CPU backend
    /// holds the iteration buffers of that list and reads the scene in place).
    pub device_mib: f64,
    /// Threads of the CPU backend; 0 on a device.
    pub threads: usize,
}

impl Profile {
    /// Candidates/s if the device did nothing but cast their rays.
    pub fn ceiling_mutations_per_s(&self) -> f64 {
        self.bare_rays_per_s / self.rays_per_candidate
    }

    /// Bare rays/s per CPU thread (per device on a device).
    pub fn bare_rays_per_s_per_thread(&self) -> f64 {
        self.bare_rays_per_s / self.threads.max(1) as f64
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
            "{},{},{},{},{},{},{:.4},{:.1},{:.1},{:.1},{:.4},{:.2},{}",
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
            self.device_mib,
            self.threads
        )
    }
}

/// The CSV header of `passes.csv`: a `<stage>_ms` column per stage.
pub fn csv_header() -> String {
    let stages: Vec<String> = Stage::ITERATION.iter().map(|s| format!("{}_ms", s.name())).collect();
    format!(
        "scene,view,method,candidates,clock,{},rays_per_candidate,bare_rays_per_s,ceiling_mutations_per_s,\
         mutations_per_s,ceiling_fraction,device_mib,threads",
        stages.join(",")
    )
}

/// What a profile is of: scene label, view and method.
pub type Profiled<'a> = (&'a str, u32, &'a str);

/// A render backend the bench can look inside (both of smlt's): an iteration timed stage by
/// stage, its candidates' rays logged, and those rays replayed bare where it casts them.
pub trait ProfiledBackend: Backend {
    /// One iteration with `params`, each stage's seconds and the clock that timed them.
    fn timed_iteration(&mut self, params: &RenderParams) -> Result<(PassTimes, Clock), RenderError>;
    /// The rays the candidates of the last iteration (`last`) cast, logged on the host: one log
    /// per group of chains.
    fn ray_logs(&self, scene: &SceneData, last: &RenderParams) -> Result<Vec<RayLog>, RenderError>;
    /// Seconds a replay of `logs` takes, bare, where the backend casts rays.
    fn replay_seconds(&self, scene: &SceneData, logs: &[RayLog]) -> Result<f64, RenderError>;
    /// The host threads that replay (0 on a device).
    fn replay_threads(&self) -> usize;
}

/// On a device: each stage timed by the device's timestamps, the rays replayed by the
/// `raycast` kernel.
impl ProfiledBackend for GpuBackend {
    fn timed_iteration(&mut self, params: &RenderParams) -> Result<(PassTimes, Clock), RenderError> {
        self.iterate_timed(params)
    }

    fn ray_logs(&self, scene: &SceneData, last: &RenderParams) -> Result<Vec<RayLog>, RenderError> {
        let c = last.candidates as usize;
        let cand_u: Vec<f32> = self.gpu().read(&self.buffers().iteration.cand_u, c * last.dims as usize)?;
        let cand_depth: Vec<u32> = self.gpu().read(&self.buffers().iteration.cand_depth, c)?;
        Ok(vec![log_candidates(scene, last, &cand_u, &cand_depth)])
    }

    fn replay_seconds(&self, scene: &SceneData, logs: &[RayLog]) -> Result<f64, RenderError> {
        let mut seconds = 0.0;
        for log in logs {
            seconds += replay(self.gpu(), scene, log, REPLAYS)?.seconds;
        }
        Ok(seconds)
    }

    fn replay_threads(&self) -> usize {
        0
    }
}

/// On the CPU backend: each stage timed over all groups, the rays of every group's candidates
/// replayed bare on the backend's threads.
impl ProfiledBackend for CpuBackend<'_> {
    fn timed_iteration(&mut self, params: &RenderParams) -> Result<(PassTimes, Clock), RenderError> {
        Ok((self.iterate_timed(params), Clock::Wall))
    }

    fn ray_logs(&self, scene: &SceneData, last: &RenderParams) -> Result<Vec<RayLog>, RenderError> {
        Ok(self
            .candidates(last)
            .into_iter()
            .map(|(p, u, depth)| log_candidates(scene, &p, u, depth))
            .collect())
    }

    fn replay_seconds(&self, scene: &SceneData, logs: &[RayLog]) -> Result<f64, RenderError> {
        let pool = self.thread_pool().expect("the CPU backend has a pool");
        Ok(replay_on_host(pool, scene, logs, REPLAYS).seconds)
    }

    fn replay_threads(&self) -> usize {
        self.threads()
    }
}

/// Profiles `what`'s render of `scene` on `backend` from `params` (the next iteration's), whose
/// equal-time run measured `mutations_per_s`: times [`TIMED_ITERATIONS`] iterations stage by
/// stage, then logs the rays of the last iteration's candidates on the host and replays them
/// bare where the backend casts them.
pub fn profile(
    backend: &mut dyn ProfiledBackend,
    scene: &SceneData,
    what: Profiled,
    params: RenderParams,
    mutations_per_s: f64,
) -> Result<Profile, RenderError> {
    let (last, clock, total) = timed_iterations(params, |p| backend.timed_iteration(p))?;
    let logs = backend.ray_logs(scene, &last)?;
    let seconds = backend.replay_seconds(scene, &logs)?;
    let threads = backend.replay_threads();
    Ok(assemble(scene, what, (&last, clock, total), &logs, seconds, mutations_per_s, threads))
}

/// The path tracer's ray-casting ceiling on `backend`, whose equal-time run of `what` under
/// `params` measured `paths_per_s`: the rays of one sample through pixels spread over the image
/// ([`log_paths`]), replayed bare where the backend casts rays. The path tracer has no stages,
/// so the profile's pass times are NaN; its candidates are the paths of a round.
pub fn path_tracer_profile(
    backend: &dyn ProfiledBackend,
    scene: &SceneData,
    what: Profiled,
    params: &PathTracerParams,
    paths_per_s: f64,
) -> Result<Profile, RenderError> {
    let threads = backend.replay_threads();
    // A few logs a thread, so that the host's threads share the replay as they share a round.
    let logs = log_paths(scene, params, (4 * threads).max(1) as u32);
    let seconds = backend.replay_seconds(scene, &logs)?;
    let rays: u64 = logs.iter().map(|l| l.count).sum();
    let paths: u64 = logs.iter().map(|l| l.candidates as u64).sum();
    Ok(Profile {
        scene: what.0.to_string(),
        view: what.1,
        method: what.2.to_string(),
        candidates: params.width * params.height * params.samples,
        clock: Clock::Wall,
        pass_ms: [f64::NAN; Stage::COUNT],
        rays_per_candidate: rays as f64 / paths.max(1) as f64,
        bare_rays_per_s: rays as f64 / seconds,
        mutations_per_s: paths_per_s,
        device_mib: 0.0,
        threads,
    })
}

/// Runs [`TIMED_ITERATIONS`] iterations from `params` through `iterate` (seconds per stage and
/// the clock that timed them); returns the last iteration's parameters, the clock and each
/// stage's summed seconds.
fn timed_iterations(
    params: RenderParams,
    mut iterate: impl FnMut(&RenderParams) -> Result<(PassTimes, Clock), RenderError>,
) -> Result<(RenderParams, Clock, PassTimes), RenderError> {
    let mut total = [0.0f64; Stage::COUNT];
    let (mut last, mut clock) = (params, Clock::Wall);
    for i in 0..TIMED_ITERATIONS {
        last = RenderParams { iteration: params.iteration + i, ..params };
        let (seconds, c) = iterate(&last)?;
        clock = c;
        for (sum, s) in total.iter_mut().zip(seconds) {
            *sum += s;
        }
    }
    Ok((last, clock, total))
}

/// A profile from the timed passes (params of the last timed iteration, clock, summed seconds)
/// and the replayed ray logs.
fn assemble(
    scene: &SceneData,
    (label, view, method): Profiled,
    (last, clock, total): (&RenderParams, Clock, PassTimes),
    logs: &[RayLog],
    replay_seconds: f64,
    mutations_per_s: f64,
    threads: usize,
) -> Profile {
    let rays: u64 = logs.iter().map(|l| l.count).sum();
    let candidates: u64 = logs.iter().map(|l| l.candidates as u64).sum();
    Profile {
        scene: label.to_string(),
        view,
        method: method.to_string(),
        candidates: last.candidates,
        clock,
        pass_ms: total.map(|s| s * 1e3 / TIMED_ITERATIONS as f64),
        rays_per_candidate: rays as f64 / candidates.max(1) as f64,
        bare_rays_per_s: rays as f64 / replay_seconds,
        mutations_per_s,
        device_mib: smlt::passes::buffers::device_bytes(scene, last) as f64 / 1048576.0,
        threads,
    }
}

/// Markdown tables of `profiles`, one per scene view: each pass's device time per iteration,
/// and the ray-casting ceiling.
pub fn tables(profiles: &[Profile]) -> String {
    let mut out = String::new();
    for (scene, view) in first_seen(profiles.iter().map(|p| (p.scene.clone(), p.view))) {
        let rows: Vec<&Profile> = profiles.iter().filter(|p| p.scene == scene && p.view == view).collect();
        // The path tracer's row has no passes, and no clock of its own.
        let clock = rows.iter().find(|p| p.iteration_ms().is_finite()).map_or(Clock::Wall, |p| p.clock);
        let names: Vec<&str> = Stage::ITERATION.iter().map(|s| s.name()).collect();
        let _ = writeln!(
            out,
            "### Inside an iteration: {scene} v{view} (ms per iteration, {clock} clock)\n\n\
             | method | candidates | {} | total | trace+connect ns/candidate \
             | rays/candidate | bare M rays/s | per thread | ceiling M mut/s | measured M mut/s | of ceiling | device MiB |\n\
             |---|---|{}---|---|---|---|---|---|---|---|---|",
            names.join(" | "),
            "---|".repeat(names.len())
        );
        for p in rows {
            let stages: Vec<String> = p.pass_ms.iter().map(|&ms| finite(ms, 2)).collect();
            let _ = writeln!(
                out,
                "| {} | {} | {} | {} | {} | {:.2} | {:.2} | {} | {:.2} | {:.2} | {:.0} % | {:.1} |",
                p.method,
                p.candidates,
                stages.join(" | "),
                finite(p.iteration_ms(), 2),
                finite(p.trace_connect_ns(), 1),
                p.rays_per_candidate,
                p.bare_rays_per_s / 1e6,
                if p.threads > 0 {
                    format!("{:.2}", p.bare_rays_per_s_per_thread() / 1e6)
                } else {
                    "–".into()
                },
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

/// `x` to `decimals` places, or a dash where it is not measured (NaN: the path tracer's passes).
fn finite(x: f64, decimals: usize) -> String {
    if x.is_nan() {
        "–".into()
    } else {
        format!("{x:.decimals$}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The path tracer's row shows its ray ceiling and a dash for each pass it does not have.
    #[test]
    fn the_path_tracers_row_has_a_ceiling_and_no_passes() {
        let pt = Profile {
            scene: "cornell".into(),
            view: 1,
            method: "pt".into(),
            candidates: 9216,
            clock: Clock::Wall,
            pass_ms: [f64::NAN; Stage::COUNT],
            rays_per_candidate: 8.0,
            bare_rays_per_s: 6.4e6,
            mutations_per_s: 0.4e6,
            device_mib: 0.0,
            threads: 2,
        };
        let naive = Profile {
            method: "naive".into(),
            clock: Clock::Timestamp,
            pass_ms: [1.0; Stage::COUNT],
            ..pt.clone()
        };
        assert!(
            (pt.ceiling_mutations_per_s() - 0.8e6).abs() < 1e-6
                && (pt.ceiling_fraction() - 0.5).abs() < 1e-12
        );
        let table = tables(&[pt, naive]);
        let row = table.lines().find(|l| l.starts_with("| pt |")).expect("the pt row");
        assert_eq!(row.matches("| – ").count(), Stage::COUNT + 2, "{row}");
        assert!(row.contains("| 0.80 | 0.40 | 50 % |"), "{row}");
        // The clock is the one that timed the passes.
        assert!(table.contains("timestamp clock"), "{table}");
    }
}
