//! `scripts/gpu-tables.sh`, the paper's Table 3 and Figure 7 on a GPU in one call, in its short
//! mode on whatever Vulkan device is here (lavapipe in CI): every method of every view measured,
//! profiled inside an iteration with its ray ceiling, and the tables and the plot written to one
//! folder, so that the first GPU lent runs it unchanged.

mod common;

use std::path::Path;
use std::process::Command;

const METHODS: [&str; 12] =
    ["naive", "s2", "s3", "s4", "s5", "s6", "rc2", "rc4", "rc8", "rc16", "rc32", "rc64"];

#[test]
fn the_gpu_tables_script_writes_table_3_and_figure_7() {
    if common::gpu_or_skip("the_gpu_tables_script_writes_table_3_and_figure_7").is_none() {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scenes = root.join("../shared/scenes");
    if !scenes.join("sibenik/sibenik.gltf").exists() {
        assert_ne!(std::env::var("CI").as_deref(), Ok("true"), "CI=true and no {}", scenes.display());
        eprintln!("SKIPPED: no {}", scenes.display());
        return;
    }
    let out = std::env::temp_dir().join(format!("smlt-gpu-tables-{}", std::process::id()));
    let run = Command::new(root.join("scripts/gpu-tables.sh"))
        .arg("--short")
        .arg(&out)
        .env("SMLT", env!("CARGO_BIN_EXE_smlt"))
        .env("SHARED_SCENES", &scenes)
        .output()
        .expect("run scripts/gpu-tables.sh");
    let said = String::from_utf8_lossy(&run.stdout).to_string() + &String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{said}");
    let read = |name: &str| std::fs::read_to_string(out.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
    let tables = read("tables.md");
    for title in ["### Million mutations", "### Speedup of mutations/s over naive", "### Inside an iteration"]
    {
        assert!(tables.contains(title), "tables.md has no {title}");
    }
    // One profile row (pass times and the ray ceiling) per method and view.
    let passes = read("passes.csv");
    let rows: Vec<&str> = passes.lines().skip(1).collect();
    assert_eq!(rows.len(), METHODS.len() * 3, "{passes}");
    for m in METHODS {
        assert_eq!(rows.iter().filter(|r| r.split(',').nth(2) == Some(m)).count(), 3, "{m} in {passes}");
    }
    let results = read("results.csv");
    for view in ["sibenik,1", "sponza_banner,1", "sponza_banner,2"] {
        assert!(results.lines().any(|l| l.starts_with(view)), "no {view} in results.csv");
    }
    assert!(std::fs::metadata(out.join("speedup.png")).map(|m| m.len() > 0).unwrap_or(false));
    assert!(read("run.txt").contains("wall time"));
    println!("{}", read("run.txt"));
    std::fs::remove_dir_all(&out).unwrap();
}
