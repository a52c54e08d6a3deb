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
use crate::interval::{clear_best, Interval};
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
    /// Independent runs of every method (seeds `seed`, `seed + 1`, …).
    pub repeats: u32,
    /// A reference image to use instead of rendering one (one scene view only).
    pub reference: Option<PathBuf>,
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
    /// Which of the independent repeats (0-based; its seed is the bench's seed + repeat).
    pub repeat: u32,
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
    "scene,view,method,repeat,seconds,candidates,steps,mutations_per_s,steps_per_s,rmse,relmse,psnr,nan_inf,b,b_rel_se";

impl Row {
    /// The row as CSV.
    pub fn csv(&self) -> String {
        format!(
            "{},{},{},{},{:.3},{},{:.0},{:.1},{:.1},{:.6e},{:.6e},{:.3},{},{:.6e},{:.4e}",
            self.scene,
            self.view,
            self.method,
            self.repeat,
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

/// Reads the rows of a `results.csv` by its header's column names (the `repeat`, NaN/Inf and b
/// columns may be absent, as in files written before they existed).
pub fn read_csv(text: &str) -> anyhow::Result<Vec<Row>> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name);
    let required = [
        "scene",
        "view",
        "method",
        "seconds",
        "candidates",
        "steps",
        "mutations_per_s",
        "steps_per_s",
        "rmse",
        "relmse",
        "psnr",
    ];
    if let Some(missing) = required.iter().find(|n| column(n).is_none()) {
        anyhow::bail!("line 1: no column {missing} (not a results.csv of smlt bench)");
    }
    let mut rows = Vec::new();
    for (i, line) in lines.enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        if f.len() != header.len() {
            anyhow::bail!("line {}: {} fields, the header has {}", i + 2, f.len(), header.len());
        }
        let text = |name: &str| column(name).map(|k| f[k]);
        let num = |name: &str| -> anyhow::Result<Option<f64>> {
            match text(name) {
                Some(v) => {
                    v.parse::<f64>().map(Some).map_err(|e| anyhow::anyhow!("line {}, {name}: {e}", i + 2))
                }
                None => Ok(None),
            }
        };
        let need = |name: &str| -> anyhow::Result<f64> { Ok(num(name)?.expect("required column")) };
        rows.push(Row {
            scene: text("scene").unwrap_or_default().to_string(),
            view: need("view")? as u32,
            method: text("method").unwrap_or_default().to_string(),
            repeat: num("repeat")?.unwrap_or(0.0) as u32,
            seconds: need("seconds")?,
            candidates: need("candidates")? as u64,
            steps: need("steps")?,
            mutations_per_s: need("mutations_per_s")?,
            steps_per_s: need("steps_per_s")?,
            errors: Errors { rmse: need("rmse")?, relmse: need("relmse")?, psnr: need("psnr")? },
            nan_inf: num("nan_inf")?.unwrap_or(0.0) as u64,
            b: num("b")?.unwrap_or(f64::NAN),
            b_rel_se: num("b_rel_se")?.unwrap_or(f64::NAN),
        });
    }
    Ok(rows)
}

/// Each repeat's last measurement of `method` on a scene view.
pub fn finals<'a>(rows: &'a [Row], scene: &str, view: u32, method: &str) -> Vec<&'a Row> {
    let mut out: Vec<&Row> = Vec::new();
    for r in rows.iter().filter(|r| r.scene == scene && r.view == view && r.method == method) {
        match out.iter_mut().find(|x| x.repeat == r.repeat) {
            Some(x) => *x = r,
            None => out.push(r),
        }
    }
    out
}

/// The 95 % interval over repeats of a final measurement of `method` (None if it never ran).
pub fn final_interval(
    rows: &[Row],
    scene: &str,
    view: u32,
    method: &str,
    value: impl Fn(&Row) -> f64,
) -> Option<Interval> {
    let values: Vec<f64> = finals(rows, scene, view, method).into_iter().map(value).collect();
    (!values.is_empty()).then(|| Interval::of(&values))
}

