//! What several subcommands share: where the kernels run ([`DeviceArgs`], and the policy that
//! turns them into a [`Device`]), which scene and view ([`SceneArgs`]), the path settings
//! ([`PathArgs`]), the chains' settings ([`ChainArgs`]), and the parsers of bounded numbers whose errors name the flag's value.

use std::path::PathBuf;

use clap::ValueEnum;
use shared::mutation::MutationParams;

use smlt::gpu::Gpu;
use smlt::render;
use smlt::scene::{EnvironmentSpec, SceneData};

/// Where the kernels run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DeviceKind {
    /// A real GPU (discrete or integrated Vulkan adapter) if there is one, else the CPU
    /// backend on every core.
    Auto,
    /// The best Vulkan adapter (a GPU, or lavapipe, Mesa's CPU driver).
    #[value(alias = "gpu")]
    Vulkan,
    /// The same kernels on the host CPU's threads.
    Cpu,
}

/// Where the kernels run (render, reference, bench and selftest).
#[derive(clap::Args, Clone)]
pub struct DeviceArgs {
    /// Where the kernels run: auto (a real GPU if there is one, otherwise the CPU backend on
    /// every core), vulkan (the best Vulkan adapter, lavapipe included; `gpu` is an alias) or
    /// cpu.
    #[arg(long, value_enum, default_value_t = DeviceKind::Auto)]
    pub device: DeviceKind,
    /// The Vulkan adapter, by index or part of its name (`smlt devices` lists them); implies a
    /// Vulkan device.
    #[arg(long)]
    pub adapter: Option<String>,
    /// Threads of the CPU backend (default: every core).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
    pub threads: Option<u16>,
}

/// The device chosen for a command, and why.
pub struct Device {
    /// The Vulkan device, or None for the CPU backend.
    pub gpu: Option<Gpu>,
    /// Threads of the CPU backend (and of the host-side bootstrap).
    pub threads: usize,
    /// Why this device.
    pub why: String,
}

impl Device {
    /// The device in words.
    pub fn describe(&self) -> String {
        match &self.gpu {
            Some(g) => g.describe(),
            None => format!("CPU ({} thread{})", self.threads, if self.threads == 1 { "" } else { "s" }),
        }
    }
}

impl DeviceArgs {
    /// Opens the device these flags ask for (`--device auto` prefers a real GPU, then every
    /// CPU core).
    pub fn open(&self) -> anyhow::Result<Device> {
        let threads = self.threads.map_or_else(render::cpu::default_threads, |t| t as usize);
        if self.adapter.is_some() && self.device == DeviceKind::Cpu {
            anyhow::bail!(
                "--adapter names a Vulkan adapter, but --device cpu runs on the CPU: drop one of them"
            );
        }
        let kind = if self.adapter.is_some() { DeviceKind::Vulkan } else { self.device };
        match kind {
            DeviceKind::Vulkan => {
                let gpu = Gpu::open(self.adapter.as_deref())?;
                let why = match &self.adapter {
                    Some(a) => format!("--adapter {a}"),
                    None => "--device vulkan: the best Vulkan adapter".into(),
                };
                Ok(Device { gpu: Some(gpu), threads, why })
            }
            DeviceKind::Cpu => Ok(Device { gpu: None, threads, why: "--device cpu".into() }),
            DeviceKind::Auto => {
                let adapters = smlt::gpu::adapters();
                if adapters.iter().any(|a| smlt::gpu::is_real_gpu(&a.get_info())) {
                    let gpu = Gpu::open(None)?;
                    return Ok(Device {
                        gpu: Some(gpu),
                        threads,
                        why: "--device auto: a GPU is present".into(),
                    });
                }
                let seen: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
                let why = if seen.is_empty() {
                    "--device auto: no Vulkan adapter, so the CPU backend on every core".to_string()
                } else {
                    format!(
                        "--device auto: no GPU among the Vulkan adapters ({}, a CPU driver), so the CPU \
                         backend on every core, which is faster",
                        seen.join(", ")
                    )
                };
                Ok(Device { gpu: None, threads, why })
            }
        }
    }
}

/// The scene and its camera (render and reference).
#[derive(clap::Args, Clone)]
pub struct SceneArgs {
    /// glTF scene (.gltf or .glb) or a generated scene's name (cornell, atrium, nave, sunblind,
    /// slit, lamps, caustic, materials, textured, smooth, cutout); the embedded Cornell box when
    /// absent.
    pub scene: Option<PathBuf>,
    /// Which of the scene's cameras to use (1 = the first; default: its first perspective
    /// camera, or a framing of the whole scene when it has none).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub view: Option<u32>,
    #[command(flatten)]
    #[allow(missing_docs)] // flattened: documented on EnvironmentArgs
    pub environment: EnvironmentArgs,
}

