//! Convergence: the MMLT image and the path tracer's (`--method pt`) match analytic answers, on
//! the CPU and on the device, and different mutation schedules and methods converge to the
//! same image.

mod common;

use common::scenes::{furnace, furnace_radiance};
use common::stats;
use shared::mutation::MutationParams;
use smlt::render::{self, cpu::CpuBackend, gpu::GpuBackend, Backend, Budget, Method, Rendered, Settings};
use smlt::scene::SceneData;

fn settings(size: u32, max_depth: u32, mpp: f64, candidates: u32, bootstrap: u32) -> Settings {
    Settings {
        width: size,
        height: size,
        max_depth,
        seed: 7,
        method: Method::Tree(1),
        budget: Budget::MutationsPerPixel(mpp),
        candidates,
        bootstrap_samples: bootstrap,
        mutation: MutationParams::default(),
        shard: render::Shard::WHOLE,
    }
}

fn render_on(scene: &SceneData, s: &Settings, backend: &mut dyn Backend) -> Rendered {
    render::render(scene, s, backend, |_| {}).expect("render")
}

fn render_cpu(scene: &SceneData, s: &Settings) -> Rendered {
    let params = render::base_params(scene, s);
    render_on(scene, s, &mut CpuBackend::new(scene, &params, 2).expect("threads"))
}

/// Mean luminance of each of `blocks`×`blocks` image blocks.
fn block_means(r: &Rendered, blocks: u32) -> Vec<f64> {
    stats::block_means(&r.rgb, r.width, r.height, blocks)
}

/// Checks a furnace render: the image mean (= b, the bootstrap's estimate of the total) is
/// within 1 % and within 4 standard errors of the analytic radiance, and every block is
/// within `block_tolerance` of it (the chains distribute b over the image correctly).
fn check_furnace(r: &Rendered, expected: f64, block_tolerance: f64) {
    let blocks = block_means(r, 4);
    let mean: f64 = blocks.iter().sum::<f64>() / blocks.len() as f64;
    let se = r.stats.b_standard_error;
    println!(
        "furnace: mean {mean:.4} (b = {:.4} ± {se:.4}), expected {expected:.4}, blocks {blocks:.3?}",
        r.stats.b
    );
    assert!((mean / expected - 1.0).abs() < 0.01, "mean {mean} vs {expected}");
    // b pools the bootstrap's samples with every large step's, and agrees with the analytic
    // value within its own standard error.
    assert!(r.stats.large_steps > 0, "large steps refine b");
    assert!((r.stats.b - expected).abs() < 4.0 * se, "b = {} ± {se} vs {expected}", r.stats.b);
    for b in &blocks {
        assert!((b / expected - 1.0).abs() < block_tolerance, "block {b} vs {expected}");
    }
    assert_eq!(r.stats.invalid, 0);
}

#[test]
fn furnace_matches_the_analytic_radiance_on_the_cpu() {
    for (rho, k) in [(0.5, 3), (0.8, 5), (0.5, 0)] {
        let scene = furnace(1.0, rho);
        let r = render_cpu(&scene, &settings(16, k, 2048.0, 4096, 1 << 20));
        check_furnace(&r, furnace_radiance(1.0, rho, k), 0.08);
    }
}

/// Block means of `replicas` independent renders (seeds `seed0 + i`).
fn replica_blocks(scene: &SceneData, s: &Settings, seed0: u32, replicas: u32) -> Vec<Vec<f64>> {
    (0..replicas)
        .map(|i| {
            let mut s = s.clone();
            s.seed = seed0 + i;
            block_means(&render_cpu(scene, &s), 4)
        })
        .collect()
}

/// No region of the furnace deviates beyond its noise. The radiance is uniform, so every
/// block has the same distribution: the noise of a block mean is estimated from all blocks
/// of 8 independent renders together (112 degrees of freedom), and every block's mean over
/// the renders must lie within 4.5 standard errors of the analytic radiance (a family-wise
/// false-alarm rate below 0.01 % over the 16 blocks).
#[test]
fn furnace_blocks_are_within_their_noise() {
    let (rho, k) = (0.8, 5);
    let scene = furnace(1.0, rho);
    let expected = furnace_radiance(1.0, rho, k);
    let runs = replica_blocks(&scene, &settings(16, k, 256.0, 2048, 1 << 18), 100, 8);
    let pooled = (0..16).map(|b| stats::mean_and_variance(&runs, b).1).sum::<f64>() / 16.0;
    let se = (pooled / runs.len() as f64).sqrt();
    for b in 0..16 {
        let (m, _) = stats::mean_and_variance(&runs, b);
        let z = (m - expected) / se;
        println!("block {b}: {m:.4} (z = {z:+.2}, se {se:.4})");
        assert!(z.abs() < 4.5, "block {b}: {m} vs {expected}, {z:.2} standard errors");
    }
}

