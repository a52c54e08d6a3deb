//! Chains as shards: a render's image does not depend on how its chains are split — over CPU
//! threads (bit for bit), or into shards merged from part files (up to f64 rounding) — and
//! merges of parts that do not belong together are refused. And the normalisation b: every
//! method's large steps refine it, it converges to the furnace's analytic value within its
//! own error, and its error falls as 1/√samples.

mod common;

use common::scenes::{furnace, furnace_radiance};
use smlt::part::{merge, read_part, write_part, Identity, PartError};
use smlt::render::{
    self, cpu::CpuBackend, gpu::GpuBackend, Budget, ChainSettings, Integrator, Rendered, Schedule, Settings,
    Shard,
};
use smlt::scene::SceneData;

fn cornell() -> SceneData {
    SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell").expect("cornell")
}

fn settings(method: &str, shard: Shard) -> Settings {
    let chains = ChainSettings { bootstrap_samples: 8192, ..Default::default() };
    Settings {
        width: 20,
        height: 12,
        max_depth: 4,
        seed: 5,
        integrator: Integrator::new(method.parse().unwrap(), chains),
        budget: Budget::MutationsPerPixel(24.0),
        candidates: 1536,
        shard,
    }
}

/// The chains' settings of `s`, to change.
fn chains(s: &mut Settings) -> &mut ChainSettings {
    &mut s.metropolis_mut().expect("Metropolis chains").chains
}

