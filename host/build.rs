//! Hands the host the committed kernels module (`kernels/spirv/kernels.spv`, built by
//! `scripts/build-kernels.sh` with rust-gpu) as `SMLT_KERNELS_SPV`, after checking that it was
//! built from the kernels' current sources: a module whose inputs changed is refused, so a stale
//! module can never run beside the current kernel bodies that the CPU backend and the
//! difftests compile. Building smlt never builds rust-gpu's backend.

#[path = "../builder/src/inputs.rs"]
mod inputs;

fn main() {
    let manifest = std::path::PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let root = manifest.join("..");
    let spirv = root.join("kernels/spirv");
    let (hash, files) = match inputs::inputs_hash(&root) {
        Ok(found) => found,
        Err(e) => {
            println!("cargo::error=cannot read the kernels' sources to check the committed module: {e}");
            return;
        }
    };
    for file in &files {
        println!("cargo::rerun-if-changed={}", file.display());
    }
    for dir in ["kernels/src", "shared/src", "kernels/spirv"] {
        println!("cargo::rerun-if-changed={}", root.join(dir).display());
    }
    let committed = std::fs::read_to_string(spirv.join("inputs.hash")).unwrap_or_default();
    if committed.trim() != hash {
        println!(
            "cargo::error=the committed kernels module is stale (kernels/spirv/inputs.hash: {}, the kernels' sources: \
             {hash}): rebuild it with scripts/build-kernels.sh and commit kernels/spirv/",
            if committed.trim().is_empty() { "missing" } else { committed.trim() }
        );
        return;
    }
    println!("cargo::rustc-env=SMLT_KERNELS_SPV={}", spirv.join("kernels.spv").display());
}