/// The path tracer as a method: the furnace's mean within 4 standard errors of the analytic
/// radiance (the error from the spread of the pixels' means: every pixel has the same
/// distribution), and every block within 6 %, on the CPU and (with a device) on the device.
#[test]
fn the_path_tracer_matches_the_furnace() {
    let (rho, k) = (0.8, 5);
    let scene = furnace(1.0, rho);
    let expected = furnace_radiance(1.0, rho, k);
    let mut s = settings(16, k, 512.0, 4096, 1);
    s.method = Method::PathTracer;
    let mut renders = vec![("cpu", render_cpu(&scene, &s))];
    if let Some(gpu) = common::gpu_or_skip("the_path_tracer_matches_the_furnace (device half)") {
        let mut backend =
            GpuBackend::new(gpu, &scene, &render::base_params(&scene, &s)).expect("device buffers");
        renders.push(("device", render_on(&scene, &s, &mut backend)));
    }
    for (device, r) in renders {
        assert_eq!(r.stats.b, 1.0, "{device}: the path tracer is not normalised");
        assert_eq!(r.stats.candidates, 512 * 256, "{device}: 512 samples of 256 pixels");
        let luminance: Vec<f64> =
            r.rgb.chunks(3).map(|c| (c[0] as f64 + c[1] as f64 + c[2] as f64) / 3.0).collect();
        let n = luminance.len() as f64;
        let mean = luminance.iter().sum::<f64>() / n;
        let variance = luminance.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let se = (variance / n).sqrt();
        println!("{device}: path tracer mean {mean:.5} ± {se:.5}, expected {expected:.5}");
        assert!((mean - expected).abs() < 4.0 * se, "{device}: {mean} ± {se} vs {expected}");
        for b in block_means(&r, 4) {
            assert!((b / expected - 1.0).abs() < 0.06, "{device}: block {b} vs {expected}");
        }
    }
}

#[test]
fn furnace_matches_the_analytic_radiance_on_the_device() {
    let Some(gpu) = common::gpu_or_skip("furnace_matches_the_analytic_radiance_on_the_device") else {
        return;
    };
    let (rho, k) = (0.5, 3);
    let scene = furnace(1.0, rho);
    let s = settings(16, k, 1024.0, 4096, 1 << 18);
    let params = render::base_params(&scene, &s);
    let mut backend = GpuBackend::new(gpu, &scene, &params).expect("device buffers");
    let r = render_on(&scene, &s, &mut backend);
    check_furnace(&r, furnace_radiance(1.0, rho, k), 0.06);
}

/// Independent proposals only (p_large = 1) and the default schedule (p_large = 0.3) are two
/// different Markov chains with the same stationary distribution: on the default scene, each
/// 4×4 block's mean over 6 independent renders of one agrees with the other's within 5
/// standard errors of the difference (measured from the renders' spread).
#[test]
fn large_steps_only_and_the_default_schedule_agree() {
    let scene = SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell").expect("cornell");
    let mut s = settings(32, 5, 256.0, 4096, 1 << 17);
    let default = replica_blocks(&scene, &s, 10, 6);
    s.mutation.p_large = 1.0;
    let independent = replica_blocks(&scene, &s, 20, 6);
    let mut worst = 0.0f64;
    for b in 0..16 {
        let (ma, mb, z) = stats::z_score(&default, &independent, b);
        worst = worst.max(z.abs());
        assert!(z.abs() < 5.0, "block {b}: {ma:.5} vs {mb:.5} (z = {z:.2})");
    }
    println!("default vs large steps only: worst block |z| = {worst:.2}");
}

/// Every method converges to the same image: on the default scene, at a fixed seed and equal
/// budgets, each 4×4 block's mean over 5 independent renders of s2, s4, s6, rc4, rc16 and the
/// path tracer agrees with naive's within 5 standard errors of the difference (from the
/// renders' spread).
#[test]
fn every_method_converges_to_the_same_image() {
    let scene = SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell").expect("cornell");
    let mut s = settings(32, 5, 256.0, 4096, 1 << 17);
    let naive = replica_blocks(&scene, &s, 30, 5);
    for method in ["s2", "s4", "s6", "rc4", "rc16", "pt"] {
        s.method = method.parse().unwrap();
        let runs = replica_blocks(&scene, &s, 40, 5);
        let mut worst = 0.0f64;
        for b in 0..16 {
            let (ma, mb, z) = stats::z_score(&naive, &runs, b);
            worst = worst.max(z.abs());
            assert!(z.abs() < 5.0, "{method} block {b}: naive {ma:.5}, {method} {mb:.5} (z = {z:.2})");
        }
        println!("{method} vs naive: worst block |z| = {worst:.2}");
    }
}

/// A render is a function of its settings: the same seed gives the same image and the same
/// counts, bit for bit (the method names themselves are tested in `render::method`).
#[test]
fn a_render_is_deterministic() {
    let scene = SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell").expect("cornell");
    for method in ["naive", "s3", "rc8", "pt"] {
        let mut s = settings(16, 4, 16.0, 1024, 4096);
        s.method = method.parse().unwrap();
        let a = render_cpu(&scene, &s);
        let b = render_cpu(&scene, &s);
        assert_eq!(bits(&a.rgb), bits(&b.rgb), "{method}");
        assert_eq!(a.accumulation, b.accumulation, "{method}");
        assert_eq!((a.stats.b, a.stats.iterations), (b.stats.b, b.stats.iterations), "{method}");
        s.seed += 1;
        let c = render_cpu(&scene, &s);
        assert_ne!(bits(&a.rgb), bits(&c.rgb), "{method}: another seed, another image");
    }
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}
