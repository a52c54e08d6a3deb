//! Convergence: the MMLT image matches analytic answers, on the CPU and on the device, and
//! different mutation schedules converge to the same image.

mod common;

use common::scenes::{furnace, furnace_radiance};
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
    }
}

fn render_on(scene: &SceneData, s: &Settings, backend: &mut dyn Backend) -> Rendered {
    render::render(scene, s, backend, |_| {}).expect("render")
}

fn render_cpu(scene: &SceneData, s: &Settings) -> Rendered {
    let params = render::base_params(scene, s);
    render_on(scene, s, &mut CpuBackend::new(scene, &params))
}

/// Mean luminance of each of `blocks`×`blocks` image blocks.
fn block_means(r: &Rendered, blocks: u32) -> Vec<f64> {
    let mut sums = vec![0.0; (blocks * blocks) as usize];
    let mut counts = vec![0u32; sums.len()];
    for y in 0..r.height {
        for x in 0..r.width {
            let i = ((x + y * r.width) * 3) as usize;
            let lum = shared::mmlt::luminance(glam::Vec3::new(r.rgb[i], r.rgb[i + 1], r.rgb[i + 2])) as f64;
            let b = (x * blocks / r.width + (y * blocks / r.height) * blocks) as usize;
            sums[b] += lum;
            counts[b] += 1;
        }
    }
    sums.iter().zip(&counts).map(|(s, c)| s / *c as f64).collect()
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

/// No region of the furnace deviates beyond its noise: over 6 independent renders (seeds),
/// every 4×4 block's mean is within 4 standard errors (measured across the seeds) of the
/// analytic radiance.
#[test]
fn furnace_blocks_are_within_their_noise() {
    let (rho, k) = (0.8, 5);
    let scene = furnace(1.0, rho);
    let expected = furnace_radiance(1.0, rho, k);
    let runs: Vec<Vec<f64>> = (0..6)
        .map(|seed| {
            let mut s = settings(16, k, 512.0, 2048, 1 << 18);
            s.seed = 100 + seed;
            block_means(&render_cpu(&scene, &s), 4)
        })
        .collect();
    let r = runs.len() as f64;
    for b in 0..16 {
        let m = runs.iter().map(|x| x[b]).sum::<f64>() / r;
        let var = runs.iter().map(|x| (x[b] - m).powi(2)).sum::<f64>() / (r - 1.0);
        let se = (var / r).sqrt();
        println!("block {b}: {m:.4} ± {se:.4} (expected {expected:.4})");
        assert!((m - expected).abs() < 4.0 * se.max(1e-3 * expected), "block {b}: {m} ± {se} vs {expected}");
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
/// different Markov chains with the same stationary distribution: on the default scene their
/// 4×4 block means agree within 10 % of the image's mean brightness.
#[test]
fn large_steps_only_and_the_default_schedule_agree() {
    let scene = SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell").expect("cornell");
    let mut s = settings(32, 5, 1024.0, 4096, 1 << 18);
    let default = render_cpu(&scene, &s);
    s.mutation.p_large = 1.0;
    s.seed = 8;
    let independent = render_cpu(&scene, &s);
    let a = block_means(&default, 4);
    let b = block_means(&independent, 4);
    let mean: f64 = a.iter().sum::<f64>() / a.len() as f64;
    let worst = a.iter().zip(&b).map(|(x, y)| (x - y).abs() / mean).fold(0.0, f64::max);
    println!("default vs large steps: worst block difference {:.3} of the mean {mean:.4}", worst);
    println!(
        "acceptance: default {:.3}, large steps only {:.3}",
        default.stats.acceptance, independent.stats.acceptance
    );
    assert!(worst < 0.10, "{a:.4?} vs {b:.4?}");
    assert!(independent.stats.acceptance < default.stats.acceptance);
}