/// The measurements of `method` on a scene view along time: for the k-th measurement time,
/// the mean render seconds and the interval of `value` over the repeats.
pub fn along_time(
    rows: &[Row],
    scene: &str,
    view: u32,
    method: &str,
    value: impl Fn(&Row) -> f64,
) -> Vec<(f64, Interval)> {
    let mine: Vec<&Row> =
        rows.iter().filter(|r| r.scene == scene && r.view == view && r.method == method).collect();
    let mut repeats: Vec<u32> = mine.iter().map(|r| r.repeat).collect();
    repeats.sort_unstable();
    repeats.dedup();
    let series: Vec<Vec<&Row>> =
        repeats.iter().map(|k| mine.iter().copied().filter(|r| r.repeat == *k).collect()).collect();
    let points = series.iter().map(Vec::len).min().unwrap_or(0);
    (0..points)
        .map(|i| {
            let at: Vec<&Row> = series.iter().map(|s| s[i]).collect();
            let seconds = at.iter().map(|r| r.seconds).sum::<f64>() / at.len() as f64;
            (seconds, Interval::of(&at.iter().map(|r| value(r)).collect::<Vec<f64>>()))
        })
        .collect()
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
        let (reference, noise) = match &b.reference {
            Some(path) => (given_reference(b, path)?, None),
            None => reference_image(b, (&label, *view), &scene, scene_hash, gpu)?,
        };
        noises.push((label.clone(), *view, noise));
        let repeats = b.repeats.max(1);
        for repeat in 0..repeats {
            let first = rows.len();
            let run = EqualTime { scene: &scene, label: &label, view: *view, repeat, reference: &reference };
            let last = equal_time(b, &run, gpu, &mut rows, &mut profiles, &mut log)?;
            if repeat + 1 == repeats {
                write_finals(b, (&label, *view), &rows[first..], &last, &reference)?;
            }
        }
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

/// An external reference image (`--reference`), which must have the bench's size.
fn given_reference(b: &BenchSettings, path: &Path) -> anyhow::Result<Vec<f32>> {
    if b.scenes.len() != 1 {
        anyhow::bail!(
            "--reference {} serves one scene view, but {} are benched",
            path.display(),
            b.scenes.len()
        );
    }
    let (w, h, rgb) = crate::output::read_exr(path)?;
    if (w, h) != (b.width, b.height) {
        anyhow::bail!(
            "--reference {} is {w}×{h}, the bench renders {}×{}",
            path.display(),
            b.width,
            b.height
        );
    }
    Ok(rgb)
}

/// One repeat of the equal-time runs on one scene view.
struct EqualTime<'a> {
    scene: &'a SceneData,
    label: &'a str,
    view: u32,
    repeat: u32,
    reference: &'a [f32],
}

