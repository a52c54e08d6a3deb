//! `smlt render`: one render of a scene view to an EXR (and a tone-mapped PNG), or to a part
//! file with `--shard`, with a progress bar, Ctrl-C and checkpoints, and the closing summary.

use std::cell::Cell;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use indicatif::{ProgressBar, ProgressStyle};

use super::args::{exposure, positive_f64, ChainArgs, DeviceArgs, ImageArgs, PathArgs, SceneArgs};
use smlt::output::Exposure;
use smlt::render::auto::KeptPilot;
use smlt::render::{self, Budget, Integrator, Method, MethodChoice, Settings, Shard};

/// `smlt render`'s flags.
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    #[allow(missing_docs)] // flattened: documented on SceneArgs
    pub scene: SceneArgs,
    /// auto (chosen for the view by a short pilot of pt and naive; the summary says
    /// which and why), pt (the path tracer), naive, s<d> (speculative tree of depth d = 1..8; s1
    /// is naive), or rc<l> (reject chain of l = 2..64 proposals); path-naive, path-s<d>,
    /// path-rc<l>: the same chains over the path tracer's estimate instead of the paper's
    /// multiplexed paths.
    #[arg(long, default_value = "auto", value_parser = |s: &str| s.parse::<MethodChoice>())]
    pub method: MethodChoice,
    /// Stop after this many seconds of iterations (after the bootstrap).
    #[arg(long, value_parser = positive_f64, conflicts_with = "mutations_per_pixel", allow_negative_numbers = true)]
    pub time: Option<f64>,
    /// Stop after this many candidate paths per pixel (default 64 when --time is absent); for
    /// pt, samples per pixel (rounded up to whole rounds).
    #[arg(long, value_parser = positive_f64, allow_negative_numbers = true)]
    pub mutations_per_pixel: Option<f64>,
    #[command(flatten)]
    #[allow(missing_docs)] // flattened: documented on ImageArgs
    pub image: ImageArgs,
    #[command(flatten)]
    #[allow(missing_docs)] // flattened: documented on PathArgs
    pub path: PathArgs,
    #[command(flatten)]
    #[allow(missing_docs)] // flattened: documented on DeviceArgs
    pub device: DeviceArgs,
    /// Output EXR (a tone-mapped PNG is written beside it); with --shard, the part file
    /// (default smlt.shard-K-of-N.exr).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Exposure of the PNG in stops (default: automatic, from the image's 95th luminance
    /// percentile); the EXR is always linear radiance.
    #[arg(long, value_parser = exposure, allow_negative_numbers = true)]
    pub exposure: Option<f32>,
    /// Render only part K of N of the chains, into a part file for `smlt merge`: the parts of
    /// one render merge into the image the same command without --shard gives.
    #[arg(long, value_parser = |s: &str| s.parse::<Shard>())]
    pub shard: Option<Shard>,
    /// Candidate paths traced per iteration, divided among chains (default: 262144 on a GPU,
    /// 16384 on a CPU Vulkan device such as lavapipe, 4096 with --device cpu); for pt, paths per
    /// iteration, as whole samples per pixel (at least one).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16_777_216))]
    pub candidates: Option<u32>,
    #[command(flatten)]
    #[allow(missing_docs)] // flattened: documented on ChainArgs
    pub chains: ChainArgs,
    /// Write the image so far every this many seconds (Ctrl-C always writes it once more).
    #[arg(long, value_parser = positive_f64, allow_negative_numbers = true)]
    pub checkpoint: Option<f64>,
}

/// The command line's view of a render: the compilation spinner, progress bar, Ctrl-C,
/// checkpoints.
struct CliObserver<'a> {
    bar: ProgressBar,
    spinner: Option<ProgressBar>,
    stop: Arc<AtomicBool>,
    every: Option<f64>,
    last: f64,
    out: &'a Path,
    exposure: Option<f32>,
    checkpoints: Rc<Cell<u32>>,
    /// Auto's pilot, pooled into every image written.
    kept: Option<&'a KeptPilot>,
}

impl render::Observer for CliObserver<'_> {
    fn compiling(&mut self) {
        let spinner = ProgressBar::new_spinner();
        spinner.set_message("compiling kernels (first run only)");
        spinner.enable_steady_tick(std::time::Duration::from_millis(120));
        self.spinner = Some(spinner);
    }

    fn compiled(&mut self) {
        if let Some(spinner) = self.spinner.take() {
            spinner.finish_and_clear();
        }
    }

    fn progress(&mut self, fraction: f64) {
        self.bar.set_position((fraction * 1000.0) as u64);
    }

    fn stop_requested(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    fn checkpoint_due(&mut self, elapsed: f64) -> bool {
        match self.every {
            Some(every) if elapsed - self.last >= every => {
                self.last = elapsed;
                true
            }
            _ => false,
        }
    }

    fn checkpoint(&mut self, image: &render::Rendered) {
        let exposure = self.exposure.map_or(Exposure::Auto, Exposure::Ev);
        let rgb = KeptPilot::image(self.kept, image);
        match smlt::output::write_images_exposed(self.out, image.width, image.height, &rgb, exposure) {
            Ok(_) => self.checkpoints.set(self.checkpoints.get() + 1),
            Err(e) => self.bar.println(format!("warning: checkpoint not written: {e}")),
        }
    }
}

