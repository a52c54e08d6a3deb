//! `smlt bench`: the paper's evaluation on our scenes — equal-time runs of each method per
//! scene/view in one process on one device, interleaved (every method is advanced in turns to
//! the same render times 1, 2, 4, … s), each compared with the scene's reference image.
//!
//! Writes to the output folder: `results.csv` (one row per method and time: scene, view,
//! method, seconds, candidates, steps, mutations/s, steps/s, RMSE, relMSE, PSNR, the
//! candidates rejected as NaN/Inf, b and its relative standard error — error along time, so convergence is a curve; one scene,
//! one method and a long time is the soak run), `tables.md` (the paper's Table 3: million mutations/s, and
//! Table 4: PSNR after the full time), the plots of `plots` (`speedup.png`, the paper's Fig. 7,
//! and `error_<scene>_v<view>.png`, RMSE against time on log–log axes), the final image of each
//! method and error heat maps of naive and the best method (`metrics::heat_map`), and the cached
//! references; and `passes.csv` and its tables (`profile`: each pass's time per
//! iteration, rays per candidate and the bare ray throughput, on a device or on the CPU
//! backend's threads).

pub mod interval;
pub mod metrics;
pub mod plots;
pub mod profile;
pub mod raycast;
pub mod results;
pub mod tables;

use std::path::{Path, PathBuf};

use shared::params::RenderParams;

use metrics::{errors, heat_map};
use profile::{path_tracer_profile, profile, Profile, ProfiledBackend};
use results::{final_row, Row, CSV_HEADER};
use smlt::gpu::Gpu;
use smlt::reference::{cached_or_render, read_sidecar, sidecar, ReferenceSettings};
use smlt::render::auto::KeptPilot;
use smlt::render::{self, Backend, Budget, Method, MethodChoice, Renderer, Settings};
use smlt::scene::SceneData;

/// What to measure.
#[derive(Clone, Debug)]
pub struct BenchSettings {
    /// (scene name, view): generated scenes by name, or glTF paths.
    pub scenes: Vec<(String, u32)>,
    /// Methods to compare (`auto`: the method its pilot chooses, the pilot's time counted).
    pub methods: Vec<MethodChoice>,
    /// Every method's render, but for its method (each takes the integrator its name gives,
    /// with these chain settings), its seed (repeat r uses `seed + r`), its budget (`seconds`)
    /// and, where `candidates` is None, its candidates (by device, as `smlt render`).
    pub render: Settings,
    /// Candidates per iteration (None: by device, as `smlt render`).
    pub candidates: Option<u32>,
    /// Render seconds per method.
    pub seconds: f64,
    /// Samples per pixel of the references.
    pub reference_spp: u32,
    /// Tessellation of generated scenes.
    pub tessellation: u32,
    /// The environment light every scene is lit by besides its own lights (`--environment`).
    pub environment: Option<smlt::scene::EnvironmentSpec>,
    /// Threads of the CPU backend.
    pub threads: usize,
    /// Independent runs of every method (seeds `seed`, `seed + 1`, …).
    pub repeats: u32,
    /// A reference image to use instead of rendering one (one scene view only).
    pub reference: Option<PathBuf>,
    /// Folder for `results.csv`, `passes.csv`, `tables.md`, the plots and the references.
    pub out: PathBuf,
}

impl BenchSettings {
    /// The settings of `method`'s run in repeat `repeat` with `candidates` per iteration.
    pub fn settings(&self, method: Method, repeat: u32, candidates: u32) -> Settings {
        Settings {
            seed: self.render.seed.wrapping_add(repeat),
            budget: Budget::Seconds(self.seconds),
            candidates,
            shard: render::Shard::WHOLE,
            ..self.render.clone().with_method(method)
        }
    }
}

/// The render times at which every method is measured: 1, 2, 4, … below `seconds`, and `seconds`.
pub fn time_grid(seconds: f64) -> Vec<f64> {
    let mut grid = Vec::new();
    let mut t = 1.0;
    while t < seconds {
        grid.push(t);
        t *= 2.0;
    }
    grid.push(seconds);
    grid
}

