//! `smlt plot`: the bench's plots and tables redrawn from a `results.csv` (also one with
//! peers' rows).

use std::path::PathBuf;

/// `smlt plot`'s flags.
#[derive(clap::Args)]
pub struct Args {
    /// The bench's results.csv.
    pub csv: PathBuf,
    /// Output folder.
    #[arg(long)]
    pub out: PathBuf,
}

/// Runs `smlt plot`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let text = std::fs::read_to_string(&a.csv)
        .map_err(|e| anyhow::anyhow!("cannot read {}: {e}", a.csv.display()))?;
    let rows =
        smlt_bench::results::read_csv(&text).map_err(|e| anyhow::anyhow!("{}: {e}", a.csv.display()))?;
    std::fs::create_dir_all(&a.out)?;
    smlt_bench::plots::plot(&rows, &a.out)?;
    // The tables of every method in the file (the bench's own and peers' rows alike), at the
    // longest time measured.
    let methods = smlt_bench::results::first_seen(rows.iter().map(|r| r.method.clone()));
    let seconds = rows.iter().map(|r| r.seconds).fold(0.0, f64::max).round();
    std::fs::write(a.out.join("tables.md"), smlt_bench::tables::tables(&methods, seconds, &rows, &[]))?;
    println!("wrote the plots and tables.md of {} rows to {}", rows.len(), a.out.display());
    Ok(())
}
