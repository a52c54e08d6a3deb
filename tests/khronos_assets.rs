//! The Khronos glTF-Validator's own test assets (`tests/khronos/`, Apache-2.0, with the
//! validator's expected report beside each): smlt never panics or hangs on one, refuses every
//! asset the validator reports an error for with one line, and refuses a valid one only for its
//! content (no triangles, nothing that emits light) or a feature it names as unsupported.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use smlt::scene::{SceneData, SceneError};

/// Every asset with its expected report, in a fixed order.
fn assets(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            assets(&path, out);
        } else if matches!(path.extension().and_then(|e| e.to_str()), Some("gltf" | "glb"))
            && report_path(&path).exists()
        {
            out.push(path);
        }
    }
}

fn report_path(asset: &Path) -> PathBuf {
    let mut name = asset.file_name().unwrap().to_os_string();
    name.push(".report.json");
    asset.with_file_name(name)
}

/// What loading an asset came to.
enum Outcome {
    Loaded,
    Refused(SceneError),
    Panicked(String),
    Hung,
}

/// Loads `path` on a thread of its own, within `limit`.
fn load(path: &Path, limit: Duration) -> Outcome {
    let (tx, rx) = mpsc::channel();
    let owned = path.to_path_buf();
    std::thread::spawn(move || {
        let result = std::panic::catch_unwind(|| SceneData::load(&owned));
        let _ = tx.send(result);
    });
    match rx.recv_timeout(limit) {
        Ok(Ok(Ok(_))) => Outcome::Loaded,
        Ok(Ok(Err(e))) => Outcome::Refused(e),
        Ok(Err(panic)) => Outcome::Panicked(
            panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default(),
        ),
        Err(_) => Outcome::Hung,
    }
}

#[test]
fn the_khronos_validator_assets_are_read_or_refused_in_one_line() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/khronos");
    let mut list = Vec::new();
    assets(&root, &mut list);
    assert!(list.len() > 350, "{} assets", list.len());
    let mut failures = Vec::new();
    let (mut loaded, mut refused, mut for_content, mut invalid_for_content) = (0, 0, 0, 0);
    for path in &list {
        let report: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(report_path(path)).unwrap()).unwrap();
        let errors = report["issues"]["numErrors"].as_u64().unwrap();
        let shown = path.strip_prefix(&root).unwrap().display().to_string();
        match load(path, Duration::from_secs(20)) {
            Outcome::Panicked(m) => failures.push(format!("{shown}: panicked: {m}")),
            Outcome::Hung => failures.push(format!("{shown}: still loading after 20 s")),
            Outcome::Loaded if errors > 0 => {
                let first = &report["issues"]["messages"][0];
                failures.push(format!(
                    "{shown}: read, but the validator reports {errors} errors ({})",
                    first["code"]
                ))
            }
            Outcome::Loaded => loaded += 1,
            Outcome::Refused(e) => {
                let line = e.to_string();
                if line.contains('\n') {
                    failures.push(format!("{shown}: refused in more than one line: {line}"));
                } else if errors > 0 {
                    refused += 1;
                    if matches!(e, SceneError::Empty(_) | SceneError::NoEmitter(_)) {
                        invalid_for_content += 1;
                    }
                } else if matches!(
                    e,
                    SceneError::Empty(_) | SceneError::NoEmitter(_) | SceneError::Unsupported { .. }
                ) {
                    for_content += 1;
                } else {
                    failures.push(format!("{shown}: valid, refused while reading: {line}"));
                }
            }
        }
    }
    // The assets hold no emitter, so a file whose errors lie where smlt reads nothing (an
    // animation, a skin) is refused for that: `invalid_for_content` counts them.
    println!(
        "{} assets: {loaded} read, {refused} refused with the validator's errors ({invalid_for_content} of them \
         for their content), {for_content} valid ones refused for their content or an unsupported feature named",
        list.len()
    );
    assert!(failures.is_empty(), "{} of {} assets:\n{}", failures.len(), list.len(), failures.join("\n"));
}
