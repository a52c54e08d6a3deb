//! `smlt bench`: the paper's evaluation — equal-time runs of the methods on scene views against
//! their references (`smlt_bench`).

use std::path::PathBuf;

use super::args::{positive_f64, ChainArgs, DeviceArgs, EnvironmentArgs, PathArgs};
use smlt::render::{Integrator, Method, MethodChoice, Settings};

/// A scene with an optional view: `atrium:2`.
fn scene_view(s: &str) -> Result<(String, u32), String> {
    match s.split_once(':') {
        Some((name, view)) => match view.parse::<u32>() {
            Ok(v) if v >= 1 => Ok((name.to_string(), v)),
            _ => Err(format!("'{s}': the view after ':' must be a number ≥ 1")),
        },
        None => Ok((s.to_string(), 1)),
    }
}

/// `smlt bench`'s flags.
#[derive(clap::Args)]
pub struct Args {
    /// Scenes, comma-separated, each a generated scene (cornell, atrium, nave, sunblind, slit, lamps, caustic, materials) or a
    /// glTF path, with an optional view: atrium:2.
    #[arg(long, value_delimiter = ',', default_value = "cornell,atrium:1,atrium:2,nave,sunblind", value_parser = scene_view)]
    pub scenes: Vec<(String, u32)>,
    /// Methods, comma-separated (pt: the path tracer; path-<method>: the chains over the path
    /// tracer's estimate; auto: the method its pilot chooses, the pilot's time counted).
    #[arg(long, value_delimiter = ',', default_value = "auto,pt,naive,path-naive,s2,s3,s4,s5,s6,rc2,rc4,rc8,rc16,rc32,rc64", value_parser = |s: &str| s.parse::<MethodChoice>())]
    pub methods: Vec<MethodChoice>,
    /// Render seconds per method (errors are also measured at 1, 2, 4, … s).
    #[arg(long, default_value_t = 8.0, value_parser = positive_f64)]
    pub seconds: f64,
    /// Image width (smaller than a render's by default: the bench renders every method and a
    /// reference).
    #[arg(long, default_value_t = 128, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: u32,
    /// Image height.
    #[arg(long, default_value_t = 128, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: u32,
    #[command(flatten)]
    #[allow(missing_docs)] // flattened: documented on PathArgs
    pub path: PathArgs,
    /// Samples per pixel of the (cached) references.
    #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(1..))]
    pub reference_spp: u32,
    /// Candidates per iteration (default by device, as for render).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16_777_216))]
    pub candidates: Option<u32>,
    /// Tessellation of the generated scenes.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=256))]
    pub tessellation: u32,
    #[command(flatten)]
    #[allow(missing_docs)] // flattened: documented on EnvironmentArgs (every scene is lit by it)
    pub environment: EnvironmentArgs,
    #[command(flatten)]
    #[allow(missing_docs)] // flattened: documented on DeviceArgs
    pub device: DeviceArgs,
    /// Independent runs of every method (seeds seed, seed + 1, …): tables and plots show the
    /// mean and its 95 % confidence interval.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub repeats: u32,
    /// Use this EXR as the reference instead of rendering one (one scene view only; it must
    /// have the bench's resolution). Where `smlt reference` wrote it, its sidecar
    /// (`FILE.exr.json`) gives the tables its noise, and one of another scene, view or max depth
    /// is refused.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Output folder.
    #[arg(long, default_value = "bench")]
    pub out: PathBuf,
    #[command(flatten)]
    #[allow(missing_docs)] // flattened: documented on ChainArgs (every Metropolis method's)
    pub chains: ChainArgs,
}

/// Runs `smlt bench`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let device = a.device.open()?;
    println!("bench on {} — {}", device.describe(), device.why);
    println!("{}", smlt_bench::results::CSV_HEADER);
    let render = Settings {
        width: a.width,
        height: a.height,
        max_depth: a.path.max_depth,
        seed: a.path.seed,
        integrator: Integrator::new(Method::NAIVE, a.chains.settings()),
        ..Default::default()
    };
    let settings = smlt_bench::BenchSettings {
        scenes: a.scenes,
        methods: a.methods,
        render,
        seconds: a.seconds,
        reference_spp: a.reference_spp,
        candidates: a.candidates,
        tessellation: a.tessellation,
        environment: a.environment.spec(),
        threads: device.threads,
        repeats: a.repeats,
        reference: a.reference.clone(),
        out: a.out.clone(),
    };
    smlt_bench::run(&settings, device.gpu.as_ref(), |line| println!("{line}"))?;
    println!("wrote {}/results.csv and {}/tables.md", a.out.display(), a.out.display());
    Ok(())
}
