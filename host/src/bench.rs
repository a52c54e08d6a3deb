//! `smlt bench`: the seed's evaluation on our scenes — equal-time runs of each method per
//! scene/view in one process on one device, interleaved (every method is advanced in turns to
//! the same render times 1, 2, 4, … s), each compared with the scene's reference image.
//!
//! Writes to the output folder: `results.csv` (one row per method and time: scene, view,
//! method, seconds, candidates, steps, mutations/s, steps/s, RMSE, relMSE, PSNR, the
//! candidates rejected as NaN/Inf, b and its relative standard error — error along time, so convergence is a curve; one scene,
//! one method and a long time is the soak run), `tables.md` (the seed's Table 3: million mutations/s, and
//! Table 4: PSNR after the full time), the plots of `plots` (`speedup.png`, the seed's Fig. 7,
//! and `error_<scene>_v<view>.png`, RMSE against time on log–log axes), the final image of each
//! method and error heat maps of naive and the best method (`metrics::heat_map`), and the cached
//! references; with a device also `passes.csv` and its tables (`crate::profile`: each pass's
//! device time per iteration, rays per candidate and the bare ray throughput).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::gpu::Gpu;
use crate::metrics::{errors, heat_map, Errors};
use crate::profile::{profile, Profile};
use crate::reference::{cached, content_hash, render_reference, write_sidecar, ReferenceSettings, Sidecar};
use crate::render::{self, cpu::CpuBackend, gpu::GpuBackend, Backend, Budget, Method, Renderer, Settings};
use crate::scene::SceneData;
use shared::mmlt::RenderParams;

/// What to measure.
#[derive(Clone, Debug)]
pub struct BenchSettings {
    /// (scene name, view): generated scenes by name, or glTF paths.
    pub scenes: Vec<(String, u32)>,
    /// Methods to compare.
    pub methods: Vec<Method>,
    /// Render seconds per method.
    pub seconds: f64,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Maximum bounces.
    pub max_depth: u32,
    /// Seed.
    pub seed: u32,
    /// Samples per pixel of the references.
    pub reference_spp: u32,
    /// Candidates per iteration (None: by device, as `smlt render`).
    pub candidates: Option<u32>,
    /// Tessellation of generated scenes.
    pub tessellation: u32,
    /// Threads of the CPU backend.
    pub threads: usize,
    /// Output folder.
    pub out: PathBuf,
}

/// One measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Scene name.
    pub scene: String,
    /// View.
    pub view: u32,
    /// Method.
    pub method: String,
    /// Render seconds so far.
    pub seconds: f64,
    /// Candidates traced so far.
    pub candidates: u64,
    /// Chain steps so far.
    pub steps: f64,
    /// Candidates per second.
    pub mutations_per_s: f64,
    /// Chain steps per second.
    pub steps_per_s: f64,
    /// Errors against the reference.
    pub errors: Errors,
    /// Candidates rejected so far for a NaN or infinite contribution (never splatted).
    pub nan_inf: u64,
    /// The normalisation b so far (bootstrap and large steps pooled).
    pub b: f64,
    /// b's standard error relative to b.
    pub b_rel_se: f64,
}

/// The CSV header of `results.csv`.
pub const CSV_HEADER: &str =
    "scene,view,method,seconds,candidates,steps,mutations_per_s,steps_per_s,rmse,relmse,psnr,nan_inf,b,b_rel_se";

impl Row {
    /// The row as CSV.
    pub fn csv(&self) -> String {
        format!(
            "{},{},{},{:.3},{},{:.0},{:.1},{:.1},{:.6e},{:.6e},{:.3},{},{:.6e},{:.4e}",
            self.scene,
            self.view,
            self.method,
            self.seconds,
            self.candidates,
            self.steps,
            self.mutations_per_s,
            self.steps_per_s,
            self.errors.rmse,
            self.errors.relmse,
            self.errors.psnr,
            self.nan_inf,
            self.b,
            self.b_rel_se
        )
    }
}

