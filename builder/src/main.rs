//! Builds the kernels module: `kernels` compiled to one SPIR-V module by rust-gpu
//! (`spirv-unknown-vulkan1.2`, release, with variable names kept for the driver's messages),
//! written to `kernels/spirv/kernels.spv` with the hash of its inputs (`inputs.rs`) in
//! `kernels/spirv/inputs.hash`. The host embeds that module and refuses to build when the
//! hash no longer matches its inputs.
//!
//! `cargo run --release` in `builder/` (or `scripts/build-kernels.sh`); `--check` compares the
//! rebuilt module with the committed one and fails when they differ.

mod inputs;

use std::path::PathBuf;
use std::process::ExitCode;

use spirv_builder::{SpirvBuilder, SpirvMetadata};

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let check = std::env::args().any(|a| a == "--check");
    let root =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").canonicalize().map_err(|e| e.to_string())?;
    let mut builder = SpirvBuilder::new(root.join("kernels"), "spirv-unknown-vulkan1.2")
        .release(true)
        .spirv_metadata(SpirvMetadata::NameVariables);
    builder.build_script.defaults = false;
    let result = builder.build().map_err(|e| format!("rust-gpu could not build the kernels: {e}"))?;
    let built = std::fs::read(result.module.unwrap_single()).map_err(|e| e.to_string())?;
    let (hash, _) =
        inputs::inputs_hash(&root).map_err(|e| format!("cannot hash the kernels' inputs: {e}"))?;
    let out = root.join("kernels/spirv");
    if check {
        let committed = std::fs::read(out.join("kernels.spv")).unwrap_or_default();
        let committed_hash = std::fs::read_to_string(out.join("inputs.hash")).unwrap_or_default();
        if committed_hash.trim() != hash {
            return Err(format!(
                "kernels/spirv/inputs.hash is {} but the inputs hash to {hash}: run scripts/build-kernels.sh and commit",
                committed_hash.trim()
            ));
        }
        if committed != built {
            return Err(format!(
                "the committed kernels/spirv/kernels.spv ({} bytes, {}) is not what its sources build ({} bytes, {}): \
                 run scripts/build-kernels.sh and commit",
                committed.len(),
                inputs::fnv1a(&committed),
                built.len(),
                inputs::fnv1a(&built)
            ));
        }
        println!(
            "kernels/spirv/kernels.spv is what its sources build ({} bytes, inputs {hash})",
            built.len()
        );
        return Ok(());
    }
    std::fs::create_dir_all(&out).map_err(|e| e.to_string())?;
    std::fs::write(out.join("kernels.spv"), &built).map_err(|e| e.to_string())?;
    std::fs::write(out.join("inputs.hash"), format!("{hash}\n")).map_err(|e| e.to_string())?;
    println!("wrote kernels/spirv/kernels.spv ({} bytes) and inputs.hash ({hash})", built.len());
    Ok(())
}