/// Runs `smlt render`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let out = a.out.clone().unwrap_or_else(|| match a.shard {
        Some(k) => PathBuf::from(format!("smlt.shard-{}-of-{}.exr", k.index, k.count)),
        None => PathBuf::from("smlt.exr"),
    });
    smlt::output::check_writable(&out)?;
    let loading = std::time::Instant::now();
    let (scene, scene_hash) = a.scene.load()?;
    let load_seconds = loading.elapsed().as_secs_f64();
    let budget = match (a.time, a.mutations_per_pixel) {
        (Some(t), _) => Budget::Seconds(t),
        (None, Some(m)) => Budget::MutationsPerPixel(m),
        (None, None) => Budget::MutationsPerPixel(render::DEFAULT_MUTATIONS_PER_PIXEL),
    };
    let device = a.device.open()?;
    let why = device.why.clone();
    let mut settings = Settings {
        width: a.image.width,
        height: a.image.height(&scene),
        max_depth: a.path.max_depth,
        seed: a.path.seed,
        integrator: Integrator::new(
            match a.method {
                MethodChoice::Named(m) => m,
                MethodChoice::Auto => Method::NAIVE,
            },
            a.chains.settings(),
        ),
        budget,
        candidates: a.candidates.unwrap_or(render::default_candidates(device.gpu.as_ref())),
        shard: a.shard.unwrap_or(Shard::WHOLE),
    };
    // What a part file records: the user's budget (auto's render has what its pilot left).
    let asked = settings.clone();
    let mut chosen = None;
    if a.method == MethodChoice::Auto {
        let (gpu, threads) = (device.gpu.as_ref(), device.threads);
        let candidates: Vec<String> = render::auto::CANDIDATES.iter().map(|m| m.to_string()).collect();
        let spinner = ProgressBar::new_spinner();
        spinner.set_message(format!("auto: a pilot of {} on the view", candidates.join(", ")));
        spinner.enable_steady_tick(std::time::Duration::from_millis(120));
        let choice =
            render::auto::choose(&scene, &settings, &mut |p| render::new_backend(gpu, &scene, p, threads));
        spinner.finish_and_clear();
        let choice = choice?;
        settings = Settings {
            budget: render::auto::remaining_budget(settings.budget, choice.seconds),
            ..settings.with_method(choice.method)
        };
        chosen = Some(choice);
    }
    if settings.metropolis().is_some() && settings.shard.count > settings.chains() {
        anyhow::bail!(
            "--shard {}: the render has only {} chains to split; use at most {} shards or more --candidates",
            settings.shard,
            settings.chains(),
            settings.chains()
        );
    }
    let params = render::base_params(&scene, &settings);
    let on_device = device.gpu.is_some();
    let mut backend = render::new_backend(device.gpu.as_ref(), &scene, &params, device.threads)?;
    println!("device: {} — {why}", backend.describe());
    if let Some(choice) = &chosen {
        println!("auto: chose {}", choice.describe());
    }
    let buffers_mib = smlt::passes::buffers::device_bytes(&scene, &params) as f64 / 1048576.0;
    let work = match settings.integrator {
        Integrator::PathTracer => format!(
            "{} samples per pixel an iteration{}",
            settings.samples_per_round(),
            match a.shard {
                Some(k) => format!("; shard {k}: rounds {}, {}, …", k.index - 1, k.index - 1 + k.count),
                None => String::new(),
            }
        ),
        Integrator::Metropolis(_) => format!(
            "{} chains{}, {} candidates per iteration",
            params.chains,
            match a.shard {
                Some(k) => format!(" of {}: shard {k}", settings.chains()),
                None => String::new(),
            },
            params.candidates
        ),
    };
    println!(
        "rendering {} at {}×{} with {} ({work})",
        scene.name,
        settings.width,
        settings.height,
        settings.method()
    );
    println!("scene: {}, loaded in {load_seconds:.2} s", scene.describe_contents());
    if let Some(env) = a.scene.environment.spec() {
        let e = &scene.environment;
        println!("lit by environment {} ({} × {} texels)", env.describe(), e.width, e.height);
    }
    if let Some(line) = render::blind_spot(settings.method(), &scene) {
        eprintln!("note: {line}");
    }
    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {percent:>3}% {elapsed_precise} eta {eta}")
            .expect("progress template"),
    );
    // Ctrl-C ends the render after the current iteration and writes the image so far; a second
    // Ctrl-C exits at once.
    let stop = Arc::new(AtomicBool::new(false));
    let flag = stop.clone();
    let _ = ctrlc::set_handler(move || {
        if flag.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
    });
    let checkpoints = Rc::new(Cell::new(0));
    let observer = CliObserver {
        bar: bar.clone(),
        spinner: None,
        stop: stop.clone(),
        every: if a.shard.is_some() { None } else { a.checkpoint },
        last: 0.0,
        out: &out,
        exposure: a.exposure,
        checkpoints: checkpoints.clone(),
        kept: chosen.as_ref().and_then(|c| c.kept.as_ref()),
    };
    let result = render::render(&scene, &settings, backend.as_mut(), observer)?;
    bar.finish_and_clear();
    let written = match a.shard {
        Some(shard) => {
            let recorded = Settings { budget: asked.budget, ..settings.clone() };
            let identity =
                smlt::part::Identity::new(&scene.name, &scene_hash, a.scene.view(&scene), &recorded);
            let identity = if chosen.is_some() { identity.chosen_by_auto() } else { identity };
            smlt::part::write_part(&out, &identity, shard, &result, &backend.describe())?;
            format!("part {shard}: {} (combine the parts with smlt merge)", out.display())
        }
        None => {
            let ev = smlt::output::write_images_exposed(
                &out,
                result.width,
                result.height,
                &KeptPilot::image(chosen.as_ref().and_then(|c| c.kept.as_ref()), &result),
                a.exposure.map_or(Exposure::Auto, Exposure::Ev),
            )?;
            format!(
                "{} and {} (PNG at {ev:+.2} EV{})",
                out.display(),
                smlt::output::png_path(&out).display(),
                if a.exposure.is_none() { ", automatic" } else { "" }
            )
        }
    };
    if let Some(choice) = &chosen {
        println!(
            "method               {} (chosen by auto; its pilot {:.2} s)",
            choice.method, choice.seconds
        );
        if let Some(kept) = &choice.kept {
            println!(
                "pilot kept           {} {} of {}'s pilot, pooled into the image",
                kept.candidates,
                if settings.metropolis().is_some() { "candidates" } else { "paths" },
                choice.method
            );
        }
    }
    print_summary(&result, &settings);
    if on_device {
        println!("device buffers       {buffers_mib:.1} MiB");
    }
    if checkpoints.get() > 0 {
        println!("checkpoints          {}", checkpoints.get());
    }
    println!("wrote                {written}");
    if stop.load(Ordering::SeqCst) {
        anyhow::bail!("interrupted: the image so far was written to {}", out.display());
    }
    Ok(())
}

