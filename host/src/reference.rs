//! `smlt reference`: the ground truth of a scene by the independent path tracer
//! (`shared::path_tracer`), rendered long on the device or the CPU, and cached: the EXR is
//! written with a sidecar `<out>.json` holding its settings and the scene's hash, and a later
//! run with the same settings reuses it. The sidecar also holds the reference's own noise,
//! estimated from the spread of its independent rounds, so that the bench can show that the
//! errors it compares are well above it.

use std::path::{Path, PathBuf};

use shared::path_tracer::PathTracerParams;

use crate::gpu::Gpu;
use crate::render::cpu::{default_threads, CpuBackend};
use crate::render::gpu::GpuBackend;
use crate::render::{
    base_params, path_tracer_params, Accumulation, Backend, Budget, Integrator, RenderError, Settings, Shard,
};
use crate::scene::SceneData;

/// What defines a reference image.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ReferenceSettings {
    /// Scene name (for people).
    pub scene: String,
    /// FNV-1a hash of the scene's bytes.
    pub scene_hash: String,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Maximum number of bounces (pbrt's maxdepth).
    pub max_depth: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// The `seed` word of the reference kernel's random keys.
    pub seed: u32,
}

/// The sidecar holding a reference's settings.
pub fn sidecar(out: &Path) -> PathBuf {
    let mut name = out.as_os_str().to_owned();
    name.push(".json");
    PathBuf::from(name)
}

/// What the sidecar holds: the settings, and the reference's estimated noise.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sidecar {
    /// The settings that define the image.
    #[serde(flatten)]
    pub settings: ReferenceSettings,
    /// The reference's own RMSE against the exact image, estimated (absent in older sidecars).
    #[serde(default)]
    pub noise_rmse: Option<f64>,
}

/// The sidecar of the reference at `out`: None where it has none, an error naming it where it
/// is not one that `smlt reference` wrote.
pub fn read_sidecar(out: &Path) -> anyhow::Result<Option<Sidecar>> {
    let json = sidecar(out);
    if !json.exists() {
        return Ok(None);
    }
    let text = std::fs::read_to_string(&json).map_err(|e| anyhow::anyhow!("{}: {e}", json.display()))?;
    let found = serde_json::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", json.display()))?;
    Ok(Some(found))
}

/// The sidecar of `out` when `out` already holds a reference with exactly these settings.
pub fn cached(out: &Path, settings: &ReferenceSettings) -> Option<Sidecar> {
    let found = read_sidecar(out).ok()??;
    (out.exists() && found.settings == *settings).then_some(found)
}

/// The reference at `out` for `settings`: the cached one when its sidecar holds the same
/// settings, else rendered now (`per_round` samples a round, `progress` told the fraction done)
/// and written with its sidecar. Returns the sidecar and whether it was rendered now.
pub fn cached_or_render(
    out: &Path,
    scene: &SceneData,
    settings: &ReferenceSettings,
    gpu: Option<&Gpu>,
    per_round: u32,
    progress: impl FnMut(f64),
) -> anyhow::Result<(Sidecar, bool)> {
    if let Some(found) = cached(out, settings) {
        return Ok((found, false));
    }
    let reference = render_reference(scene, settings, gpu, per_round, progress)?;
    crate::output::write_images(out, settings.width, settings.height, &reference.rgb)?;
    let written = Sidecar { settings: settings.clone(), noise_rmse: Some(reference.noise_rmse) };
    write_sidecar(out, &written)?;
    Ok((written, true))
}

/// Writes the sidecar of `out` (through a temporary file, so that a half-written one is never
/// taken for a cache entry).
pub fn write_sidecar(out: &Path, sidecar_data: &Sidecar) -> anyhow::Result<()> {
    let json = sidecar(out);
    let tmp = json.with_extension("json.tmp");
    std::fs::write(&tmp, serde_json::to_string_pretty(sidecar_data)?)?;
    std::fs::rename(&tmp, &json)?;
    Ok(())
}

/// A rendered reference.
#[derive(Clone, Debug)]
pub struct Reference {
    /// Linear rgb.
    pub rgb: Vec<f32>,
    /// Its estimated RMSE against the exact image: the standard error of each pixel's mean from
    /// the spread of the independent rounds' means, √(Σ(yᵢ − ȳ)² / (P(P − 1))), in root mean
    /// square over pixels and channels (NaN with a single round).
    pub noise_rmse: f64,
}

/// Renders the reference: `spp` samples per pixel in rounds of `per_round`, on `gpu` or the CPU
/// — the `reference` pass of a render backend, drained after every round.
pub fn render_reference(
    scene: &SceneData,
    s: &ReferenceSettings,
    gpu: Option<&Gpu>,
    per_round: u32,
    mut progress: impl FnMut(f64),
) -> Result<Reference, RenderError> {
    let pixels = (s.width * s.height) as usize;
    // The path tracer's render settings: a backend holds the scene, the image and the pass.
    let settings = Settings {
        width: s.width,
        height: s.height,
        max_depth: s.max_depth,
        seed: s.seed,
        integrator: Integrator::PathTracer,
        budget: Budget::MutationsPerPixel(s.spp as f64),
        candidates: per_round.saturating_mul(pixels as u32),
        shard: Shard::WHOLE,
    };
    let params = base_params(scene, &settings);
    let mut backend: Box<dyn Backend + '_> = match gpu {
        Some(gpu) => Box::new(GpuBackend::new(gpu.clone(), scene, &params)?),
        None => Box::new(CpuBackend::new(scene, &params, default_threads())?),
    };
    let base = path_tracer_params(scene, (s.width, s.height), s.max_depth, s.seed, per_round);
    if backend.compiles_kernels() {
        backend.warm_up_path_tracer(&base)?;
    }
    let rounds = s.spp.div_ceil(per_round);
    let mut sum = vec![0.0f64; pixels * 3];
    // Σ of each round's per-pixel mean, and of its square, for the noise estimate.
    let mut round_means = vec![0.0f64; pixels * 3];
    let mut round_squares = vec![0.0f64; pixels * 3];
    let mut part = Accumulation::new(pixels);
    for i in 0..rounds {
        let p = PathTracerParams { round: i, samples: per_round.min(s.spp - i * per_round), ..base };
        backend.trace_path_tracer_round(&p)?;
        backend.drain(&mut part)?;
        for (j, v) in part.image.iter_mut().enumerate() {
            sum[j] += *v;
            let y = *v / p.samples as f64;
            round_means[j] += y;
            round_squares[j] += y * y;
            *v = 0.0;
        }
        progress((i + 1) as f64 / rounds as f64);
    }
    let count = rounds as f64;
    let variance: f64 = round_means
        .iter()
        .zip(&round_squares)
        .map(|(m, q)| ((q - m * m / count) / (count * (count - 1.0))).max(0.0))
        .sum::<f64>()
        / (pixels * 3).max(1) as f64;
    Ok(Reference {
        rgb: sum.iter().map(|v| (v / s.spp as f64) as f32).collect(),
        noise_rmse: variance.sqrt(),
    })
}
