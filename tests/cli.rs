//! The `smlt` command line as a user runs it.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

fn smlt(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_smlt")).args(args).output().expect("run smlt");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    (out.status.success(), String::from_utf8_lossy(&out.stdout).into_owned(), stderr)
}

/// A tiny render of the default scene on `device` into `out`, as a command to adjust (its
/// environment) and run.
fn tiny_render(device: &str, out: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_smlt"));
    command.args([
        "render",
        "--width",
        "8",
        "--height",
        "6",
        "--mutations-per-pixel",
        "2",
        "--device",
        device,
    ]);
    command.arg("--out").arg(out);
    command
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("smlt-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn check_render(dir: &Path, extra: &[&str]) -> String {
    let exr = dir.join("out.exr");
    let mut args =
        vec!["render", "--width", "12", "--height", "7", "--mutations-per-pixel", "8", "--bootstrap", "4096"];
    args.extend_from_slice(extra);
    let exr_arg = exr.to_str().unwrap().to_string();
    args.extend_from_slice(&["--out", &exr_arg]);
    let (ok, stdout, stderr) = smlt(&args);
    assert!(ok, "{stderr}");
    // Without --method, auto chooses and says so; the summary is the chosen method's.
    let chosen = match stdout.lines().find_map(|l| l.strip_prefix("method ")) {
        Some(line) => {
            assert!(!extra.contains(&"--method") && line.contains("(chosen by auto"), "{stdout}");
            line.split_whitespace().next().unwrap().to_string()
        }
        None => {
            extra[extra.iter().position(|a| *a == "--method").expect("auto names its choice") + 1].to_string()
        }
    };
    let keys: &[&str] = if chosen == "pt" {
        &["paths traced", "samples per pixel", "paths/s"]
    } else {
        &[
            "chains",
            "candidates traced",
            "chain steps",
            "mutations/s",
            "acceptance rate",
            "normalisation b",
            "NaN/Inf rejected",
        ]
    };
    for key in keys {
        assert!(stdout.contains(key), "summary lacks {key}: {stdout}");
    }
    let (w, h, rgb) = smlt::output::read_exr(&exr).unwrap();
    assert_eq!((w, h), (12, 7));
    assert!(rgb.iter().all(|v| v.is_finite() && *v >= 0.0) && rgb.iter().any(|v| *v > 0.0));
    let png = image::open(dir.join("out.png")).unwrap();
    assert_eq!((png.width(), png.height()), (12, 7));
    stdout
}

/// A new user's first render, on a machine without a display (no `XDG_RUNTIME_DIR`), prints
/// no error: the summary on stdout, and on stderr only the progress.
#[test]
fn a_render_without_a_display_prints_no_error() {
    for device in ["cpu", "gpu"] {
        if device == "gpu" && common::gpu_or_skip("a_render_without_a_display_prints_no_error").is_none() {
            continue;
        }
        let dir = temp_dir(&format!("quiet-{device}"));
        let out = tiny_render(device, &dir.join("q.exr")).env_remove("XDG_RUNTIME_DIR").output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        assert!(!stderr.to_lowercase().contains("error"), "{device}: {stderr}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// The CPU backend names its ray caster on the first line: Embree where it is installed (as
/// in CI), obvhs's traversal when `SMLT_RAY_CASTER=obvhs` asks for it; both render.
#[test]
fn the_cpu_backend_names_its_ray_caster() {
    for (caster, expected) in [(None, "Embree 3"), (Some("obvhs"), "obvhs")] {
        let dir = temp_dir(&format!("caster-{expected}").replace(' ', "-"));
        let mut command = tiny_render("cpu", &dir.join("c.exr"));
        if let Some(c) = caster {
            command.env("SMLT_RAY_CASTER", c);
        }
        let out = command.output().unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let first = stdout.lines().next().unwrap_or_default();
        if caster.is_none() && smlt::caster::embree_unavailable().is_some() {
            assert_ne!(std::env::var("CI").as_deref(), Ok("true"), "CI=true and no Embree");
            eprintln!("SKIPPED the Embree line: {:?}", smlt::caster::embree_unavailable());
        } else {
            assert!(first.contains(&format!("rays through {expected}")), "{first}");
        }
        assert!(dir.join("c.exr").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

#[test]
fn renders_the_default_scene_on_the_cpu() {
    let dir = temp_dir("cpu");
    check_render(&dir, &["--device", "cpu"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn renders_the_default_scene_on_the_device() {
    if common::gpu_or_skip("renders_the_default_scene_on_the_device").is_none() {
        return;
    }
    let dir = temp_dir("gpu");
    check_render(&dir, &["--device", "gpu", "--candidates", "1024", "--method", "s2"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Each bad input: non-zero exit, one line on stderr naming the problem, no output written.
#[test]
fn bad_input_gets_one_line_and_no_output() {
    let dir = temp_dir("bad");
    let out = dir.join("x.exr");
    let out_s = out.to_str().unwrap();
    let garbage = dir.join("garbage.glb");
    std::fs::write(&garbage, [0x13u8, 0x57, 0x9b, 0xdf, 1, 2, 3, 4, 5, 6, 7, 8]).unwrap();
    let truncated = dir.join("truncated.gltf");
    std::fs::write(&truncated, "{\"asset\": {\"version\": \"2.0\"}, \"scenes\": [").unwrap();
    // Node 0's child is node 1 and node 1's child is node 0: a walk of the graph never ends.
    let cycle = dir.join("cycle.gltf");
    std::fs::write(
        &cycle,
        r#"{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
            "nodes": [{"children": [1]}, {"children": [0]}]}"#,
    )
    .unwrap();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["render".into(), dir.join("missing.gltf").display().to_string()], "missing.gltf"),
        (vec!["render".into(), dir.display().to_string()], "is a directory"),
        (vec!["render".into(), garbage.display().to_string()], "garbage.glb"),
        (vec!["render".into(), truncated.display().to_string()], "truncated.gltf"),
        (
            vec!["render".into(), cycle.display().to_string()],
            "node 0 is reached twice (again as a child of node 1)",
        ),
        (vec!["render".into(), "--method".into(), "s9".into()], "s9"),
        (vec!["render".into(), "--method".into(), "s0".into()], "s0"),
        (vec!["render".into(), "--method".into(), "bogus".into()], "bogus"),
        (vec!["render".into(), "--method".into(), "rc1".into()], "rc1"),
        (vec!["render".into(), "--method".into(), "rc65".into()], "rc65"),
        (vec!["render".into(), "--method".into(), "path-pt".into()], "use pt"),
        (vec!["render".into(), "--method".into(), "path-foo".into()], "'path-foo' is not a method"),
        (vec!["render".into(), "--width".into(), "0".into()], "width"),
        (vec!["render".into(), "--time".into(), "-1".into()], "time"),
        (vec!["render".into(), "--time".into(), "0".into()], "time"),
        (vec!["render".into(), "--out".into(), "/nonexistent-dir/x.exr".into()], "/nonexistent-dir/x.exr"),
        (vec!["render".into(), "--out".into(), dir.join("x.png").display().to_string()], ".exr"),
        (
            vec!["render".into(), "--environment".into(), dir.join("sky.exr").display().to_string()],
            "no such file",
        ),
        (vec!["render".into(), "--environment".into(), garbage.display().to_string()], "reads .exr and .hdr"),
        (vec!["render".into(), "--environment".into(), "1,2".into()], "one value or three"),
        (vec!["render".into(), "--environment".into(), "-1".into()], "≥ 0"),
        (
            vec![
                "render".into(),
                "--environment".into(),
                "1".into(),
                "--environment-strength".into(),
                "nan".into(),
            ],
            "strength",
        ),
        (vec!["render".into(), "--environment-strength".into(), "2".into()], "--environment"),
    ];
    for (mut args, needle) in cases {
        if !args.iter().any(|a| a == "--out") {
            args.extend(["--out".to_string(), out_s.to_string(), "--device".into(), "cpu".into()]);
        }
        let refs: Vec<&str> = args.iter().map(|s| s.as_str()).collect();
        let (ok, _, stderr) = smlt(&refs);
        assert!(!ok, "{args:?} succeeded");
        let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
        assert!(
            lines.iter().any(|l| l.contains(needle)),
            "{args:?}: stderr does not name '{needle}': {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
        assert!(!out.exists(), "{args:?} left an output file");
        assert_eq!(lines.len(), 1, "{args:?}: more than one line: {stderr}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Odd image sizes and candidate counts that do not divide the workgroup size (64) or the tree:
/// the render finishes with a finite, non-negative image of exactly the asked size.
#[test]
fn odd_sizes_and_chain_counts_on_the_device() {
    if common::gpu_or_skip("odd_sizes_and_chain_counts_on_the_device").is_none() {
        return;
    }
    let dir = temp_dir("odd");
    for (w, h, method, candidates) in
        [(1, 1, "naive", "1000"), (1, 37, "s3", "1000"), (1023, 7, "rc8", "999")]
    {
        let exr = dir.join(format!("{w}x{h}.exr"));
        let (ws, hs) = (w.to_string(), h.to_string());
        let args = [
            "render",
            "--width",
            &ws,
            "--height",
            &hs,
            "--method",
            method,
            "--candidates",
            candidates,
            "--mutations-per-pixel",
            "4",
            "--bootstrap",
            "2048",
            "--device",
            "gpu",
            "--out",
            exr.to_str().unwrap(),
        ];
        let (ok, _, stderr) = smlt(&args);
        assert!(ok, "{w}×{h} {method}: {stderr}");
        let (rw, rh, rgb) = smlt::output::read_exr(&exr).unwrap();
        assert_eq!((rw, rh), (w, h));
        assert!(rgb.iter().all(|v| v.is_finite() && *v >= 0.0));
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Device-dependent bad input: more than the device's buffer limits (the error names the
/// limit), and no Vulkan adapter at all (the error says how to install lavapipe).
#[test]
fn device_limits_and_a_missing_adapter_are_one_line_errors() {
    let dir = temp_dir("limits");
    let out = dir.join("x.exr");
    let out_s = out.to_str().unwrap();
    if common::gpu_or_skip("device_limits_and_a_missing_adapter_are_one_line_errors").is_some() {
        for args in [
            vec!["render", "--device", "gpu", "--width", "16384", "--height", "16384", "--out", out_s],
            vec!["render", "--device", "gpu", "--candidates", "16777216", "--out", out_s],
        ] {
            let (ok, _, stderr) = smlt(&args);
            assert!(!ok && stderr.contains("max_storage_buffer_binding_size"), "{args:?}: {stderr}");
            assert_eq!(stderr.lines().count(), 1, "{stderr}");
            assert!(!out.exists());
        }
    }
    let missing = dir.join("no-such-icd.json");
    let output = Command::new(env!("CARGO_BIN_EXE_smlt"))
        .args(["render", "--device", "gpu", "--out", out_s])
        .env("VK_DRIVER_FILES", &missing)
        .env("VK_ICD_FILENAMES", &missing)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(stderr.contains("no Vulkan adapter") && stderr.contains("lavapipe"), "{stderr}");
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A scene whose only light faces away from everything the camera can reach: every bootstrap
/// sample is zero, and the render says so instead of dividing by zero.
#[test]
fn a_bootstrap_of_zeros_is_a_one_line_error() {
    let dir = temp_dir("dark");
    let mut b = smlt::scenes::GltfBuilder::new();
    let lamp = b.material("lamp", [0.5; 3], [1.0; 3], 1.0, None);
    // A quad in the plane y = 0, emitting towards −y (away from the camera above it).
    b.quad(
        lamp,
        [
            glam::Vec3::new(-1., 0., -1.),
            glam::Vec3::new(1., 0., -1.),
            glam::Vec3::new(1., 0., 1.),
            glam::Vec3::new(-1., 0., 1.),
        ],
    );
    b.camera(glam::Vec3::new(0.0, 3.0, 0.1), glam::Vec3::ZERO, glam::Vec3::Y, 0.8);
    let scene = dir.join("dark.gltf");
    std::fs::write(&scene, b.to_json()).unwrap();
    let out = dir.join("x.exr");
    let (ok, _, stderr) = smlt(&[
        "render",
        scene.to_str().unwrap(),
        "--device",
        "cpu",
        "--bootstrap",
        "4096",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok && stderr.contains("bootstrap samples carry no light"), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Ctrl-C (SIGINT) during a render writes the image so far and exits non-zero; checkpoints
/// were written before it.
#[test]
fn ctrl_c_writes_the_image_so_far() {
    let dir = temp_dir("sigint");
    let out = dir.join("x.exr");
    let child = Command::new(env!("CARGO_BIN_EXE_smlt"))
        .args(["render", "--device", "cpu", "--width", "32", "--height", "32", "--time", "60"])
        .args(["--checkpoint", "0.5", "--out", out.to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Interrupt once the first checkpoint is on disk (the render is under way), at most 60 s.
    let waited = std::time::Instant::now();
    while !out.exists() && waited.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    assert!(out.exists(), "no checkpoint within 60 s");
    let status = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(status.success());
    let output = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(stderr.contains("interrupted"), "{stderr}");
    assert!(stdout.contains("checkpoints"), "{stdout}");
    let (w, h, rgb) = smlt::output::read_exr(&out).unwrap();
    assert_eq!((w, h), (32, 32));
    assert!(rgb.iter().any(|v| *v > 0.0));
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `smlt reference` caches its image with its settings: the same settings reuse it, other
/// settings render anew.
#[test]
fn the_reference_is_cached_with_its_settings() {
    let dir = temp_dir("reference");
    let out = dir.join("ref.exr");
    let out_s = out.to_str().unwrap();
    let args =
        ["reference", "--device", "cpu", "--width", "8", "--height", "8", "--spp", "4", "--out", out_s];
    let (ok, stdout, stderr) = smlt(&args);
    assert!(ok && stdout.contains("wrote"), "{stderr}");
    let (ok, stdout, _) = smlt(&args);
    assert!(ok && stdout.contains("cached"), "{stdout}");
    let (ok, stdout, _) = smlt(&[
        "reference",
        "--device",
        "cpu",
        "--width",
        "8",
        "--height",
        "8",
        "--spp",
        "8",
        "--out",
        out_s,
    ]);
    assert!(ok && !stdout.contains("cached") && stdout.contains("wrote"), "{stdout}");
    let (w, h, _) = smlt::output::read_exr(&out).unwrap();
    assert_eq!((w, h), (8, 8));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `smlt bench --reference` with a reference `smlt reference` wrote: the bench reports the
/// reference's own noise from its sidecar, and refuses one of another depth, view or scene, a
/// damaged sidecar or a missing file, with one line naming it (it would measure every error
/// against the wrong image).
#[test]
fn the_bench_reads_and_checks_a_references_sidecar() {
    let dir = temp_dir("bench_reference");
    let reference = dir.join("ref.exr");
    let size = ["--width", "8", "--height", "8"];
    let (ok, _, stderr) = smlt(
        &[
            &["reference", "atrium", "--spp", "16", "--max-depth", "3", "--device", "cpu"][..],
            &size,
            &["--out", reference.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(ok, "{stderr}");
    let bench = |scene: &str, depth: &str| {
        let out = dir.join(format!("bench_{scene}_{depth}"));
        let args = [
            &["bench", "--scenes", scene, "--methods", "pt", "--seconds", "0.2", "--max-depth", depth][..],
            &size,
            &["--device", "cpu", "--reference", reference.to_str().unwrap(), "--out", out.to_str().unwrap()],
        ]
        .concat();
        let (ok, _, stderr) = smlt(&args);
        (ok, stderr, out)
    };
    let (ok, stderr, out) = bench("atrium", "3");
    assert!(ok, "{stderr}");
    let noise = smlt::reference::read_sidecar(&reference).unwrap().unwrap().noise_rmse.unwrap();
    let tables = std::fs::read_to_string(out.join("tables.md")).unwrap();
    assert!(
        tables.contains(&format!("| atrium v1 | {} |", smlt_bench::tables::significant(noise))),
        "the reference's noise, {noise}: {tables}"
    );
    for (scene, depth, said) in [
        ("atrium", "4", "is a reference of max depth 3, the bench renders 4"),
        ("atrium:2", "3", "the bench renders view 2"),
        ("cornell", "3", "is a reference of another scene"),
    ] {
        let (ok, stderr, _) = bench(scene, depth);
        assert!(!ok && stderr.contains(said), "{scene} depth {depth}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    }
    std::fs::write(smlt::reference::sidecar(&reference), "{ not json").unwrap();
    let (ok, stderr, _) = bench("atrium", "3");
    assert!(!ok && stderr.contains("ref.exr.json"), "{stderr}");
    // A reference that is not there is one it cannot read (it said "cannot write").
    let missing = dir.join("missing.exr");
    let (ok, _, stderr) = smlt(
        &[
            &["bench", "--scenes", "atrium", "--methods", "pt", "--seconds", "0.2", "--device", "cpu"][..],
            &size,
            &["--reference", missing.to_str().unwrap(), "--out", dir.join("bench_missing").to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(!ok && stderr.contains(&format!("cannot read {}", missing.display())), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `smlt bench` runs end to end on a tiny configuration and writes a well-formed CSV (every
/// row parses, one per method and measurement time), the tables and the heat maps.
#[test]
fn the_bench_writes_a_well_formed_csv() {
    let device =
        if common::gpu_or_skip("the_bench_writes_a_well_formed_csv").is_some() { "gpu" } else { "cpu" };
    let dir = temp_dir("bench");
    let (ok, _, stderr) = smlt(&[
        "bench",
        "--scenes",
        "cornell,atrium:2",
        "--methods",
        "pt,naive,s2,rc2",
        "--seconds",
        "1.5",
        "--width",
        "16",
        "--height",
        "12",
        "--reference-spp",
        "16",
        "--candidates",
        "1000",
        "--repeats",
        "2",
        "--device",
        device,
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let csv = std::fs::read_to_string(dir.join("results.csv")).unwrap();
    let mut lines = csv.lines();
    let header = lines.next().unwrap();
    assert_eq!(header, smlt_bench::results::CSV_HEADER);
    assert!(header.starts_with(
        "scene,view,method,repeat,seconds,candidates,steps,mutations_per_s,steps_per_s,rmse,relmse,psnr"
    ));
    let rows: Vec<Vec<String>> = lines.map(|l| l.split(',').map(String::from).collect()).collect();
    // 2 scene views × 4 methods × 2 repeats × 2 times (1 s and 1.5 s).
    assert_eq!(rows.len(), 32, "{csv}");
    assert_eq!(rows.iter().filter(|r| r[3] == "1").count(), 16, "half the rows are the second repeat");
    for r in &rows {
        assert_eq!(r.len(), header.split(',').count(), "{r:?} against {header}");
        assert!(["pt", "naive", "s2", "rc2"].contains(&r[2].as_str()));
        if r[2] == "pt" {
            // The path tracer's b is exactly 1, and every path is a step.
            assert_eq!(r[5], r[6], "{r:?}");
            assert_eq!(r[13].parse::<f64>().unwrap(), 1.0, "{r:?}");
        }
        for field in &r[3..] {
            let v: f64 = field.parse().unwrap_or_else(|_| panic!("{field} in {r:?}"));
            assert!(v.is_finite() && v >= 0.0, "{r:?}");
        }
    }
    let tables = std::fs::read_to_string(dir.join("tables.md")).unwrap();
    assert!(tables.contains("Million mutations") && tables.contains("PSNR") && tables.contains("| rc2 |"));
    assert!(tables.contains("| pt |"), "{tables}");
    assert!(tables.contains("relMSE") && tables.contains(" ± "), "means with intervals: {tables}");
    assert!(dir.join("heat_cornell_v1_naive.png").exists());
    {
        // Inside an iteration, on the device as on the CPU backend: a profile per scene view and
        // method, every number positive, the CPU backend's threads counted; the path tracer's
        // has its ray ceiling and no passes (NaN).
        let passes = std::fs::read_to_string(dir.join("passes.csv")).unwrap();
        let mut lines = passes.lines();
        let header = lines.next().unwrap();
        assert_eq!(header, smlt_bench::profile::csv_header());
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
        assert_eq!(rows.len(), 8, "{passes}");
        let stages = smlt::passes::Stage::COUNT;
        for r in &rows {
            assert_eq!(r.len(), header.split(',').count(), "{r:?}");
            assert!(r[4] == "timestamp" || r[4] == "wall");
            let pt = r[2] == "pt";
            for (i, field) in r[5..].iter().chain(&r[3..4]).enumerate() {
                let v: f64 = field.parse().unwrap_or_else(|_| panic!("{field} in {r:?}"));
                assert!(if pt && i < stages { v.is_nan() } else { v.is_finite() && v >= 0.0 }, "{r:?}");
            }
            let rays_per_candidate: f64 = r[10].parse().unwrap();
            // Most techniques trace a camera ray, and most connections cast a shadow ray.
            assert!(rays_per_candidate > 0.5, "{r:?}");
            let threads: usize = r.last().unwrap().parse().unwrap();
            assert_eq!(threads > 0, device == "cpu", "{r:?}");
            assert!(device == "gpu" || r[4] == "wall", "{r:?}");
        }
        assert_eq!(rows.iter().filter(|r| r[2] == "pt").count(), 2, "{passes}");
        assert!(tables.contains("Inside an iteration: atrium v2") && tables.contains("bare M rays/s"));
    }
    for plot in ["speedup.png", "error_cornell_v1.png", "error_atrium_v2.png"] {
        let img = image::open(dir.join(plot)).unwrap_or_else(|e| panic!("{plot}: {e}"));
        assert!(img.width() >= 800 && img.height() >= 500);
    }
    // The plots and tables can be redrawn from the CSV alone, also with a peer's rows added.
    let again = dir.join("again");
    let mut with_peer = csv.clone();
    with_peer.push_str("cornell,1,mitsuba-path,0,1.000,1000,1000,1000.0,1000.0,1e-1,1e-1,20.000,0,nan,nan\n");
    std::fs::write(dir.join("with_peer.csv"), with_peer).unwrap();
    let (ok, stdout, stderr) =
        smlt(&["plot", dir.join("with_peer.csv").to_str().unwrap(), "--out", again.to_str().unwrap()]);
    assert!(ok && stdout.contains("33 rows"), "{stderr}");
    assert!(again.join("speedup.png").exists());
    let tables = std::fs::read_to_string(again.join("tables.md")).unwrap();
    assert!(tables.contains("| mitsuba-path |") && tables.contains("Efficiency"), "{tables}");
    assert!(dir.join("reference_atrium_v2.exr.json").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Output into a closed pipe (`smlt … | head -0`) ends the process quietly, as other
/// command-line tools do (success, or the SIGPIPE status 141), never in a panic (101).
#[test]
fn a_closed_stdout_pipe_is_not_a_panic() {
    let smlt = env!("CARGO_BIN_EXE_smlt");
    let output = Command::new("bash")
        .arg("-c")
        .arg(format!(
            "{smlt} scene --help | head -c 0; a=${{PIPESTATUS[0]}}; {smlt} --help | head -c 1 >/dev/null; echo \"$a ${{PIPESTATUS[0]}}\""
        ))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let statuses: Vec<&str> = stdout.split_whitespace().collect();
    assert_eq!(statuses.len(), 2, "{stdout}");
    for s in statuses {
        assert!(s == "0" || s == "141", "smlt exited with {s} into a closed pipe: {stderr}");
    }
}

/// Without --height, the image has the glTF camera's aspect ratio (when it states one); the
/// PNG is exposed automatically and the exposure is reported, or set with --exposure.
#[test]
fn the_height_follows_the_camera_and_the_png_is_exposed() {
    let dir = temp_dir("aspect");
    let wide = include_str!("../scenes/cornell.gltf")
        .replace("\"perspective\": {", "\"perspective\": {\"aspectRatio\": 2.0,");
    let scene = dir.join("wide.gltf");
    std::fs::write(&scene, wide).unwrap();
    let out = dir.join("x.exr");
    let base =
        ["render", scene.to_str().unwrap(), "--device", "cpu", "--width", "40", "--mutations-per-pixel", "4"];
    let (ok, stdout, stderr) = smlt(&[&base[..], &["--out", out.to_str().unwrap()]].concat());
    assert!(ok && stdout.contains("at 40×20") && stdout.contains("EV, automatic"), "{stdout}{stderr}");
    let (w, h, _) = smlt::output::read_exr(&out).unwrap();
    assert_eq!((w, h), (40, 20));
    let auto = image::open(dir.join("x.png")).unwrap().to_rgb8();
    let (ok, stdout, _) = smlt(&[&base[..], &["--exposure", "-3", "--out", out.to_str().unwrap()]].concat());
    assert!(ok && stdout.contains("-3.00 EV"), "{stdout}");
    let dark = image::open(dir.join("x.png")).unwrap().to_rgb8();
    let mean =
        |img: &image::RgbImage| img.pixels().map(|p| p.0.iter().map(|&v| v as f64).sum::<f64>()).sum::<f64>();
    assert!(mean(&dark) < mean(&auto), "-3 EV is darker than the automatic exposure");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--device auto` (the default) takes a GPU when the machine has one, and otherwise the CPU
/// backend on every core, and the first line of the render says which and why; with no Vulkan
/// driver at all it still renders, on the CPU.
#[test]
fn the_default_device_is_the_fastest_one() {
    let dir = temp_dir("auto");
    let out = dir.join("x.exr");
    let out_s = out.to_str().unwrap();
    let args =
        ["render", "--width", "8", "--height", "8", "--mutations-per-pixel", "4", "--bootstrap", "1024"];
    let has_gpu = smlt::gpu::adapters().iter().any(|a| smlt::gpu::is_real_gpu(&a.get_info()));
    let (ok, stdout, stderr) = smlt(&[&args[..], &["--out", out_s]].concat());
    assert!(ok, "{stderr}");
    let first = stdout.lines().next().unwrap_or_default();
    assert!(first.starts_with("device: ") && first.contains("--device auto"), "{first}");
    assert_eq!(first.starts_with("device: CPU"), !has_gpu, "{first}");
    let missing = dir.join("no-such-icd.json");
    let output = Command::new(env!("CARGO_BIN_EXE_smlt"))
        .args(args)
        .args(["--out", out_s])
        .env("VK_DRIVER_FILES", &missing)
        .env("VK_ICD_FILENAMES", &missing)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.starts_with("device: CPU") && stdout.contains("no Vulkan adapter"), "{stdout}");
    let (ok, stdout, _) = smlt(&["devices"]);
    assert!(ok && stdout.contains("--device auto chooses"), "{stdout}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A small render of the default scene on the CPU that shard tests split (its method aside).
const SHARDED_RENDER: [&str; 13] = [
    "render",
    "--device",
    "cpu",
    "--width",
    "10",
    "--height",
    "6",
    "--mutations-per-pixel",
    "16",
    "--bootstrap",
    "4096",
    "--candidates",
    "600",
];

/// `render --shard K/N` writes part files that `smlt merge` combines into the image the same
/// render without --shard writes; a merge with a shard missing or twice, or of parts of
/// different renders, is one line naming the problem and writes nothing.
#[test]
fn shards_merge_into_the_unsplit_image() {
    let dir = temp_dir("shards");
    let base = [&SHARDED_RENDER[..], &["--method", "s2"]].concat();
    let path = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let (ok, _, stderr) = smlt(&[&base[..], &["--out", &path("whole.exr")]].concat());
    assert!(ok, "{stderr}");
    for k in 1..=3 {
        let shard = format!("{k}/3");
        let (ok, stdout, stderr) =
            smlt(&[&base[..], &["--shard", &shard, "--out", &path(&format!("part{k}.exr"))]].concat());
        assert!(ok && stdout.contains(&format!("part {k}/3")), "{stderr}");
    }
    let (ok, stdout, stderr) = smlt(&[
        "merge",
        &path("part3.exr"),
        &path("part1.exr"),
        &path("part2.exr"),
        "--out",
        &path("merged.exr"),
    ]);
    assert!(ok && stdout.contains("merged"), "{stderr}");
    let (_, _, whole) = smlt::output::read_exr(&dir.join("whole.exr")).unwrap();
    let (w, h, merged) = smlt::output::read_exr(&dir.join("merged.exr")).unwrap();
    assert_eq!((w, h), (10, 6));
    for (a, b) in whole.iter().zip(&merged) {
        assert!((a - b).abs() <= 1e-6 * a.abs().max(1e-3), "{a} vs {b}");
    }
    let bad = path("bad.exr");
    let (ok, _, _) =
        smlt(&[&base[..], &["--seed", "9", "--shard", "3/3", "--out", &path("seed9.exr")]].concat());
    assert!(ok);
    for (parts, needle) in [
        (vec![path("part1.exr"), path("part2.exr")], "shard 3/3 is missing"),
        (vec![path("part1.exr"), path("part2.exr"), path("part2.exr"), path("part3.exr")], "given twice"),
        (vec![path("part1.exr"), path("part2.exr"), path("seed9.exr")], "seed 1 vs 9"),
        (vec![path("part1.exr"), path("part2.exr"), path("whole.exr")], "not an smlt part file"),
        (vec![path("part1.exr"), path("nothing.exr")], "nothing.exr"),
    ] {
        let mut args = vec!["merge".to_string()];
        args.extend(parts);
        args.extend(["--out".to_string(), bad.clone()]);
        let refs: Vec<&str> = args.iter().map(|s| s.as_str()).collect();
        let (ok, _, stderr) = smlt(&refs);
        assert!(!ok && stderr.contains(needle), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(!Path::new(&bad).exists(), "{args:?} wrote {bad}");
    }
    let (ok, _, stderr) = smlt(&[&base[..], &["--shard", "4/3", "--out", &bad]].concat());
    assert!(!ok && stderr.contains("4/3"), "{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--method auto` on shards: each shard's pilot chooses for itself and its part records that
/// auto chose. Parts that chose alike merge into the unsplit render of the chosen method; parts
/// whose methods differ (a pilot is timed, so shards on different machines may choose
/// differently) are refused in one line that names both methods and the way out, and a shard
/// rendered again with the others' method then merges.
#[test]
fn sharded_auto_renders_merge_or_say_what_to_render_again() {
    let dir = temp_dir("auto-shards");
    let path = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let base = SHARDED_RENDER;
    let render = |extra: &[&str]| -> String {
        let (ok, stdout, stderr) = smlt(&[&base[..], extra].concat());
        assert!(ok, "{extra:?}: {stdout}{stderr}");
        stdout
    };
    let chosen = |stdout: &str| -> String {
        let line = stdout.lines().find(|l| l.starts_with("auto: chose ")).expect("auto's line");
        line.split_whitespace().nth(2).unwrap().to_string()
    };
    let merge = || smlt(&["merge", &path("part1.exr"), &path("part2.exr"), "--out", &path("merged.exr")]);
    let first = chosen(&render(&["--shard", "1/2", "--out", &path("part1.exr")]));
    let second = chosen(&render(&["--shard", "2/2", "--out", &path("part2.exr")]));
    if first == second {
        let (ok, stdout, stderr) = merge();
        assert!(ok && stdout.contains("merged"), "{stdout}{stderr}");
    }
    // Shard 2 with another method: refused, naming both and what to render again.
    let other = if first == "pt" { "naive" } else { "pt" };
    render(&["--method", other, "--shard", "2/2", "--out", &path("part2.exr")]);
    let (ok, _, stderr) = merge();
    let said = format!(
        "method {first} vs {other}, chosen by --method auto on a shard: render the shards again with \
         --method {first} or --method {other}, the same on all"
    );
    assert!(!ok && stderr.contains(&said) && stderr.lines().count() == 1, "{stderr}");
    // Shard 2 again with shard 1's choice: the parts merge into the unsplit render of it.
    render(&["--method", &first, "--shard", "2/2", "--out", &path("part2.exr")]);
    let _ = std::fs::remove_file(dir.join("merged.exr"));
    let (ok, stdout, stderr) = merge();
    assert!(ok && stdout.contains("merged"), "{stdout}{stderr}");
    render(&["--method", &first, "--out", &path("whole.exr")]);
    let (_, _, whole) = smlt::output::read_exr(&dir.join("whole.exr")).unwrap();
    let (_, _, merged) = smlt::output::read_exr(&dir.join("merged.exr")).unwrap();
    for (a, b) in whole.iter().zip(&merged) {
        assert!((a - b).abs() <= 1e-6 * a.abs().max(1e-3), "{first}: whole {a} vs merged {b}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `render --method pt` is the reference's estimator as a method: at the same seed and samples
/// it writes the image `smlt reference` writes, and its shards (which take the rounds in
/// turns) merge into the unsplit image; its summary counts paths, not chains.
#[test]
fn the_path_tracer_is_a_method_with_shards() {
    let dir = temp_dir("pt");
    let path = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let size = ["--device", "cpu", "--width", "10", "--height", "6", "--seed", "3"];
    let base =
        [&["render", "--method", "pt", "--mutations-per-pixel", "16", "--candidates", "240"], &size[..]]
            .concat();
    let (ok, stdout, stderr) = smlt(&[&base[..], &["--out", &path("whole.exr")]].concat());
    assert!(ok, "{stderr}");
    for line in ["paths traced         960", "samples per pixel    16", "iterations           4"] {
        assert!(stdout.contains(line), "{line}: {stdout}");
    }
    assert!(!stdout.contains("chains") && !stdout.contains("normalisation"), "{stdout}");
    let (ok, _, stderr) =
        smlt(&[&["reference", "--spp", "16", "--out", &path("reference.exr")], &size[..]].concat());
    assert!(ok, "{stderr}");
    let (_, _, whole) = smlt::output::read_exr(&dir.join("whole.exr")).unwrap();
    let (_, _, reference) = smlt::output::read_exr(&dir.join("reference.exr")).unwrap();
    for (a, b) in whole.iter().zip(&reference) {
        assert!((a - b).abs() <= 1e-6 * a.abs().max(1e-3), "render {a} vs reference {b}");
    }
    // Five shards of four rounds: shard 5 has none of its own, and still merges.
    let mut parts = vec!["merge".to_string()];
    for k in 1..=5 {
        let part = path(&format!("part{k}.exr"));
        let (ok, stdout, stderr) =
            smlt(&[&base[..], &["--shard", &format!("{k}/5"), "--out", &part]].concat());
        assert!(ok && stdout.contains(&format!("part {k}/5")), "{stderr}");
        parts.push(part);
    }
    parts.extend(["--out".to_string(), path("merged.exr")]);
    let refs: Vec<&str> = parts.iter().map(|s| s.as_str()).collect();
    let (ok, stdout, stderr) = smlt(&refs);
    assert!(ok && stdout.contains("paths traced         960"), "{stdout}{stderr}");
    let (_, _, merged) = smlt::output::read_exr(&dir.join("merged.exr")).unwrap();
    for (a, b) in whole.iter().zip(&merged) {
        assert!((a - b).abs() <= 1e-6 * a.abs().max(1e-3), "whole {a} vs merged {b}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A scene too large for a device's storage buffers (3.07 M triangles: 141 MiB of triangles
/// against lavapipe's 128 MiB) is refused with one line naming the buffer, its size, the limit
/// and the way out, and nothing is written; the CPU backend, which has no such limit, is named.
#[test]
fn a_scene_beyond_the_device_is_refused_by_name() {
    let Some(gpu) = common::gpu_or_skip("a_scene_beyond_the_device_is_refused_by_name") else {
        return;
    };
    let limit = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
    // 120 n² triangles of 48 bytes each: the smallest tessellation past the limit.
    let n = ((limit as f64 / 48.0 / 120.0).sqrt() as u32 + 1).max(1);
    if n > 256 {
        eprintln!("SKIPPED: this device's buffers hold more than the largest generated scene");
        return;
    }
    let dir = temp_dir("too-large");
    let scene = dir.join("big.gltf");
    let (ok, _, stderr) =
        smlt(&["scene", "atrium", "--tessellation", &n.to_string(), "--out", scene.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    let out = dir.join("big.exr");
    let (ok, stdout, stderr) = smlt(&[
        "render",
        scene.to_str().unwrap(),
        "--device",
        "vulkan",
        "--mutations-per-pixel",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok, "{stdout}");
    let lines: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(lines.len(), 1, "{stderr}");
    assert!(
        lines[0].contains("the triangles buffer needs")
            && lines[0].contains("MiB per storage buffer")
            && lines[0].contains("--device cpu"),
        "{stderr}"
    );
    assert!(!out.exists() && !dir.join("big.png").exists(), "nothing is written");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Malformed scenes, each changed in one place from the default scene (and the measured
/// Cornell box for its index accessor), are refused with exit 1 and one line naming the glTF
/// path of the element, before anything is written.
#[test]
fn malformed_scenes_are_refused_by_name() {
    let base: serde_json::Value = serde_json::from_str(include_str!("../scenes/cornell.gltf")).unwrap();
    let mut cases: Vec<(serde_json::Value, &str)> = Vec::new();
    let mut edit = |pointer: &str, value: serde_json::Value, expected: &'static str| {
        let mut doc = base.clone();
        *doc.pointer_mut(pointer).unwrap() = value;
        cases.push((doc, expected));
    };
    edit("/bufferViews/4/byteLength", serde_json::json!(5000), "bufferViews[4]: byteOffset");
    edit("/accessors/0/count", serde_json::json!(55), "accessors[0]: 55 elements");
    edit("/cameras/0/perspective/yfov", serde_json::json!(-1.0), "cameras[0].perspective.yfov: -1 rad");
    edit("/cameras/0/perspective/yfov", serde_json::json!(0.0), "cameras[0].perspective.yfov: 0 rad");
    edit(
        "/nodes/5/rotation",
        serde_json::json!([0.0, 0.0, 0.0, 2.0]),
        "nodes[5].rotation: the quaternion has length 2",
    );
    edit(
        "/materials/0/pbrMetallicRoughness/baseColorFactor",
        serde_json::json!([2.0, 0.5, 0.5, 1.0]),
        "materials[0].pbrMetallicRoughness.baseColorFactor: 2 is outside [0, 1]",
    );
    edit(
        "/materials/3/extensions/KHR_materials_emissive_strength/emissiveStrength",
        serde_json::json!(-1.0),
        "emissiveStrength: -1 is not a finite number ≥ 0",
    );
    let dir = temp_dir("malformed");
    let out = dir.join("out.exr");
    let check = |scene: &Path, expected: &str| {
        let (ok, _, stderr) =
            smlt(&["render", scene.to_str().unwrap(), "--device", "cpu", "--out", out.to_str().unwrap()]);
        assert!(!ok, "{expected}: rendered");
        let lines: Vec<&str> = stderr.lines().collect();
        assert_eq!(lines.len(), 1, "{expected}: {stderr}");
        assert!(
            lines[0].starts_with("error: malformed glTF") && lines[0].contains(expected),
            "{expected}: {stderr}"
        );
        assert!(!out.exists() && !dir.join("out.png").exists(), "{expected}: nothing is written");
    };
    for (i, (doc, expected)) in cases.iter().enumerate() {
        let scene = dir.join(format!("case{i}.gltf"));
        std::fs::write(&scene, serde_json::to_vec(doc).unwrap()).unwrap();
        check(&scene, expected);
    }
    // A field of view of π or more is valid glTF, but no pinhole's: refused as unsupported.
    let mut wide = base.clone();
    *wide.pointer_mut("/cameras/0/perspective/yfov").unwrap() = serde_json::json!(3.2);
    let scene = dir.join("wide.gltf");
    std::fs::write(&scene, serde_json::to_vec(&wide).unwrap()).unwrap();
    let (ok, _, stderr) =
        smlt(&["render", scene.to_str().unwrap(), "--device", "cpu", "--out", out.to_str().unwrap()]);
    assert!(!ok && stderr.lines().count() == 1, "{stderr}");
    assert!(
        stderr.starts_with("error: unsupported glTF content")
            && stderr.contains("cameras[0].perspective.yfov: 3.2 rad"),
        "{stderr}"
    );
    // An index accessor whose count runs past its buffer view and is not a multiple of 3.
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes/cornell_box");
    if shared.exists() {
        let mut doc: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(shared.join("cornell_box.gltf")).unwrap()).unwrap();
        let indices = doc["meshes"][0]["primitives"][0]["indices"].as_u64().unwrap() as usize;
        let count = doc["accessors"][indices]["count"].as_u64().unwrap();
        doc["accessors"][indices]["count"] = serde_json::json!(count + 1);
        std::fs::copy(shared.join("cornell_box.bin"), dir.join("cornell_box.bin")).unwrap();
        let scene = dir.join("indices.gltf");
        std::fs::write(&scene, serde_json::to_vec(&doc).unwrap()).unwrap();
        check(&scene, &format!("accessors[{indices}]"));
        // One index short of whole triangles: valid glTF (the validator warns); the incomplete
        // triangle is dropped with a warning, and the rest renders.
        doc["accessors"][indices]["count"] = serde_json::json!(count - 1);
        std::fs::write(&scene, serde_json::to_vec(&doc).unwrap()).unwrap();
        let (ok, _, stderr) = smlt(&[
            "render",
            scene.to_str().unwrap(),
            "--device",
            "cpu",
            "--width",
            "16",
            "--mutations-per-pixel",
            "1",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{stderr}");
        assert!(stderr.contains("are no multiple of 3: the last 2 form no triangle"), "{stderr}");
    } else {
        assert_ne!(std::env::var("CI").as_deref(), Ok("true"), "CI=true and no {}", shared.display());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--environment` lights a scene that has no light of its own: an image (here an EXR sky
/// written by the test, turned by --environment-rotation) or a constant colour; the summary
/// says what lit it.
#[test]
fn an_environment_lights_a_scene_without_lights() {
    let dir = temp_dir("environment");
    let scene = dir.join("plate.gltf");
    let mut b = smlt::scenes::GltfBuilder::new();
    let grey = b.material("grey", [0.5; 3], [0.0; 3], 1.0, None);
    let v = glam::Vec3::new;
    b.quad(grey, [v(-1., 0., 1.), v(1., 0., 1.), v(1., 0., -1.), v(-1., 0., -1.)]);
    b.camera(v(0.0, 1.5, 2.0), v(0.0, 0.0, 0.0), glam::Vec3::Y, 50f32.to_radians());
    std::fs::write(&scene, b.to_json()).unwrap();
    let scene_s = scene.to_str().unwrap();
    let (ok, _, stderr) =
        smlt(&["render", scene_s, "--device", "cpu", "--out", dir.join("a.exr").to_str().unwrap()]);
    assert!(!ok && stderr.contains("--environment"), "a scene without lights is refused: {stderr}");
    let sky = dir.join("sky.exr");
    exr::prelude::write_rgb_file(&sky, 16, 8, |_, y| if y < 4 { (0.4, 0.6, 1.0) } else { (0.1, 0.1, 0.1) })
        .unwrap();
    for env in [sky.to_str().unwrap(), "0.5,0.6,0.8"] {
        let out = dir.join("lit.exr");
        let (ok, stdout, stderr) = smlt(&[
            "render",
            scene_s,
            "--device",
            "cpu",
            "--width",
            "16",
            "--height",
            "12",
            "--mutations-per-pixel",
            "16",
            "--environment",
            env,
            "--environment-strength",
            "2",
            "--environment-rotation",
            "-30",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{env}: {stderr}");
        assert!(stdout.contains("lit by environment") && stdout.contains(env), "{stdout}");
        let (_, _, rgb) = smlt::output::read_exr(&out).unwrap();
        assert!(rgb.iter().all(|v| v.is_finite()) && rgb.iter().sum::<f32>() > 0.0, "{env}: lit");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--method auto` (the default) on the lamps' caustic through glass (`scenes/caustic.gltf`),
/// which the path tracer does not render (a spot through glass): its pilot sees the path tracer
/// missing light against the multiplexed chains and does not choose it. On the Cornell box,
/// where nothing is missing, it flags no candidate. The budget is one in which the missing
/// caustic outweighs the path tracer's noise and the pilot's naive image holds it beyond its
/// own noise: at 512 mutations per pixel the light missing read 0.7–7 × 10⁻³ over four pilots
/// and one chose `pt`; at 2048, 1.6–11 × 10⁻³ against `pt`'s variance of 1.0–1.4 × 10⁻³ over
/// six, none (`cargo run --release --example pilot -- scenes/caustic.gltf 1 REF 6 200`).
#[test]
fn auto_sees_the_light_the_path_tracer_misses() {
    let dir = temp_dir("auto-caustic");
    let out = dir.join("a.exr");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/caustic.gltf");
    let size = ["--width", "64", "--height", "64", "--mutations-per-pixel", "2048", "--device", "cpu"];
    let (ok, stdout, stderr) =
        smlt(&[&["render", scene][..], &size, &["--out", out.to_str().unwrap()]].concat());
    assert!(ok, "{stderr}");
    let line = stdout.lines().find(|l| l.starts_with("auto: chose ")).expect("auto's line");
    assert!(
        line.contains(" pt ")
            && line.split(" pt ").nth(1).unwrap().split(',').nth(1) == Some(" missing light"),
        "{line}"
    );
    assert!(!line.starts_with("auto: chose pt "), "{line}");
    let size = ["--width", "64", "--height", "64", "--mutations-per-pixel", "512", "--device", "cpu"];
    let (ok, stdout, stderr) =
        smlt(&[&["render", "cornell"][..], &size, &["--out", out.to_str().unwrap()]].concat());
    assert!(ok, "{stderr}");
    assert!(stdout.contains("auto: chose") && !stdout.contains("missing light"), "{stdout}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A render on the CPU backend repeated with the same seed and budget writes the same files, byte
/// for byte: the EXR's tiles in a fixed order (`smlt::output::EXR_ENCODING`), where the exr
/// crate's default order (its threads' finishing order) made equal images unequal files. A
/// 256 × 192 image is 12 tiles, so an unordered writer would almost surely show.
#[test]
fn the_same_seed_and_budget_write_the_same_file() {
    let dir = temp_dir("same-file");
    for method in ["pt", "naive"] {
        let mut files = Vec::new();
        for run in 1..=2 {
            let out = dir.join(format!("{method}{run}.exr"));
            let (ok, _, stderr) = smlt(&[
                "render",
                "--device",
                "cpu",
                "--method",
                method,
                "--mutations-per-pixel",
                "2",
                "--seed",
                "3",
                "--width",
                "256",
                "--height",
                "192",
                "--out",
                out.to_str().unwrap(),
            ]);
            assert!(ok, "{stderr}");
            files.push((std::fs::read(&out).unwrap(), std::fs::read(out.with_extension("png")).unwrap()));
        }
        assert!(files[0].0 == files[1].0, "{method}: the two EXR files differ");
        assert!(files[0].1 == files[1].1, "{method}: the two PNG files differ");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Above 512×512 pixels the pixel importance is estimated per block of pixels, so that it takes
/// at most 2^20 samples before the clock (`smlt::render::importance::block_side`); the summary
/// names the blocks, and the render is whole.
#[test]
fn a_large_image_estimates_its_pixel_importance_in_blocks() {
    let dir = temp_dir("importance-blocks");
    let out = dir.join("large.exr");
    let (ok, stdout, stderr) = smlt(&[
        "render",
        "--device",
        "cpu",
        "--method",
        "naive",
        "--mutations-per-pixel",
        "1",
        "--width",
        "600",
        "--height",
        "520",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("pixel importance     4 samples a 2×2 block of pixels in"), "{stdout}");
    let (w, h, rgb) = smlt::output::read_exr(&out).unwrap();
    assert_eq!((w, h), (600, 520));
    assert!(rgb.iter().all(|v| v.is_finite()) && rgb.iter().any(|&v| v > 0.0));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--method auto` keeps its pilot where the pilot rendered the render's pixels (a whole render
/// at most 128 pixels wide): the summary says how many of the chosen method's paths or
/// candidates it kept, and the image is the pool of the pilot's and the render's, each weighed
/// by its candidates. With a `--mutations-per-pixel` budget the render is `--method <chosen>`'s
/// with the same seed, so the pilot's image can be taken back out of the pool: it is an
/// estimate of the same image (its mean within a tenth of the render's). A wider render's pilot
/// is smaller than its image and is not kept.
#[test]
fn auto_keeps_its_pilot_where_it_rendered_the_renders_pixels() {
    let dir = temp_dir("auto-kept");
    let path = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let base =
        ["render", "--device", "cpu", "--width", "32", "--height", "24", "--mutations-per-pixel", "64"];
    let (ok, stdout, stderr) = smlt(&[&base[..], &["--out", &path("auto.exr")]].concat());
    assert!(ok, "{stderr}");
    let value = |key: &str| -> f64 {
        let line =
            stdout.lines().find_map(|l| l.strip_prefix(key)).unwrap_or_else(|| panic!("{key}: {stdout}"));
        line.split_whitespace().next().unwrap().parse().unwrap()
    };
    let chosen =
        stdout.lines().find_map(|l| l.strip_prefix("method ")).unwrap().split_whitespace().next().unwrap();
    let kept = value("pilot kept ");
    let rendered = if chosen == "pt" { value("paths traced ") } else { value("candidates traced ") };
    let (ok, _, stderr) = smlt(&[&base[..], &["--method", chosen, "--out", &path("named.exr")]].concat());
    assert!(ok, "{stderr}");
    let (_, _, pool) = smlt::output::read_exr(&dir.join("auto.exr")).unwrap();
    let (_, _, render) = smlt::output::read_exr(&dir.join("named.exr")).unwrap();
    assert_ne!(pool, render, "the pilot was pooled in");
    let pilot: Vec<f64> = pool
        .iter()
        .zip(&render)
        .map(|(p, r)| ((kept + rendered) * *p as f64 - rendered * *r as f64) / kept)
        .collect();
    let mean = |v: &mut dyn Iterator<Item = f64>| {
        let (sum, n) = v.fold((0.0, 0.0), |(s, n), x| (s + x, n + 1.0));
        sum / n
    };
    let (pilot_mean, render_mean) =
        (mean(&mut pilot.iter().copied()), mean(&mut render.iter().map(|&v| v as f64)));
    assert!(pilot.iter().all(|v| v.is_finite() && *v > -1e-3), "{chosen}: the pilot's image is an image");
    assert!(
        (pilot_mean / render_mean - 1.0).abs() < 0.1,
        "{chosen}: pilot {pilot_mean} vs render {render_mean}"
    );
    let wide = ["render", "--device", "cpu", "--width", "160", "--height", "8", "--mutations-per-pixel", "8"];
    let (ok, stdout, stderr) = smlt(&[&wide[..], &["--out", &path("wide.exr")]].concat());
    assert!(ok && stdout.contains("chosen by auto") && !stdout.contains("pilot kept"), "{stdout}{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}
