//! `smlt reference`: the ground truth of a scene by the independent path tracer
//! (`shared::path_tracer`), rendered long on the device or the CPU, and cached: the EXR is
//! written with a sidecar `<out>.json` holding its settings and the scene's hash, and a later
//! run with the same settings reuses it. The sidecar also holds the reference's own noise,
//! estimated from the spread of its independent rounds, so that the bench can show that the
//! errors it compares are well above it.

use std::path::{Path, PathBuf};

use shared::path_tracer::ReferenceParams;

use crate::gpu::Gpu;
use crate::passes;
use crate::passes::buffers::{OnDevice, SceneBuffers};
use crate::render::{reference_params, RenderError};
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

/// The sidecar of `out` when `out` already holds a reference with exactly these settings.
pub fn cached(out: &Path, settings: &ReferenceSettings) -> Option<Sidecar> {
    let text = std::fs::read_to_string(sidecar(out)).ok()?;
    let found: Sidecar = serde_json::from_str(&text).ok()?;
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

/// Renders the reference: `spp` samples per pixel in rounds of `per_round`, on `gpu` or the CPU.
pub fn render_reference(
    scene: &SceneData,
    s: &ReferenceSettings,
    gpu: Option<&Gpu>,
    per_round: u32,
    mut progress: impl FnMut(f64),
) -> Result<Reference, RenderError> {
    let base = reference_params(scene, (s.width, s.height), s.max_depth, s.seed, per_round);
    let pixels = (s.width * s.height) as usize;
    let rounds = s.spp.div_ceil(per_round);
    let mut sum = vec![0.0f64; pixels * 3];
    // Σ of each round's per-pixel mean, and of its square, for the noise estimate.
    let mut round_means = vec![0.0f64; pixels * 3];
    let mut round_squares = vec![0.0f64; pixels * 3];
    let mut add_round = |part: &[f32], samples: u32| {
        for i in 0..part.len() {
            let v = part[i] as f64;
            sum[i] += v;
            let y = v / samples as f64;
            round_means[i] += y;
            round_squares[i] += y * y;
        }
    };
    match gpu {
        Some(gpu) => {
            let limit = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
            if (pixels * 12) as u64 > limit {
                return Err(RenderError::TooLarge(format!(
                    "the reference image needs {:.1} MiB but the device allows {:.1} MiB per storage buffer \
                     (max_storage_buffer_binding_size); lower the resolution",
                    (pixels * 12) as f64 / 1048576.0,
                    limit as f64 / 1048576.0
                )));
            }
            let params = gpu.storage_from("reference params", &[base]);
            let b = SceneBuffers::new(&mut OnDevice(gpu.clone()), scene);
            let image = gpu.storage_zeroed::<f32>("reference image", pixels * 3);
            let pass = passes::reference::gpu(
                gpu,
                [&params, &b.nodes, &b.triangles, &b.materials, &b.lights, &image],
            )?;
            for i in 0..rounds {
                let p = ReferenceParams { round: i, samples: per_round.min(s.spp - i * per_round), ..base };
                gpu.queue.write_buffer(&params, 0, bytemuck::bytes_of(&p));
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                pass.encode(gpu, &mut encoder, pixels as u32);
                gpu.queue.submit([encoder.finish()]);
                let part: Vec<f32> = gpu.read(&image, pixels * 3)?;
                add_round(&part, p.samples);
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                encoder.clear_buffer(&image, 0, None);
                gpu.queue.submit([encoder.finish()]);
                progress((i + 1) as f64 / rounds as f64);
            }
        }
        None => {
            let shared_scene = scene.shared();
            let mut image = vec![0.0f32; pixels * 3];
            for i in 0..rounds {
                let p = ReferenceParams { round: i, samples: per_round.min(s.spp - i * per_round), ..base };
                image.iter_mut().for_each(|v| *v = 0.0);
                passes::reference::cpu(&p, shared_scene, &mut image);
                add_round(&image, p.samples);
                progress((i + 1) as f64 / rounds as f64);
            }
        }
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