/// Renders every method on one scene view with the repeat's seed, advancing them in turns to
/// the same render times, appends a row per method and time to `rows`, then (on a device, in
/// the first repeat) profiles each method's passes into `profiles`. Returns each method's
/// final image.
fn equal_time(
    b: &BenchSettings,
    run: &EqualTime,
    gpu: Option<&Gpu>,
    rows: &mut Vec<Row>,
    profiles: &mut Vec<Profile>,
    log: &mut impl FnMut(&str),
) -> anyhow::Result<Vec<Vec<f32>>> {
    let EqualTime { scene, label, view, repeat, reference } = *run;
    let candidates = b.candidates.unwrap_or(render::default_candidates(gpu));
    let settings: Vec<Settings> = b
        .methods
        .iter()
        .map(|m| Settings {
            width: b.width,
            height: b.height,
            max_depth: b.max_depth,
            seed: b.seed.wrapping_add(repeat),
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
                repeat,
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
    for (i, device) in gpu_backends.iter_mut().enumerate().filter(|_| repeat == 0) {
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
    // `rows` are this repeat's: the last of each method is its final measurement.
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
    let methods: Vec<String> = b.methods.iter().map(Method::to_string).collect();
    let mut tables = tables(&methods, b.seconds, rows);
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

/// The seed's Table 3 (million mutations/s) and Table 4 (PSNR after the full time), with RMSE
/// and relMSE, as Markdown: methods down, scene views across, each cell the mean over the
/// repeats of the final measurements with its 95 % interval; a cell is bold where that method
/// is best and its interval overlaps no other method's.
pub fn tables(methods: &[String], seconds: f64, rows: &[Row]) -> String {
    let columns: Vec<(String, u32)> = {
        let mut c: Vec<(String, u32)> = Vec::new();
        for r in rows {
            if !c.contains(&(r.scene.clone(), r.view)) {
                c.push((r.scene.clone(), r.view));
            }
        }
        c
    };
    let repeats = rows.iter().map(|r| r.repeat + 1).max().unwrap_or(1);
    let mut out = format!(
        "Every cell: the mean over {repeats} independent run(s){}; **bold**: best, with an interval that overlaps no other method's.\n\n",
        if repeats > 1 { " ± the half-width of its 95 % confidence interval (Student t)" } else { "" }
    );
    let header = columns.iter().map(|(s, v)| format!(" {s} v{v} |")).collect::<String>();
    let rule = "---|".repeat(columns.len());
    type Value = fn(&Row) -> f64;
    let tables: [(String, Value, usize, bool); 6] = [
        (
            "Million mutations (candidates; a peer's paths) per second".into(),
            |r| r.mutations_per_s / 1e6,
            3,
            true,
        ),
        ("Speedup of mutations/s over naive (ratio of the means)".into(), |r| r.mutations_per_s, 2, true),
        (format!("PSNR (dB, peak 1 on clamped values) after {seconds} s"), |r| r.errors.psnr, 2, true),
        (format!("RMSE after {seconds} s"), |r| r.errors.rmse, 4, false),
        (format!("relMSE after {seconds} s"), |r| r.errors.relmse, 4, false),
        (
            format!("Efficiency 1 / (relMSE × seconds) after {seconds} s"),
            |r| 1.0 / (r.errors.relmse * r.seconds),
            3,
            true,
        ),
    ];
    for (t, (title, value, decimals, higher)) in tables.iter().enumerate() {
        let _ = writeln!(out, "### {title}\n\n| method |{header}\n|---|{rule}");
        let cells: Vec<Vec<Option<Interval>>> = methods
            .iter()
            .map(|m| columns.iter().map(|(s, v)| final_interval(rows, s, *v, m, value)).collect())
            .collect();
        let best: Vec<Option<usize>> = (0..columns.len())
            .map(|c| {
                let column: Vec<Interval> = cells.iter().filter_map(|m| m[c]).collect();
                if t == 1 || column.len() != cells.len() {
                    return None;
                }
                clear_best(&column, *higher)
            })
            .collect();
        for (i, m) in methods.iter().enumerate() {
            let text: String = (0..columns.len())
                .map(|c| match (t, cells[i][c]) {
                    (_, None) => " — |".to_string(),
                    (1, Some(x)) => {
                        let naive = final_interval(rows, &columns[c].0, columns[c].1, "naive", value);
                        naive.map_or(" — |".to_string(), |n| format!(" {:.2}× |", x.mean / n.mean))
                    }
                    (_, Some(x)) if best[c] == Some(i) => format!(" **{}** |", x.show(*decimals)),
                    (_, Some(x)) => format!(" {} |", x.show(*decimals)),
                })
                .collect();
            let _ = writeln!(out, "| {m} |{text}");
        }
        out.push('\n');
    }
    out
}

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
            .filter_map(|m| final_interval(rows, scene, *view, &m.to_string(), |r| r.errors.rmse))
            .map(|i| i.mean)
            .fold(f64::INFINITY, f64::min);
        let _ = match noise {
            Some(n) => writeln!(out, "| {scene} v{view} | {n:.4} | {best:.4} | {:.2} |", n / best),
            None => writeln!(out, "| {scene} v{view} | — | {best:.4} | — |"),
        };
    }
    out.push('\n');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(method: &str, repeat: u32, seconds: f64, rmse: f64) -> Row {
        Row {
            scene: "s".into(),
            view: 1,
            method: method.into(),
            repeat,
            seconds,
            candidates: 1,
            steps: 1.0,
            mutations_per_s: 1.0,
            steps_per_s: 1.0,
            errors: Errors { rmse, relmse: rmse, psnr: 1.0 },
            nan_inf: 0,
            b: 1.0,
            b_rel_se: 0.01,
        }
    }

    /// Repeats are summarised per measurement time and at the end; the CSV round-trips, and a
    /// file from before the `repeat` column reads as one repeat.
    #[test]
    fn repeats_are_summarised_and_read_back() {
        let rows = vec![
            row("naive", 0, 1.0, 0.4),
            row("naive", 0, 2.1, 0.2),
            row("naive", 1, 1.1, 0.6),
            row("naive", 1, 2.0, 0.4),
        ];
        let curve = along_time(&rows, "s", 1, "naive", |r| r.errors.rmse);
        assert_eq!(curve.len(), 2);
        assert!((curve[0].0 - 1.05).abs() < 1e-12 && (curve[0].1.mean - 0.5).abs() < 1e-12);
        let end = final_interval(&rows, "s", 1, "naive", |r| r.errors.rmse).unwrap();
        assert_eq!((end.n, end.mean), (2, 0.30000000000000004));
        let text = rows.iter().fold(format!("{CSV_HEADER}\n"), |s, r| s + &r.csv() + "\n");
        assert_eq!(read_csv(&text).unwrap().len(), 4);
        let old = "scene,view,method,seconds,candidates,steps,mutations_per_s,steps_per_s,rmse,relmse,psnr\n\
                   s,1,naive,1.0,10,10,1.0,1.0,0.5,0.5,6.0\n";
        let old = read_csv(old).unwrap();
        assert_eq!((old[0].repeat, old[0].errors.rmse, old[0].nan_inf), (0, 0.5, 0));
        assert!(read_csv("a,b\n1,2\n").is_err());
    }
}
