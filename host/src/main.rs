//! The `smlt` command line.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use smlt::gpu::Gpu;

#[derive(Parser)]
#[command(name = "smlt", version, about = "Coherent Metropolis light transport with speculative mutations")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Opens the Vulkan adapter, prints its name, and checks that the device computes the
    /// speculative-tree, reject-chain and mutation math exactly as the CPU does.
    Selftest {
        /// Seed of the random test cases.
        #[arg(long, default_value_t = 1)]
        seed: u32,
    },
}

fn selftest(seed: u32) -> anyhow::Result<()> {
    let gpu = Gpu::new()?;
    println!("adapter: {}", gpu.describe());
    let batch = smlt::selftest::standard_batch(seed);
    let cpu = batch.run_cpu();
    let device = batch.run_gpu(&gpu)?;
    let cmp = smlt::selftest::compare(&batch, &cpu, &device);
    if let Some(first) = cmp.mismatches.first() {
        anyhow::bail!(
            "device self-test failed: {} of {} values differ; first: {first}",
            cmp.mismatches.len(),
            cmp.floats + cmp.words
        );
    }
    println!(
        "self-test passed: {} cases, {} floats within {} ulps (max {:.1}), {} words exact, {} selections on a rounding boundary",
        batch.cases.len(),
        cmp.floats,
        smlt::selftest::TOLERANCE_ULPS,
        cmp.max_ulps,
        cmp.words,
        cmp.boundary_selections
    );
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Selftest { seed } => selftest(seed),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