/// Runs the bench; `log` gets one line per measurement.
pub fn run(b: &BenchSettings, gpu: Option<&Gpu>, mut log: impl FnMut(&str)) -> anyhow::Result<Vec<Row>> {
    std::fs::create_dir_all(&b.out)?;
    let mut rows = Vec::new();
    let mut profiles: Vec<Profile> = Vec::new();
    let mut noises: Vec<(String, u32, Option<f64>)> = Vec::new();
    let mut blind = Vec::new();
    let mut choices = Vec::new();
    for (name, view) in &b.scenes {
        let (label, mut scene, scene_hash) =
            smlt::scenes::open_with_environment(Some(name), b.tessellation, b.environment.as_ref())?;
        scene.select_view(*view)?;
        for m in &b.methods {
            let MethodChoice::Named(m) = m else { continue };
            if let Some(why) = smlt::render::blind_spot(*m, &scene) {
                log(&format!("note: {label} v{view}: {why}"));
                blind.push((label.clone(), *view, m.to_string(), why));
            }
        }
        let (reference, noise) = match &b.reference {
            Some(path) => given_reference(b, path, (&scene_hash, *view))?,
            None => reference_image(b, (&label, *view), &scene, scene_hash, gpu)?,
        };
        noises.push((label.clone(), *view, noise));
        let repeats = b.repeats.max(1);
        for repeat in 0..repeats {
            let first = rows.len();
            let run = EqualTime { scene: &scene, label: &label, view: *view, repeat, reference: &reference };
            let last = equal_time(b, &run, gpu, &mut rows, &mut profiles, &mut choices, &mut log)?;
            if repeat + 1 == repeats {
                write_finals(b, (&label, *view), &rows[first..], &last, &reference)?;
            }
        }
    }
    write_results(b, &rows, &noises, &profiles, &blind, &choices)?;
    Ok(rows)
}

/// The scene view's reference image, cached with its settings in the output folder, and its
/// own noise. A CPU Vulkan device (lavapipe) is slower than the host's own threads for it, so
/// then the host renders it.
fn reference_image(
    b: &BenchSettings,
    (label, view): (&str, u32),
    scene: &SceneData,
    scene_hash: String,
    gpu: Option<&Gpu>,
) -> anyhow::Result<(Vec<f32>, Option<f64>)> {
    let path = b.out.join(format!("reference_{label}_v{view}.exr"));
    let rs = ReferenceSettings {
        scene: format!("{label} view {view}"),
        scene_hash,
        width: b.render.width,
        height: b.render.height,
        max_depth: b.render.max_depth,
        spp: b.reference_spp,
        seed: b.render.seed.wrapping_add(1000),
    };
    // On a CPU Vulkan driver the CPU backend renders the reference faster.
    let device = gpu.filter(|g| g.info.device_type != wgpu::DeviceType::Cpu);
    let (sidecar, _) = cached_or_render(&path, scene, &rs, device, 16, |_| {})?;
    let noise = sidecar.noise_rmse;
    let (_, _, reference) = smlt::output::read_exr(&path)?;
    Ok((reference, noise))
}

/// An external reference image (`--reference`), which must have the bench's size, and its own
/// noise where `smlt reference` wrote it: its sidecar (`<path>.json`) then says what it is a
/// reference of, and one of another scene, view or depth is refused (it would measure every
/// method's error against the wrong image).
fn given_reference(
    b: &BenchSettings,
    path: &Path,
    (scene_hash, view): (&str, u32),
) -> anyhow::Result<(Vec<f32>, Option<f64>)> {
    if b.scenes.len() != 1 {
        anyhow::bail!(
            "--reference {} serves one scene view, but {} are benched",
            path.display(),
            b.scenes.len()
        );
    }
    let (w, h, rgb) = smlt::output::read_exr(path)?;
    if (w, h) != (b.render.width, b.render.height) {
        anyhow::bail!(
            "--reference {} is {w}×{h}, the bench renders {}×{}",
            path.display(),
            b.render.width,
            b.render.height
        );
    }
    let Some(written) = read_sidecar(path)? else {
        return Ok((rgb, None));
    };
    let json = sidecar(path);
    let r = &written.settings;
    let of = |what: String| {
        anyhow::anyhow!("--reference {} is a reference of {what} ({})", path.display(), json.display())
    };
    if r.scene_hash != scene_hash {
        return Err(of(format!("another scene (hash {}; the bench's {scene_hash})", r.scene_hash)));
    }
    if !r.scene.ends_with(&format!(" view {view}")) {
        return Err(of(format!("{}, the bench renders view {view}", r.scene)));
    }
    if r.max_depth != b.render.max_depth {
        return Err(of(format!("max depth {}, the bench renders {}", r.max_depth, b.render.max_depth)));
    }
    Ok((rgb, written.noise_rmse))
}