/// The closing summary of a render or a merge with `settings`.
pub fn print_summary(r: &render::Rendered, settings: &Settings) {
    let s = &r.stats;
    let Some(m) = settings.metropolis() else {
        let pixels = r.width as f64 * r.height as f64;
        println!("iterations           {}", s.iterations);
        println!("paths traced         {}", s.candidates);
        println!("samples per pixel    {}", s.candidates as f64 / pixels);
        if s.render_seconds > 0.0 {
            println!("paths/s              {:.3} M", s.candidates as f64 / s.render_seconds / 1e6);
        }
        if let Some(seconds) = s.compile_seconds {
            println!("kernels compiled     {seconds:.2} s (before the clock)");
        }
        println!("render time          {:.2} s", s.render_seconds);
        return;
    };
    println!("chains               {}", s.chains);
    println!("iterations           {}", s.iterations);
    println!("candidates traced    {}", s.candidates);
    println!("chain steps          {:.0}", s.steps);
    if s.render_seconds > 0.0 {
        println!(
            "mutations/s          {:.3} M (candidates traced per second)",
            s.candidates as f64 / s.render_seconds / 1e6
        );
        println!("chain steps/s        {:.3} M", s.steps / s.render_seconds / 1e6);
    }
    println!("acceptance rate      {:.3}", s.acceptance);
    let source = if s.large_steps > 0 {
        format!("{} bootstrap + {} large-step samples", s.bootstrap_samples, s.large_steps)
    } else if m.chains.mutation.p_large > 0.0 {
        format!("{} bootstrap samples (no large step yet)", s.bootstrap_samples)
    } else {
        format!("{} bootstrap samples only (--p-large 0: no large steps refine it)", s.bootstrap_samples)
    };
    println!(
        "normalisation b      {:.6} ± {:.6} ({:.2} %; {source})",
        s.b,
        s.b_standard_error,
        100.0 * s.b_relative_standard_error()
    );
    println!("NaN/Inf rejected     {}", s.invalid);
    if let Some(seconds) = s.compile_seconds {
        println!("kernels compiled     {seconds:.2} s (before the clock)");
    }
    if let Some(seconds) = s.importance_seconds {
        use smlt::render::importance::{block_side, IMPORTANCE_SPP};
        let side = block_side(r.width, r.height);
        let per =
            if side == 1 { "spp".to_string() } else { format!("samples a {side}×{side} block of pixels") };
        println!("pixel importance     {IMPORTANCE_SPP} {per} in {seconds:.2} s (before the clock)");
    }
    if s.bootstrap_seconds > 0.0 {
        println!("bootstrap            {} samples in {:.2} s", s.bootstrap_samples, s.bootstrap_seconds);
    }
    println!("render time          {:.2} s", s.render_seconds);
}
