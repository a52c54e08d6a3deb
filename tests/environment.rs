//! The environment light (`--environment`): the furnace under a uniform environment has its
//! analytic radiance with every estimator, on the CPU and on the device; every method converges
//! to the same image under a sky with a sun, through glass and beside a triangle lamp.

mod common;

use common::scenes::{environment_furnace, sky_scene};
use common::stats;
use smlt::render::{
    self, cpu::CpuBackend, gpu::GpuBackend, Backend, Budget, ChainSettings, Integrator, Method, Rendered,
    Settings,
};
use smlt::scene::SceneData;

fn settings(size: u32, max_depth: u32, mpp: f64, method: &str, seed: u32) -> Settings {
    let chains = ChainSettings { bootstrap_samples: 1 << 18, ..Default::default() };
    Settings {
        width: size,
        height: size,
        max_depth,
        seed,
        integrator: Integrator::new(Method::NAIVE, chains),
        budget: Budget::MutationsPerPixel(mpp),
        candidates: 4096,
        ..Default::default()
    }
    .with_method(method.parse().unwrap())
}

fn render_on(scene: &SceneData, s: &Settings, backend: &mut dyn Backend) -> Rendered {
    render::render(scene, s, backend, |_| {}).expect("render")
}

fn render_cpu(scene: &SceneData, s: &Settings) -> Rendered {
    let params = render::base_params(scene, s);
    render_on(scene, s, &mut CpuBackend::new(scene, &params, 2).expect("threads"))
}

/// The render's mean (of the rgb mean) is within 1 % of `expected` — within 4 of its standard
/// errors as well, the path tracer's from its pixels, a Metropolis render's from b — and each
/// of its 4 × 4 blocks is within `block_tolerance`.
fn check_uniform(what: &str, r: &Rendered, expected: f64, block_tolerance: f64) {
    let grey: Vec<f64> = r.rgb.chunks(3).map(|c| (c[0] as f64 + c[1] as f64 + c[2] as f64) / 3.0).collect();
    let n = grey.len() as f64;
    let mean = grey.iter().sum::<f64>() / n;
    let se = if r.stats.b_standard_error > 0.0 {
        r.stats.b_standard_error / r.stats.b * mean
    } else {
        (grey.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt()
    };
    let blocks = stats::block_means(&r.rgb, r.width, r.height, 4);
    println!("{what}: mean {mean:.5} ± {se:.5}, expected {expected:.5}, blocks {blocks:.3?}");
    assert!((mean / expected - 1.0).abs() < 0.01, "{what}: mean {mean} vs {expected}");
    assert!((mean - expected).abs() < 4.0 * se + 1e-4 * expected, "{what}: {mean} ± {se} vs {expected}");
    for b in blocks {
        assert!((b / expected - 1.0).abs() < block_tolerance, "{what}: block {b} vs {expected}");
    }
    assert_eq!(r.stats.invalid, 0, "{what}: invalid samples");
}

/// A convex object under a uniform environment of radiance 1 sends what it receives: a white
/// cube and the environment around it are 1 everywhere; a cube of albedo 0.5 that fills the
/// view is 0.5; a lossless glass cube that fills it is 1. With the path tracer, the multiplexed
/// estimator and the path estimator on the CPU, and the first two on the device.
#[test]
fn a_convex_object_under_a_uniform_environment_sends_what_it_receives() {
    let gpu = common::gpu_or_skip(
        "a_convex_object_under_a_uniform_environment_sends_what_it_receives (device half)",
    );
    for (what, rho, glass, fill, expected, depth) in [
        ("white cube in the open", 1.0, false, false, 1.0, 3),
        ("grey cube filling the view", 0.5, false, true, 0.5, 3),
        ("glass cube filling the view", 1.0, true, true, 1.0, 16),
    ] {
        let scene = environment_furnace(rho, glass, fill);
        for (method, mpp, blocks) in
            [("pt", 256.0, 0.03), ("naive", 4096.0, 0.08), ("path-naive", 4096.0, 0.08)]
        {
            let s = settings(16, depth, mpp, method, 5);
            check_uniform(&format!("{what}, {method}"), &render_cpu(&scene, &s), expected, blocks);
            if let (Some(gpu), false) = (&gpu, method == "path-naive") {
                let mut backend = GpuBackend::new(gpu.clone(), &scene, &render::base_params(&scene, &s))
                    .expect("device buffers");
                check_uniform(
                    &format!("{what}, {method} on the device"),
                    &render_on(&scene, &s, &mut backend),
                    expected,
                    blocks,
                );
            }
        }
    }
}

/// Block means of `replicas` independent renders (seeds `seed0 + i`).
fn replica_blocks(scene: &SceneData, s: &Settings, seed0: u32, replicas: u32) -> Vec<Vec<f64>> {
    (0..replicas)
        .map(|i| {
            let mut s = s.clone();
            s.seed = seed0 + i;
            let r = render_cpu(scene, &s);
            stats::block_means(&r.rgb, r.width, r.height, 4)
        })
        .collect()
}

/// Every method converges to the same image under the sky (`sky_scene`: a sun in a lat-long
/// map, a glass ball, a triangle lamp): each 4 × 4 block's mean over 5 renders of the path
/// tracer, s3, rc4 and the path estimator agrees with naive's within 5 standard errors of the
/// difference.
#[test]
fn every_method_converges_to_the_same_image_under_the_sky() {
    let scene = sky_scene();
    let naive = replica_blocks(&scene, &settings(32, 5, 256.0, "naive", 1), 60, 5);
    for name in ["pt", "s3", "rc4", "path-naive"] {
        let runs = replica_blocks(&scene, &settings(32, 5, 256.0, name, 1), 70, 5);
        let worst = stats::assert_blocks_agree(&format!("sky: naive vs {name}"), &naive, &runs);
        println!("sky: {name} vs naive: worst block |z| = {worst:.2}");
    }
}