/// One repeat of the equal-time runs on one scene view.
/// What `auto`'s pilot chose in one repeat of one scene view (`auto.csv`).
#[derive(Clone, Debug)]
pub struct AutoChoice {
    #[allow(missing_docs)]
    pub scene: String,
    #[allow(missing_docs)]
    pub view: u32,
    #[allow(missing_docs)]
    pub repeat: u32,
    #[allow(missing_docs)] // the pilot's outcome
    pub choice: render::auto::Choice,
}

impl AutoChoice {
    /// `auto.csv`'s header.
    pub const CSV_HEADER: &'static str =
        "scene,view,repeat,chosen,pilot_seconds,method,pilot_render_seconds,halves_relmse,missing_relmse,firefly_share,predicted_relmse,kept_candidates";

    /// One line per candidate.
    pub fn csv(&self) -> Vec<String> {
        let c = &self.choice;
        c.assessments
            .iter()
            .map(|a| {
                format!(
                    "{},{},{},{},{:.3},{},{:.3},{:.4e},{:.4e},{:.3},{:.4e},{}",
                    self.scene,
                    self.view,
                    self.repeat,
                    c.method,
                    c.seconds,
                    a.method,
                    a.seconds,
                    a.halves_relmse,
                    a.missing_relmse,
                    a.firefly_share,
                    a.predicted_relmse(c.render_seconds, c.pixels),
                    // The chosen candidate's pilot candidates pooled into the render (0: none).
                    c.kept.as_ref().filter(|_| a.method == c.method).map_or(0, |k| k.candidates)
                )
            })
            .collect()
    }
}

struct EqualTime<'a> {
    scene: &'a SceneData,
    label: &'a str,
    view: u32,
    repeat: u32,
    reference: &'a [f32],
}

