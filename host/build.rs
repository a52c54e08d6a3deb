//! Compiles the `kernels` crate to one SPIR-V module with rust-gpu and hands its path to the
//! host as the `SMLT_KERNELS_SPV` environment variable (read with `env!`).

use spirv_builder::{SpirvBuilder, SpirvMetadata};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let manifest = std::path::PathBuf::from(std::env::var("CARGO_MANIFEST_DIR")?);
    let kernels = manifest.join("../kernels");
    let mut builder = SpirvBuilder::new(&kernels, "spirv-unknown-vulkan1.2")
        .release(true)
        .spirv_metadata(SpirvMetadata::NameVariables);
    builder.build_script.defaults = true;
    let result = builder.build()?;
    let path = result.module.unwrap_single();
    println!("cargo::rustc-env=SMLT_KERNELS_SPV={}", path.display());
    Ok(())
}