fn render_cpu(scene: &SceneData, s: &Settings, threads: usize) -> Rendered {
    let params = render::base_params(scene, s);
    let mut backend = CpuBackend::new(scene, &params, threads).expect("threads");
    render::render(scene, s, &mut backend, |_| {}).expect("render")
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("smlt-shards-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The same image, bit for bit, with 1, 2 and 3 threads: the chains are cut into fixed
/// groups and summed in a fixed order, whatever the number of threads.
#[test]
fn the_image_is_the_same_for_every_thread_count() {
    let scene = cornell();
    for method in ["naive", "s3", "rc8", "path-s2"] {
        let s = settings(method, Shard::WHOLE);
        let one = render_cpu(&scene, &s, 1);
        for threads in [2, 3] {
            let r = render_cpu(&scene, &s, threads);
            assert_eq!(bits(&one.rgb), bits(&r.rgb), "{method}, {threads} threads");
            assert_eq!(one.accumulation, r.accumulation, "{method}, {threads} threads");
        }
        assert!(one.rgb.iter().any(|v| *v > 0.0));
    }
}

/// Writes the parts `shards` of `count` of the render `s` to `dir` and reads them back.
fn parts(
    scene: &SceneData,
    s: &Settings,
    count: u32,
    render_part: impl Fn(&Settings) -> Rendered,
) -> Vec<smlt::part::Part> {
    let dir = temp_dir(&format!("{}-{count}-{}", s.method(), s.seed));
    let parts = (1..=count)
        .map(|index| {
            let mut p = s.clone();
            p.shard = Shard { index, count };
            let r = render_part(&p);
            let path = dir.join(format!("part{index}.exr"));
            write_part(&path, &Identity::new(&scene.name, "hash", 1, &p), p.shard, &r, "test").unwrap();
            read_part(&path).unwrap()
        })
        .collect();
    std::fs::remove_dir_all(&dir).unwrap();
    parts
}

/// The merged image against the unsplit one: the same up to f64 rounding (the f32 images
/// agree to a few ulps), and the same accumulation up to rounding.
fn assert_same_render(whole: &Rendered, merged: &Rendered, tolerance: f64, what: &str) {
    assert_eq!(whole.accumulation.candidates, merged.accumulation.candidates, "{what}");
    assert_eq!(whole.accumulation.invalid, merged.accumulation.invalid, "{what}");
    assert_eq!(whole.accumulation.large_steps.count, merged.accumulation.large_steps.count, "{what}");
    let rel = |a: f64, b: f64| (a - b).abs() / a.abs().max(1e-12);
    assert!(rel(whole.accumulation.weight, merged.accumulation.weight) < 1e-12, "{what}: W");
    assert!(
        rel(whole.stats.b, merged.stats.b) < tolerance,
        "{what}: b {} vs {}",
        whole.stats.b,
        merged.stats.b
    );
    let peak = whole.rgb.iter().fold(0.0f32, |m, v| m.max(*v)) as f64;
    let mut worst = 0.0f64;
    for (a, b) in whole.rgb.iter().zip(&merged.rgb) {
        worst = worst.max((*a as f64 - *b as f64).abs() / (a.abs() as f64).max(1e-3 * peak));
    }
    println!("{what}: worst relative pixel difference {worst:.2e}");
    assert!(worst < tolerance, "{what}: {worst}");
}

/// Shards 1..3 of 3, written to part files and merged, give the image of the unsplit render
/// (CPU backend; naive, s3, rc8).
#[test]
fn merged_shards_equal_the_unsplit_render() {
    let scene = cornell();
    for method in ["naive", "s3", "rc8", "path-s2"] {
        let s = settings(method, Shard::WHOLE);
        let whole = render_cpu(&scene, &s, 2);
        let parts = parts(&scene, &s, 3, |p| render_cpu(&scene, p, 2));
        assert_eq!(parts.iter().map(|p| p.iterations).collect::<Vec<_>>(), vec![whole.stats.iterations; 3]);
        let merged = merge(&parts).unwrap();
        assert_same_render(&whole, &merged, 1e-6, method);
    }
}

/// The same on the device (lavapipe in CI): the shards' chains are the unsplit render's chains.
/// The device splats with f32 atomics in no fixed order, so the images agree to f32 rounding.
#[test]
fn merged_shards_equal_the_unsplit_render_on_the_device() {
    let Some(gpu) = common::gpu_or_skip("merged_shards_equal_the_unsplit_render_on_the_device") else {
        return;
    };
    let scene = cornell();
    let on_device = |s: &Settings| {
        let params = render::base_params(&scene, s);
        let mut backend = GpuBackend::new(gpu.clone(), &scene, &params).expect("device buffers");
        render::render(&scene, s, &mut backend, |_| {}).expect("render")
    };
    let s = settings("s3", Shard::WHOLE);
    let whole = on_device(&s);
    let merged = merge(&parts(&scene, &s, 3, on_device)).unwrap();
    assert_same_render(&whole, &merged, 1e-4, "s3 on the device");
}

/// Merges that cannot be one render are refused, each naming the problem.
#[test]
fn merges_of_parts_that_do_not_belong_together_are_refused() {
    let scene = cornell();
    let s = settings("naive", Shard::WHOLE);
    let good = parts(&scene, &s, 3, |p| render_cpu(&scene, p, 2));
    let message = |parts: Vec<smlt::part::Part>| merge(&parts).unwrap_err().to_string();
    assert!(matches!(merge(&[]), Err(PartError::Empty)));
    assert!(message(good[..2].to_vec()).contains("shard 3/3 is missing"));
    assert!(message(vec![good[0].clone(), good[1].clone(), good[1].clone(), good[2].clone()])
        .contains("given twice"));
    let mut other = good.clone();
    type Change = fn(&mut Settings);
    let variants: [(&str, Change); 6] = [
        ("seed 5 vs 6", |s| s.seed = 6),
        ("method naive vs s2", |s| *s = s.clone().with_method("s2".parse().unwrap())),
        ("width 20 vs 22", |s| s.width = 22),
        ("max depth", |s| s.max_depth = 3),
        ("candidates", |s| s.candidates = 1024),
        ("pixel importance", |s| chains(s).pixel_importance = false),
    ];
    for (needle, change) in variants {
        let mut t = s.clone();
        change(&mut t);
        other[2] = parts(&scene, &t, 3, |p| render_cpu(&scene, p, 2)).remove(2);
        let m = message(other.clone());
        assert!(m.contains("different renders") && m.contains(needle), "{needle}: {m}");
    }
    // Another shard count, another scene.
    other[2] = parts(&scene, &s, 4, |p| render_cpu(&scene, p, 2)).remove(3);
    assert!(message(other.clone()).contains("shard count 3 vs 4"));
    let mut renamed = good.clone();
    renamed[1].identity.scene = "furnace".into();
    renamed[1].identity.scene_hash = "another".into();
    assert!(message(renamed).contains("scene"));
    // A file that is not a part.
    let dir = temp_dir("not-a-part");
    let plain = dir.join("plain.exr");
    smlt::output::write_images(&plain, 4, 4, &[0.5; 48]).unwrap();
    assert!(matches!(read_part(&plain), Err(PartError::NotAPart(_))));
    std::fs::write(dir.join("junk.exr"), b"not an exr").unwrap();
    assert!(matches!(read_part(&dir.join("junk.exr")), Err(PartError::Read(..))));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// b in the furnace: every method feeds the pooled estimator with its large steps (about
/// p_large per chain and iteration for trees, p_large per proposal for reject chains), and b
/// agrees with the analytic value within its own standard error; with `--p-large 0` nothing
/// feeds it and b is the bootstrap's alone. The luminance target (no pixel importance), whose
/// b is the furnace's radiance times the depths a state spans.
#[test]
fn every_method_refines_b_with_its_large_steps() {
    let (rho, k) = (0.5, 3);
    let scene = furnace(1.0, rho);
    let expected = furnace_radiance(1.0, rho, k);
    for method in ["naive", "s3", "rc8"] {
        let mut s = settings(method, Shard::WHOLE);
        s.max_depth = k;
        chains(&mut s).pixel_importance = false;
        chains(&mut s).bootstrap_samples = 4096;
        s.budget = Budget::MutationsPerPixel(256.0);
        let r = render_cpu(&scene, &s, 2);
        let m = *s.metropolis().expect("chains");
        let per_iteration = match m.schedule {
            Schedule::Tree(_) => s.chains() as f64,
            Schedule::RejectChain(l) => (s.chains() * l) as f64,
        } * m.chains.mutation.p_large as f64;
        let n = per_iteration * r.stats.iterations as f64;
        let got = r.stats.large_steps as f64;
        assert!((got - n).abs() < 5.0 * n.sqrt(), "{method}: {got} large steps, expected about {n}");
        let z = (r.stats.b - expected) / r.stats.b_standard_error;
        println!(
            "{method}: b = {:.5} ± {:.5} from {} + {} samples (analytic {expected:.5}, z = {z:+.2})",
            r.stats.b, r.stats.b_standard_error, r.stats.bootstrap_samples, r.stats.large_steps
        );
        assert!(z.abs() < 4.0, "{method}: b {} vs {expected}", r.stats.b);
        chains(&mut s).mutation.p_large = 0.0;
        let r = render_cpu(&scene, &s, 2);
        assert_eq!(r.stats.large_steps, 0);
        assert_eq!(r.stats.b, render::normalisation(s.state_depths(), &r.bootstrap, &Default::default()).b);
    }
}

/// b's standard error falls as 1/√(samples): four times the large steps, half the error.
#[test]
fn the_error_of_b_falls_as_one_over_root_samples() {
    let scene = cornell();
    let mut s = settings("naive", Shard::WHOLE);
    s.candidates = 512;
    chains(&mut s).bootstrap_samples = 512;
    chains(&mut s).mutation.p_large = 0.5;
    s.budget = Budget::MutationsPerPixel(40.0);
    let short = render_cpu(&scene, &s, 2);
    s.budget = Budget::MutationsPerPixel(160.0);
    let long = render_cpu(&scene, &s, 2);
    let n = |r: &Rendered| (r.stats.bootstrap_samples + r.stats.large_steps) as f64;
    let predicted = (n(&long) / n(&short)).sqrt();
    let measured = short.stats.b_standard_error / long.stats.b_standard_error;
    println!(
        "b: {:.5} ± {:.5} ({} samples), then {:.5} ± {:.5} ({} samples): se ratio {measured:.3}, √n ratio {predicted:.3}",
        short.stats.b,
        short.stats.b_standard_error,
        n(&short),
        long.stats.b,
        long.stats.b_standard_error,
        n(&long)
    );
    assert!(predicted > 1.8, "the long render has about 4× the samples");
    assert!((measured / predicted - 1.0).abs() < 0.15, "{measured} vs {predicted}");
}

/// A part changed after it was written is refused by name: one digit of its JSON header (its
/// iteration count), or bytes of its stored sums; parts of different smlt versions or kernel
/// modules do not merge.
#[test]
fn a_part_changed_after_it_was_written_is_refused() {
    let scene = cornell();
    let mut s = settings("naive", Shard { index: 1, count: 2 });
    s.width = 8;
    s.height = 6;
    let r = render_cpu(&scene, &s, 1);
    let dir = temp_dir("damaged");
    let path = dir.join("part.exr");
    write_part(&path, &Identity::new(&scene.name, "hash", 1, &s), s.shard, &r, "test").unwrap();
    let good = std::fs::read(&path).unwrap();
    assert!(read_part(&path).is_ok());
    // One digit of the header.
    let key = format!("\"iterations\":{}", r.stats.iterations);
    let at = good.windows(key.len()).position(|w| w == key.as_bytes()).expect("the header is in the file");
    let mut edited = good.clone();
    let digit = at + key.len() - 1;
    edited[digit] = if edited[digit] == b'9' { b'8' } else { edited[digit] + 1 };
    std::fs::write(&path, &edited).unwrap();
    let err = read_part(&path).unwrap_err().to_string();
    assert!(err.contains("damaged part file") && err.contains("checksum does not match"), "{err}");
    assert!(!err.contains('\n'));
    // Bytes of the pixel data (after the header): refused, as damaged or as unreadable.
    let data = good.len() - 64;
    let mut refused = 0;
    for offset in [0, 7, 19, 33] {
        let mut flipped = good.clone();
        flipped[data + offset] ^= 0x5a;
        std::fs::write(&path, &flipped).unwrap();
        match read_part(&path) {
            Err(PartError::Damaged(..)) | Err(PartError::Read(..)) => refused += 1,
            Err(e) => panic!("{e}"),
            Ok(p) => assert_eq!(
                p.accumulation,
                read_part_bytes(&good, &dir).accumulation,
                "a flip that changes nothing"
            ),
        }
    }
    assert!(refused >= 3, "{refused} of 4 flipped files refused");
    // Another smlt version, another kernels module.
    std::fs::write(&path, &good).unwrap();
    let one = read_part(&path).unwrap();
    for (field, change) in [("smlt version", 0), ("kernels", 1)] {
        let mut other = one.clone();
        other.shard = 2;
        if change == 0 {
            other.identity.smlt_version = "0.0.9".into();
        } else {
            other.identity.kernels = "0000000000000000".into();
        }
        let err = merge(&[one.clone(), other]).unwrap_err().to_string();
        assert!(err.contains("different renders") && err.contains(field), "{field}: {err}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The part held in `bytes`, read through a file in `dir`.
fn read_part_bytes(bytes: &[u8], dir: &std::path::Path) -> smlt::part::Part {
    let path = dir.join("copy.exr");
    std::fs::write(&path, bytes).unwrap();
    read_part(&path).unwrap()
}