/// Renders every method on one scene view with the repeat's seed, advancing them in turns to
/// the same render times, appends a row per method and time to `rows`, then (on a device, in
/// the first repeat) profiles each Metropolis method's passes into `profiles`. Returns each method's
/// final image.
fn equal_time(
    b: &BenchSettings,
    run: &EqualTime,
    gpu: Option<&Gpu>,
    rows: &mut Vec<Row>,
    profiles: &mut Vec<Profile>,
    choices: &mut Vec<AutoChoice>,
    log: &mut impl FnMut(&str),
) -> anyhow::Result<Vec<Vec<f32>>> {
    let EqualTime { scene, label, view, repeat, reference } = *run;
    let candidates = b.candidates.unwrap_or(render::default_candidates(gpu));
    // `auto` first runs its pilot, whose wall time starts its clock (`offsets`), and then renders
    // as the method it chose.
    let mut methods = Vec::new();
    let mut offsets = Vec::new();
    // Auto's pilot image where its render keeps it, pooled into every image of it measured.
    let mut kept = Vec::new();
    for m in &b.methods {
        let (method, offset) = match m {
            MethodChoice::Named(m) => {
                kept.push(None);
                (*m, 0.0)
            }
            MethodChoice::Auto => {
                let s = b.settings(Method::NAIVE, repeat, candidates);
                let choice =
                    render::auto::choose(scene, &s, &mut |p| render::new_backend(gpu, scene, p, b.threads))?;
                log(&format!("auto {label} v{view} repeat {repeat}: chose {}", choice.describe()));
                choices.push(AutoChoice { scene: label.to_string(), view, repeat, choice: choice.clone() });
                kept.push(choice.kept);
                (choice.method, choice.seconds)
            }
        };
        methods.push(method);
        offsets.push(offset);
    }
    let settings: Vec<Settings> = methods.iter().map(|&m| b.settings(m, repeat, candidates)).collect();
    // One backend per method, all on the same device, kept for the per-pass profile after the
    // equal-time runs.
    let mut backends: Vec<Box<dyn ProfiledBackend + '_>> = Vec::new();
    for s in &settings {
        let params = render::base_params(scene, s);
        backends.push(match gpu {
            Some(g) => Box::new(render::gpu::GpuBackend::new(g.clone(), scene, &params)?),
            None => Box::new(render::cpu::CpuBackend::new(scene, &params, b.threads)?),
        });
    }
    let mut renderers: Vec<Renderer> = Vec::new();
    for (s, backend) in settings.iter().zip(backends.iter_mut()) {
        let backend: &mut dyn Backend = backend.as_mut();
        renderers.push(Renderer::start(scene, s, backend, &mut |_: f64| {})?);
    }
    let mut last: Vec<Vec<f32>> = vec![Vec::new(); renderers.len()];
    for t in time_grid(b.seconds) {
        for (i, r) in renderers.iter_mut().enumerate() {
            if offsets[i] >= t {
                continue; // auto's pilot outlasts this time
            }
            while offsets[i] + r.stats().render_seconds < t {
                r.iterate()?;
            }
            let image = r.snapshot()?;
            let rgb = KeptPilot::image(kept[i].as_ref(), &image).into_owned();
            let st = &image.stats;
            let row = Row {
                scene: label.to_string(),
                view,
                method: b.methods[i].to_string(),
                repeat,
                seconds: offsets[i] + st.render_seconds,
                candidates: st.candidates,
                steps: st.steps,
                mutations_per_s: st.candidates as f64 / st.render_seconds,
                steps_per_s: st.steps / st.render_seconds,
                errors: errors(&rgb, reference),
                nan_inf: st.invalid,
                b: st.b,
                b_rel_se: st.b_relative_standard_error(),
            };
            log(&row.csv());
            rows.push(row);
            last[i] = rgb;
        }
    }
    // Inside an iteration: per-pass device times and the ray-casting ceiling, after the
    // equal-time runs so that they do not disturb them.
    let next: Vec<RenderParams> = renderers
        .iter()
        .zip(&settings)
        .map(|(r, s)| RenderParams {
            iteration: r.stats().iterations as u32,
            ..render::base_params(scene, s)
        })
        .collect();
    drop(renderers);
    if repeat == 0 {
        for (i, method) in b.methods.iter().enumerate() {
            // The profile looks inside the chains' iterations, and the path tracer's at its ray
            // ceiling; auto's is the profile of the method it chose.
            let MethodChoice::Named(method) = method else { continue };
            let name = method.to_string();
            let measured = final_row(rows, label, view, &name).map_or(0.0, |r| r.mutations_per_s);
            let what = (label, view, name.as_str());
            let p = if *method == Method::PathTracer {
                let params = render::path_params(scene, &settings[i]);
                path_tracer_profile(backends[i].as_ref(), scene, what, &params, measured)?
            } else {
                profile(backends[i].as_mut(), scene, what, next[i], measured)?
            };
            log(&format!("profile {}", p.csv()));
            profiles.push(p);
        }
    }
    Ok(last)
}

