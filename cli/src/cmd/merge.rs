//! `smlt merge`: the part files of a render split with `--shard K/N`, checked and summed in
//! shard order into the image the unsplit render gives.

use std::path::PathBuf;

use super::args::exposure;
use smlt::output::Exposure;

/// `smlt merge`'s flags.
#[derive(clap::Args)]
pub struct Args {
    /// The part files (every shard 1..N of one render, in any order).
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// Output EXR (a tone-mapped PNG is written beside it).
    #[arg(long)]
    pub out: PathBuf,
    /// Exposure of the PNG in stops (default: automatic).
    #[arg(long, value_parser = exposure, allow_negative_numbers = true)]
    pub exposure: Option<f32>,
}

/// Runs `smlt merge`.
pub fn run(a: Args) -> anyhow::Result<()> {
    smlt::output::check_writable(&a.out)?;
    let parts: Vec<smlt::part::Part> =
        a.parts.iter().map(|p| smlt::part::read_part(p)).collect::<Result<_, _>>()?;
    let merged = smlt::part::merge(&parts)?;
    let ev = smlt::output::write_images_exposed(
        &a.out,
        merged.width,
        merged.height,
        &merged.rgb,
        a.exposure.map_or(Exposure::Auto, Exposure::Ev),
    )?;
    let id = &parts[0].identity;
    println!(
        "merged               {} shards of {} view {} ({}, seed {})",
        parts.len(),
        id.scene,
        id.view,
        id.settings.method(),
        id.settings.seed
    );
    for p in &parts {
        println!(
            "  shard {}/{}          {} iterations in {:.2} s on {}",
            p.shard, id.settings.shard.count, p.iterations, p.render_seconds, p.device
        );
    }
    super::render::print_summary(&merged, &id.settings);
    println!(
        "wrote                {} and {} (PNG at {ev:+.2} EV)",
        a.out.display(),
        smlt::output::png_path(&a.out).display()
    );
    Ok(())
}