/// Reads the rows of a `results.csv` (the NaN/Inf and b columns may be absent, as in files
/// written before they existed).
pub fn read_csv(text: &str) -> anyhow::Result<Vec<Row>> {
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if f.len() < 11 {
            anyhow::bail!("line {}: {} fields, expected at least 11", i + 1, f.len());
        }
        let num = |k: usize| -> anyhow::Result<f64> {
            f[k].parse::<f64>().map_err(|e| anyhow::anyhow!("line {}, field {}: {e}", i + 1, k + 1))
        };
        rows.push(Row {
            scene: f[0].to_string(),
            view: num(1)? as u32,
            method: f[2].to_string(),
            seconds: num(3)?,
            candidates: num(4)? as u64,
            steps: num(5)?,
            mutations_per_s: num(6)?,
            steps_per_s: num(7)?,
            errors: Errors { rmse: num(8)?, relmse: num(9)?, psnr: num(10)? },
            nan_inf: if f.len() > 11 { num(11)? as u64 } else { 0 },
            b: if f.len() > 12 { num(12)? } else { f64::NAN },
            b_rel_se: if f.len() > 13 { num(13)? } else { f64::NAN },
        });
    }
    Ok(rows)
}

/// Writes the plots of `rows` into `out`: `speedup.png` and one `error_<scene>_v<view>.png` per
/// scene view.
pub fn plot(rows: &[Row], out: &Path) -> anyhow::Result<()> {
    crate::plots::speedup_plot(rows, &out.join("speedup.png"))?;
    let mut done: Vec<(String, u32)> = Vec::new();
    for r in rows {
        if !done.contains(&(r.scene.clone(), r.view)) {
            done.push((r.scene.clone(), r.view));
            crate::plots::error_plot(
                rows,
                &r.scene,
                r.view,
                &out.join(format!("error_{}_v{}.png", r.scene, r.view)),
            )?;
        }
    }
    Ok(())
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

/// A generated scene by name, or a glTF file (with its external buffers) by path: its label,
/// the scene, and the hash of everything it was read from.
fn load_scene(name: &str, tessellation: u32) -> anyhow::Result<(String, SceneData, String)> {
    match crate::scenes::generate(name, tessellation) {
        Some(text) => {
            let scene = SceneData::from_slice(text.as_bytes(), name)?;
            Ok((name.to_string(), scene, content_hash(text.as_bytes())))
        }
        None => {
            let path = Path::new(name);
            let label = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
            Ok((label, SceneData::load(path)?, crate::scene::files_hash(path)?))
        }
    }
}

/// Runs the bench; `log` gets one line per measurement.
pub fn run(b: &BenchSettings, gpu: Option<&Gpu>, mut log: impl FnMut(&str)) -> anyhow::Result<Vec<Row>> {
    std::fs::create_dir_all(&b.out)?;
    let mut rows = Vec::new();
    let mut profiles: Vec<Profile> = Vec::new();
    let mut noises: Vec<(String, u32, Option<f64>)> = Vec::new();
    for (name, view) in &b.scenes {
        let (label, mut scene, scene_hash) = load_scene(name, b.tessellation)?;
        scene.select_view(*view)?;
        let (reference, noise) = reference_image(b, (&label, *view), &scene, scene_hash, gpu)?;
        noises.push((label.clone(), *view, noise));
        let first = rows.len();
        let last =
            equal_time(b, (&label, *view), &scene, &reference, gpu, &mut rows, &mut profiles, &mut log)?;
        write_finals(b, (&label, *view), &rows[first..], &last, &reference)?;
    }
    write_results(b, &rows, &noises, &profiles, &mut log)?;
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
        width: b.width,
        height: b.height,
        max_depth: b.max_depth,
        spp: b.reference_spp,
        seed: b.seed.wrapping_add(1000),
    };
    let noise = match cached(&path, &rs) {
        Some(found) => found.noise_rmse,
        None => {
            let device = gpu.filter(|g| g.info.device_type != wgpu::DeviceType::Cpu);
            let r = render_reference(scene, &rs, device, 16, |_| {})?;
            crate::output::write_images(&path, b.width, b.height, &r.rgb)?;
            write_sidecar(&path, &Sidecar { settings: rs.clone(), noise_rmse: Some(r.noise_rmse) })?;
            Some(r.noise_rmse)
        }
    };
    let (_, _, reference) = crate::output::read_exr(&path)?;
    Ok((reference, noise))
}

