//! `smlt reference`: a scene view's ground truth by the independent path tracer, cached with
//! its settings (`smlt::reference`).

use std::path::PathBuf;

use indicatif::ProgressBar;

use super::args::{DeviceArgs, ImageArgs, PathArgs, SceneArgs};
use smlt::reference::{cached_or_render, sidecar, ReferenceSettings};

/// `smlt reference`'s flags.
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    #[allow(missing_docs)] // flattened: documented on SceneArgs
    pub scene: SceneArgs,
    /// Samples per pixel.
    #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(1..=16_777_216))]
    pub spp: u32,
    #[command(flatten)]
    #[allow(missing_docs)] // flattened: documented on ImageArgs
    pub image: ImageArgs,
    #[command(flatten)]
    #[allow(missing_docs)] // flattened: documented on PathArgs
    pub path: PathArgs,
    #[command(flatten)]
    #[allow(missing_docs)] // flattened: documented on DeviceArgs
    pub device: DeviceArgs,
    /// Output EXR; its settings go to `<out>.json`, and a later run with the same settings reuses it.
    #[arg(long, default_value = "reference.exr")]
    pub out: PathBuf,
}

/// Runs `smlt reference`.
pub fn run(a: Args) -> anyhow::Result<()> {
    smlt::output::check_writable(&a.out)?;
    let (scene, scene_hash) = a.scene.load()?;
    let settings = ReferenceSettings {
        scene: format!("{} view {}", scene.name, a.scene.view(&scene)),
        scene_hash,
        width: a.image.width,
        height: a.image.height(&scene),
        max_depth: a.path.max_depth,
        spp: a.spp,
        seed: a.path.seed,
    };
    if smlt::reference::cached(&a.out, &settings).is_some() {
        println!("cached               {} (same settings in {})", a.out.display(), sidecar(&a.out).display());
        return Ok(());
    }
    let device = a.device.open()?;
    println!(
        "reference of {} at {}×{}, {} spp, max depth {} on {}",
        scene.name,
        settings.width,
        settings.height,
        a.spp,
        a.path.max_depth,
        device.describe()
    );
    let bar = ProgressBar::new(1000);
    let start = std::time::Instant::now();
    let per_round = if device.gpu.is_some() { 16 } else { 4 };
    let (written, _) = cached_or_render(&a.out, &scene, &settings, device.gpu.as_ref(), per_round, |f| {
        bar.set_position((f * 1000.0) as u64)
    })?;
    bar.finish_and_clear();
    let seconds = start.elapsed().as_secs_f64();
    let paths = settings.width as f64 * settings.height as f64 * a.spp as f64;
    println!("time                 {seconds:.2} s ({:.3} M paths/s)", paths / seconds / 1e6);
    println!(
        "noise                RMSE {:.3e} (estimated from {} independent rounds)",
        written.noise_rmse.unwrap_or(f64::NAN),
        a.spp.div_ceil(per_round)
    );
    println!(
        "wrote                {}, {} and {}",
        a.out.display(),
        smlt::output::png_path(&a.out).display(),
        sidecar(&a.out).display()
    );
    Ok(())
}