/// Each method's final image, and the heat maps of naive and of the best method on one scale.
fn write_finals(
    b: &BenchSettings,
    (label, view): (&str, u32),
    rows: &[Row],
    last: &[Vec<f32>],
    reference: &[f32],
) -> anyhow::Result<()> {
    // `rows` are this repeat's: the last of each method is its final measurement.
    let finals: Vec<&Row> = rows.iter().rev().take(b.methods.len()).collect();
    let best = finals.iter().min_by(|a, b| a.errors.rmse.total_cmp(&b.errors.rmse)).map(|r| r.method.clone());
    let scale = 2.0 * finals.iter().map(|r| r.errors.rmse).fold(0.0, f64::max).max(1e-6);
    for (i, m) in b.methods.iter().enumerate() {
        let stem = format!("{label}_v{view}_{m}");
        smlt::output::write_images(
            &b.out.join(format!("{stem}.exr")),
            b.render.width,
            b.render.height,
            &last[i],
        )?;
        if *m == MethodChoice::Named(Method::NAIVE) || Some(m.to_string()) == best {
            heat_map(&last[i], reference, b.render.width, b.render.height, scale)
                .save(b.out.join(format!("heat_{stem}.png")))?;
        }
    }
    Ok(())
}

/// `results.csv`, `passes.csv`, `tables.md` and the plots.
fn write_results(
    b: &BenchSettings,
    rows: &[Row],
    noises: &[(String, u32, Option<f64>)],
    profiles: &[Profile],
    blind: &[(String, u32, String, String)],
    choices: &[AutoChoice],
) -> anyhow::Result<()> {
    let csv = |header: String, lines: Vec<String>| lines.iter().fold(header + "\n", |s, l| s + l + "\n");
    if !choices.is_empty() {
        let lines = choices.iter().flat_map(AutoChoice::csv).collect();
        std::fs::write(b.out.join("auto.csv"), csv(AutoChoice::CSV_HEADER.to_string(), lines))?;
    }
    std::fs::write(
        b.out.join("results.csv"),
        csv(CSV_HEADER.to_string(), rows.iter().map(Row::csv).collect()),
    )?;
    let methods: Vec<String> = b.methods.iter().map(MethodChoice::to_string).collect();
    let mut tables = tables::tables(&methods, b.seconds, rows, blind);
    if !choices.is_empty() {
        tables.push_str("### What auto chose (its pilot's estimates: auto.csv)\n\n| scene view | repeat | chose |\n|---|---|---|\n");
        for c in choices {
            tables.push_str(&format!(
                "| {} v{} | {} | {} |\n",
                c.scene,
                c.view,
                c.repeat,
                c.choice.describe()
            ));
        }
        tables.push('\n');
    }
    tables.push_str(&tables::reference_table(b, rows, noises));
    if !profiles.is_empty() {
        std::fs::write(
            b.out.join("passes.csv"),
            csv(profile::csv_header(), profiles.iter().map(Profile::csv).collect()),
        )?;
        tables.push_str(&profile::tables(profiles));
    }
    std::fs::write(b.out.join("tables.md"), tables)?;
    plots::plot(rows, &b.out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use render::auto::{Assessment, Choice, KeptPilot};

    /// `auto.csv`: a line per candidate, as many fields as its header, the candidates its
    /// render pooled from the pilot on the chosen one's line only.
    #[test]
    fn auto_csv_lines_match_their_header() {
        let assessment = |method| Assessment {
            method,
            seconds: 0.4,
            halves_relmse: 0.1,
            missing_relmse: 0.0,
            firefly_share: 0.2,
        };
        let choice = Choice {
            method: Method::PathTracer,
            assessments: vec![assessment(Method::PathTracer), assessment(Method::NAIVE)],
            seconds: 0.8,
            width: 8,
            height: 6,
            render_seconds: 7.2,
            pixels: 1.0,
            kept: Some(KeptPilot { rgb: vec![0.0; 144], candidates: 960 }),
        };
        let lines = AutoChoice { scene: "s".into(), view: 1, repeat: 0, choice }.csv();
        let fields = AutoChoice::CSV_HEADER.split(',').count();
        assert_eq!(lines.len(), 2);
        for (line, kept) in lines.iter().zip(["960", "0"]) {
            let f: Vec<&str> = line.split(',').collect();
            assert_eq!((f.len(), f[f.len() - 1]), (fields, kept), "{line}");
        }
    }
}