/// Renders every method on one scene view, advancing them in turns to the same render times,
/// appends a row per method and time to `rows`, then (on a device) profiles each method's
/// passes into `profiles`. Returns each method's final image.
#[allow(clippy::too_many_arguments)]
fn equal_time(
    b: &BenchSettings,
    (label, view): (&str, u32),
    scene: &SceneData,
    reference: &[f32],
    gpu: Option<&Gpu>,
    rows: &mut Vec<Row>,
    profiles: &mut Vec<Profile>,
    log: &mut impl FnMut(&str),
) -> anyhow::Result<Vec<Vec<f32>>> {
    let candidates = b.candidates.unwrap_or(render::default_candidates(gpu));
    let settings: Vec<Settings> = b
        .methods
        .iter()
        .map(|m| Settings {
            width: b.width,
            height: b.height,
            max_depth: b.max_depth,
            seed: b.seed,
            method: *m,
            budget: Budget::Seconds(b.seconds),
            candidates,
            bootstrap_samples: 65536,
            mutation: Default::default(),
            shard: render::Shard::WHOLE,
        })
        .collect();
    // One backend per method, all on the same device: the device's kept as such, for the
    // per-pass profile after the equal-time runs.
    let mut gpu_backends: Vec<GpuBackend> = Vec::new();
    let mut cpu_backends: Vec<CpuBackend> = Vec::new();
    for s in &settings {
        let params = render::base_params(scene, s);
        match gpu {
            Some(g) => gpu_backends.push(GpuBackend::new(g.clone(), scene, &params)?),
            None => cpu_backends.push(CpuBackend::new(scene, &params, b.threads)?),
        }
    }
    let mut renderers: Vec<Renderer> = Vec::new();
    let backends = gpu_backends
        .iter_mut()
        .map(|g| g as &mut dyn Backend)
        .chain(cpu_backends.iter_mut().map(|c| c as &mut dyn Backend));
    for (s, backend) in settings.iter().zip(backends) {
        renderers.push(Renderer::start(scene, s, backend)?);
    }
    let mut last: Vec<Vec<f32>> = vec![Vec::new(); renderers.len()];
    for t in time_grid(b.seconds) {
        for (i, r) in renderers.iter_mut().enumerate() {
            while r.stats().render_seconds < t {
                r.iterate()?;
            }
            let image = r.snapshot()?;
            let st = &image.stats;
            let row = Row {
                scene: label.to_string(),
                view,
                method: b.methods[i].to_string(),
                seconds: st.render_seconds,
                candidates: st.candidates,
                steps: st.steps,
                mutations_per_s: st.candidates as f64 / st.render_seconds,
                steps_per_s: st.steps / st.render_seconds,
                errors: errors(&image.rgb, reference),
                nan_inf: st.invalid,
                b: st.b,
                b_rel_se: st.b_relative_standard_error(),
            };
            log(&row.csv());
            rows.push(row);
            last[i] = image.rgb;
        }
    }
    // Inside an iteration: per-pass device times and the ray-casting ceiling, after the
    // equal-time runs so that they do not disturb them.
    let next: Vec<RenderParams> = renderers.iter().map(Renderer::next_params).collect();
    drop(renderers);
    for (i, device) in gpu_backends.iter_mut().enumerate() {
        let method = b.methods[i].to_string();
        let measured = final_row(rows, label, view, &method).map_or(0.0, |r| r.mutations_per_s);
        let p = profile(device, scene, (label, view, &method), next[i], measured)?;
        log(&format!("profile {}", p.csv()));
        profiles.push(p);
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
    let finals: Vec<&Row> = rows.iter().rev().take(b.methods.len()).collect();
    let best = finals.iter().min_by(|a, b| a.errors.rmse.total_cmp(&b.errors.rmse)).map(|r| r.method.clone());
    let scale = 2.0 * finals.iter().map(|r| r.errors.rmse).fold(0.0, f64::max).max(1e-6);
    for (i, m) in b.methods.iter().enumerate() {
        let stem = format!("{label}_v{view}_{m}");
        crate::output::write_images(&b.out.join(format!("{stem}.exr")), b.width, b.height, &last[i])?;
        if *m == Method::Tree(1) || Some(m.to_string()) == best {
            heat_map(&last[i], reference, b.width, b.height, scale)
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
    log: &mut impl FnMut(&str),
) -> anyhow::Result<()> {
    let csv = |header: String, lines: Vec<String>| lines.iter().fold(header + "\n", |s, l| s + l + "\n");
    std::fs::write(
        b.out.join("results.csv"),
        csv(CSV_HEADER.to_string(), rows.iter().map(Row::csv).collect()),
    )?;
    let mut tables = tables(b, rows);
    tables.push_str(&reference_table(b, rows, noises));
    if profiles.is_empty() {
        log("no per-pass timings or ray ceiling: they need a Vulkan device (--device gpu)");
    } else {
        std::fs::write(
            b.out.join("passes.csv"),
            csv(crate::profile::csv_header(), profiles.iter().map(Profile::csv).collect()),
        )?;
        tables.push_str(&crate::profile::tables(profiles));
    }
    std::fs::write(b.out.join("tables.md"), tables)?;
    plot(rows, &b.out)
}

/// The last measurement of `method` on a scene view.
fn final_row<'a>(rows: &'a [Row], scene: &str, view: u32, method: &str) -> Option<&'a Row> {
    rows.iter().rfind(|r| r.scene == scene && r.view == view && r.method == method)
}

/// The seed's Table 3 (million mutations/s) and Table 4 (PSNR after the full time), with
/// RMSE, as Markdown: methods down, scene views across, values at the last measurement.
pub fn tables(b: &BenchSettings, rows: &[Row]) -> String {
    let final_row = |scene: &str, view: u32, method: &str| final_row(rows, scene, view, method);
    let columns: Vec<(String, u32)> = {
        let mut c: Vec<(String, u32)> = Vec::new();
        for r in rows {
            if !c.contains(&(r.scene.clone(), r.view)) {
                c.push((r.scene.clone(), r.view));
            }
        }
        c
    };
    let mut out = String::new();
    let header = columns.iter().map(|(s, v)| format!(" {s} v{v} |")).collect::<String>();
    let rule = "---|".repeat(columns.len());
    for (title, value) in [
        ("Million mutations (candidates) per second", 0),
        ("Speedup of mutations/s over naive", 1),
        (&*format!("PSNR (dB, peak 1 on clamped values) after {} s", b.seconds), 2),
        (&*format!("RMSE after {} s", b.seconds), 3),
    ] {
        let _ = writeln!(out, "### {title}\n\n| method |{header}\n|---|{rule}");
        for m in &b.methods {
            let m = m.to_string();
            let cells: String = columns
                .iter()
                .map(|(s, v)| match final_row(s, *v, &m) {
                    Some(r) => match value {
                        0 => format!(" {:.3} |", r.mutations_per_s / 1e6),
                        1 => match final_row(s, *v, "naive") {
                            Some(n) => format!(" {:.2}× |", r.mutations_per_s / n.mutations_per_s),
                            None => " — |".into(),
                        },
                        2 => format!(" {:.2} |", r.errors.psnr),
                        _ => format!(" {:.4} |", r.errors.rmse),
                    },
                    None => " — |".into(),
                })
                .collect();
            let _ = writeln!(out, "| {m} |{cells}");
        }
        out.push('\n');
    }
    out
}

/// The references' own noise beside the errors measured against them: each scene view's
/// estimated reference RMSE and the smallest final RMSE of any method.
pub fn reference_table(b: &BenchSettings, rows: &[Row], noises: &[(String, u32, Option<f64>)]) -> String {
    let mut out = format!(
        "### References ({} spp; noise = estimated RMSE of the reference itself)\n\n\
         | scene view | reference noise | smallest method RMSE after {} s | ratio |\n|---|---|---|---|\n",
        b.reference_spp, b.seconds
    );
    for (scene, view, noise) in noises {
        let best = b
            .methods
            .iter()
            .filter_map(|m| final_row(rows, scene, *view, &m.to_string()))
            .map(|r| r.errors.rmse)
            .fold(f64::INFINITY, f64::min);
        let _ = match noise {
            Some(n) => writeln!(out, "| {scene} v{view} | {n:.4} | {best:.4} | {:.2} |", n / best),
            None => writeln!(out, "| {scene} v{view} | — | {best:.4} | — |"),
        };
    }
    out.push('\n');
    out
}
