//! `smlt reference`: the ground truth of a scene by the independent path tracer
//! (`shared::path_tracer`), rendered long on the device or the CPU, and cached: the EXR is
//! written with a sidecar `<out>.json` holding its settings and the scene's hash, and a later
//! run with the same settings reuses it.

use std::path::{Path, PathBuf};

use shared::mmlt::{RenderParams, Scene};

use crate::gpu::Gpu;
use crate::passes;
use crate::render::{self, RenderError, Settings};
use crate::scene::SceneData;

/// What defines a reference image.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ReferenceSettings {
    /// Scene name (for people).
    pub scene: String,
    /// FNV-1a hash of the scene's bytes.
    pub scene_hash: String,
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Maximum bounces.
    pub max_depth: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Seed.
    pub seed: u32,
}

/// FNV-1a (64 bit) of `bytes`, as hex: a stable content hash for the cache key.
pub fn content_hash(bytes: &[u8]) -> String {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// The sidecar holding a reference's settings.
pub fn sidecar(out: &Path) -> PathBuf {
    let mut name = out.as_os_str().to_owned();
    name.push(".json");
    PathBuf::from(name)
}

/// Whether `out` already holds a reference with exactly these settings.
pub fn cached(out: &Path, settings: &ReferenceSettings) -> bool {
    let Ok(text) = std::fs::read_to_string(sidecar(out)) else {
        return false;
    };
    out.exists() && serde_json::from_str::<ReferenceSettings>(&text).ok().as_ref() == Some(settings)
}

/// Renders the reference: `spp` samples per pixel in passes of `per_pass`, on `gpu` or the CPU.
/// Returns linear rgb.
pub fn render_reference(
    scene: &SceneData,
    s: &ReferenceSettings,
    gpu: Option<&Gpu>,
    per_pass: u32,
    mut progress: impl FnMut(f64),
) -> Result<Vec<f32>, RenderError> {
    let settings = Settings {
        width: s.width,
        height: s.height,
        max_depth: s.max_depth,
        seed: s.seed,
        method: render::Method::Tree(1),
        budget: render::Budget::MutationsPerPixel(1.0),
        candidates: 1,
        bootstrap_samples: 1,
        mutation: Default::default(),
    };
    let base = RenderParams { candidates: per_pass, ..render::base_params(scene, &settings) };
    let pixels = (s.width * s.height) as usize;
    let passes_total = s.spp.div_ceil(per_pass);
    let mut sum = vec![0.0f64; pixels * 3];
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
            let nodes = gpu.storage_from("BVH nodes", &scene.nodes);
            let triangles = gpu.storage_from("triangles", &scene.triangles);
            let materials = gpu.storage_from("materials", &scene.materials);
            let lights = gpu.storage_from("lights", &scene.lights);
            let image = gpu.storage_zeroed::<f32>("reference image", pixels * 3);
            let pass =
                passes::reference::gpu(gpu, [&params, &nodes, &triangles, &materials, &lights, &image])?;
            for i in 0..passes_total {
                let p = RenderParams { iteration: i, candidates: per_pass.min(s.spp - i * per_pass), ..base };
                gpu.queue.write_buffer(&params, 0, bytemuck::bytes_of(&p));
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                pass.encode(gpu, &mut encoder, pixels as u32);
                gpu.queue.submit([encoder.finish()]);
                let part: Vec<f32> = gpu.read(&image, pixels * 3)?;
                for (acc, v) in sum.iter_mut().zip(&part) {
                    *acc += *v as f64;
                }
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                encoder.clear_buffer(&image, 0, None);
                gpu.queue.submit([encoder.finish()]);
                progress((i + 1) as f64 / passes_total as f64);
            }
        }
        None => {
            let shared_scene = Scene {
                nodes: &scene.nodes,
                triangles: &scene.triangles,
                materials: &scene.materials,
                lights: &scene.lights,
            };
            let mut image = vec![0.0f32; pixels * 3];
            for i in 0..passes_total {
                let p = RenderParams { iteration: i, candidates: per_pass.min(s.spp - i * per_pass), ..base };
                image.iter_mut().for_each(|v| *v = 0.0);
                passes::reference::cpu(&p, shared_scene, &mut image);
                for (acc, v) in sum.iter_mut().zip(&image) {
                    *acc += *v as f64;
                }
                progress((i + 1) as f64 / passes_total as f64);
            }
        }
    }
    Ok(sum.iter().map(|v| (v / s.spp as f64) as f32).collect())
}
