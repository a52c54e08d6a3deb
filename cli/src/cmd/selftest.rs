//! `smlt selftest`: the device computes the speculative-tree, reject-chain and mutation math
//! exactly as the CPU does (`smlt::selftest`).

use smlt::gpu::Gpu;

/// `smlt selftest`'s flags.
#[derive(clap::Args)]
pub struct Args {
    /// Seed of the random test cases.
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
    /// The Vulkan adapter, by index or part of its name (default: the best one).
    #[arg(long)]
    pub adapter: Option<String>,
}

/// Runs `smlt selftest`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let gpu = Gpu::open(a.adapter.as_deref())?;
    println!("adapter: {}", gpu.describe());
    let batch = smlt::selftest::standard_batch(a.seed);
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
