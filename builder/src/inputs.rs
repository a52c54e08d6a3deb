//! The hash of everything the kernels module is built from, computed the same way by the
//! builder (which writes it beside the module) and by the host's build script (which refuses
//! a module whose inputs changed): the `kernels` and `shared` crates' manifests and sources,
//! the toolchain files (the root's compiles the kernels, the builder's builds rust-gpu's
//! backend), the builder's own manifest, lock file and source (its options), and the root
//! lock file's entries for the packages the kernels depend on (name, version, source,
//! checksum). FNV-1a, 64 bits, over the files' relative paths and bytes in path order.
//!
//! This file is compiled twice, as a module of the builder and of `host/build.rs`
//! (`#[path]`), so there is one definition of the hash.

use std::path::{Path, PathBuf};

#[path = "fnv.rs"]
mod fnv;
pub use fnv::fnv1a;

/// The files, relative to the repository root, that are hashed whole.
fn input_files(root: &Path) -> std::io::Result<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = [
        "kernels/Cargo.toml",
        "shared/Cargo.toml",
        "rust-toolchain.toml",
        "builder/Cargo.toml",
        "builder/Cargo.lock",
        "builder/rust-toolchain.toml",
        "builder/src/main.rs",
        "builder/src/inputs.rs",
        "builder/src/fnv.rs",
    ]
    .iter()
    .map(PathBuf::from)
    .collect();
    for dir in ["kernels/src", "shared/src"] {
        let mut stack = vec![root.join(dir)];
        while let Some(d) = stack.pop() {
            for entry in std::fs::read_dir(&d)? {
                let path = entry?.path();
                if path.is_dir() {
                    stack.push(path);
                } else if path.extension().is_some_and(|e| e == "rs") {
                    files.push(path.strip_prefix(root).expect("below the root").to_path_buf());
                }
            }
        }
    }
    files.sort();
    Ok(files)
}

/// The root lock file's `[[package]]` entries reachable from `kernels`, as text.
fn kernel_lock_entries(lock: &str) -> String {
    // name -> (the entry's identifying lines, its dependencies' names)
    let mut packages: std::collections::BTreeMap<String, (String, Vec<String>)> = Default::default();
    for block in lock.split("[[package]]").skip(1) {
        let mut name = String::new();
        let mut identity = String::new();
        let mut deps = Vec::new();
        let mut in_deps = false;
        for line in block.lines() {
            let line = line.trim();
            if in_deps {
                if line.starts_with(']') {
                    in_deps = false;
                } else {
                    // "name" or "name version"
                    deps.push(
                        line.trim_matches(|c| c == '"' || c == ',')
                            .split(' ')
                            .next()
                            .unwrap_or("")
                            .to_string(),
                    );
                }
            } else if let Some(v) = line.strip_prefix("name = ") {
                name = v.trim_matches('"').to_string();
                identity.push_str(line);
                identity.push('\n');
            } else if line.starts_with("version = ")
                || line.starts_with("source = ")
                || line.starts_with("checksum = ")
            {
                identity.push_str(line);
                identity.push('\n');
            } else if line.starts_with("dependencies = [") {
                in_deps = !line.ends_with(']');
            }
        }
        // Two versions of one name: keep both entries under distinct keys.
        let key =
            if packages.contains_key(&name) { format!("{name}#{}", identity.len()) } else { name.clone() };
        packages.insert(key, (identity, deps));
    }
    let mut seen = std::collections::BTreeSet::new();
    let mut stack = vec!["kernels".to_string()];
    while let Some(name) = stack.pop() {
        for (key, (_, deps)) in packages.iter().filter(|(k, _)| k.split('#').next() == Some(name.as_str())) {
            if seen.insert(key.clone()) {
                stack.extend(deps.iter().cloned());
            }
        }
    }
    seen.iter().map(|k| packages[k].0.as_str()).collect()
}

/// The hash of the kernels module's inputs below the repository `root`, and the files read
/// (for a build script's rerun-if-changed).
pub fn inputs_hash(root: &Path) -> std::io::Result<(String, Vec<PathBuf>)> {
    let mut bytes = Vec::new();
    let files = input_files(root)?;
    for file in &files {
        bytes.extend(file.to_string_lossy().replace('\\', "/").as_bytes());
        bytes.push(0);
        bytes.extend(std::fs::read(root.join(file))?);
        bytes.push(0);
    }
    let lock = std::fs::read_to_string(root.join("Cargo.lock"))?;
    bytes.extend(kernel_lock_entries(&lock).as_bytes());
    let mut read: Vec<PathBuf> = files.iter().map(|f| root.join(f)).collect();
    read.push(root.join("Cargo.lock"));
    Ok((fnv1a(&bytes), read))
}