/// The environment light a scene is lit by besides its own lights (render, reference, bench).
#[derive(clap::Args, Clone)]
pub struct EnvironmentArgs {
    /// Light the scene by an environment too: a latitude-longitude .exr or .hdr image of
    /// linear radiance (+Y up, Mitsuba's orientation), or a constant colour (0.5,0.6,0.8).
    #[arg(long, value_name = "FILE|R,G,B", allow_negative_numbers = true)]
    pub environment: Option<String>,
    /// The factor the environment's radiance is scaled by.
    #[arg(long, default_value_t = 1.0, requires = "environment")]
    pub environment_strength: f32,
    /// The environment's rotation about +Y, in degrees.
    #[arg(long, default_value_t = 0.0, requires = "environment", allow_negative_numbers = true)]
    pub environment_rotation: f32,
}

impl EnvironmentArgs {
    /// The environment light asked for, if any.
    pub fn spec(&self) -> Option<EnvironmentSpec> {
        self.environment.as_ref().map(|source| EnvironmentSpec {
            source: source.clone(),
            strength: self.environment_strength,
            rotation_degrees: self.environment_rotation,
        })
    }
}

impl SceneArgs {
    /// The view rendered: `--view`'s, or the scene's default ([`SceneData::default_view`]).
    pub fn view(&self, scene: &SceneData) -> u32 {
        self.view.unwrap_or_else(|| scene.default_view())
    }

    /// The scene at its view, lit by the environment asked for, and the hash of its files
    /// (and of the environment); prints the loader's warnings.
    pub fn load(&self) -> anyhow::Result<(SceneData, String)> {
        let name = self.scene.as_ref().map(|p| p.to_string_lossy().into_owned());
        let environment = self.environment.spec();
        let (_, mut scene, hash) =
            smlt::scenes::open_with_environment(name.as_deref(), 1, environment.as_ref())?;
        if let Some(view) = self.view {
            scene.select_view(view)?;
        }
        for w in &scene.warnings {
            eprintln!("warning: {}: {w}", scene.name);
        }
        Ok((scene, hash))
    }
}

/// The image's size (render and reference; the bench has its own, smaller default).
#[derive(clap::Args, Clone)]
pub struct ImageArgs {
    /// Image width in pixels.
    #[arg(long, default_value_t = render::DEFAULT_WIDTH, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: u32,
    /// Image height in pixels (default: the width divided by the glTF camera's aspect ratio, or
    /// the width when the camera has none).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: Option<u32>,
}

impl ImageArgs {
    /// The height: as given, else the width over the camera's aspect ratio, else the width.
    pub fn height(&self, scene: &SceneData) -> u32 {
        self.height.unwrap_or_else(|| match scene.camera.aspect {
            Some(aspect) => ((self.width as f32 / aspect).round() as u32).clamp(1, 16384),
            None => self.width,
        })
    }
}

/// What every estimator of a scene's image shares (render, reference and bench).
#[derive(clap::Args, Clone)]
pub struct PathArgs {
    /// Maximum bounces, as pbrt's maxdepth (1 = direct light only).
    #[arg(long, default_value_t = render::DEFAULT_MAX_DEPTH, value_parser = clap::value_parser!(u32).range(0..=64))]
    pub max_depth: u32,
    /// Seed of every random number.
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
}

/// What the Metropolis chains share (render and bench; the path tracer ignores them).
#[derive(clap::Args, Clone)]
pub struct ChainArgs {
    /// Bootstrap samples for the normalisation and the chains' start states.
    #[arg(long, default_value_t = render::DEFAULT_BOOTSTRAP, value_parser = clap::value_parser!(u32).range(1..=67_108_864))]
    pub bootstrap: u32,
    /// Probability of a large step.
    #[arg(long, default_value_t = MutationParams::default().p_large, value_parser = unit_f32)]
    pub p_large: f32,
    /// Largest small step of the image-plane position, as a fraction of the image (every other
    /// dimension's is 1/64, Kelemen's s2; 0.015625 is the paper's schedule).
    #[arg(long, default_value_t = render::DEFAULT_IMAGE_STEP, value_parser = step_f32)]
    pub image_step: f32,
    /// Chains follow the luminance of each contribution (the paper's target) instead of
    /// dividing it by the pixel importance, a 4-spp estimate of each pixel's luminance that
    /// gives every pixel about the same share of the steps. The same image either way, less
    /// even noise.
    #[arg(long)]
    pub no_pixel_importance: bool,
}

impl ChainArgs {
    /// The chains' settings these flags give.
    pub fn settings(&self) -> render::ChainSettings {
        render::ChainSettings {
            bootstrap_samples: self.bootstrap,
            mutation: MutationParams {
                p_large: self.p_large,
                image_s2: self.image_step,
                ..Default::default()
            },
            pixel_importance: !self.no_pixel_importance,
        }
    }
}

/// An exposure in stops.
pub fn exposure(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v.abs() <= 64.0 => Ok(v),
        _ => Err(format!("'{s}' is not an exposure in stops (a number from -64 to 64)")),
    }
}

/// A finite number above 0.
pub fn positive_f64(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("'{s}' is not a positive number")),
    }
}

/// A number in (0, 1].
pub fn step_f32(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v > 0.0 && v <= 1.0 => Ok(v),
        _ => Err(format!("'{s}' is not a number in (0, 1]")),
    }
}

/// A number in [0, 1].
pub fn unit_f32(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        _ => Err(format!("'{s}' is not a number in [0, 1]")),
    }
}
