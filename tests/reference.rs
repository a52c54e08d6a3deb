//! The reference estimator (independent path tracer): analytic furnace, device = CPU, and
//! agreement with the MMLT renderer within noise.

mod common;

use common::stats;

use common::scenes::{furnace, furnace_radiance};
use smlt::reference::{render_reference, ReferenceSettings};
use smlt::render::{self, cpu::CpuBackend, Budget, ChainSettings, Integrator, Settings};
use smlt::scene::SceneData;

fn settings(name: &str, size: u32, max_depth: u32, spp: u32, seed: u32) -> ReferenceSettings {
    ReferenceSettings {
        scene: name.into(),
        scene_hash: String::new(),
        width: size,
        height: size,
        max_depth,
        spp,
        seed,
    }
}

fn block_means(rgb: &[f32], size: u32) -> Vec<f64> {
    stats::block_means(rgb, size, size, 4)
}

/// The reference of a ρ = 0.8 furnace at max depth `k` and `seed`: its mean within `mean_tol`
/// of the analytic radiance, every 16×16-pixel block within `block_tol`.
fn check_reference_furnace(k: u32, seed: u32, mean_tol: f64, block_tol: f64) {
    let rho = 0.8;
    let scene = furnace(1.0, rho);
    let rgb = render_reference(&scene, &settings("furnace", 16, k, 512, seed), None, 16, |_| {}).unwrap().rgb;
    let expected = furnace_radiance(1.0, rho, k);
    let mean = rgb.iter().map(|v| *v as f64).sum::<f64>() / rgb.len() as f64;
    println!("reference furnace, {k} bounces: mean {mean:.5}, expected {expected:.5}");
    assert!((mean / expected - 1.0).abs() < mean_tol, "{mean} vs {expected}");
    for b in block_means(&rgb, 16) {
        assert!((b / expected - 1.0).abs() < block_tol, "block {b} vs {expected}");
    }
}

#[test]
fn the_reference_furnace_is_analytic() {
    check_reference_furnace(5, 1, 0.002, 0.01);
}

/// Twelve bounces of a ρ = 0.8 furnace: bounces 5 and on play Russian roulette (the throughput
/// has fallen to 0.8^5 ≈ 0.33 at the fifth, so two paths in three end there, and a survivor's
/// is back at 1, so one in five ends at each bounce after), and the mean still matches the
/// analytic radiance (a roulette that forgot its 1/q would lose about a fifth of it).
#[test]
fn the_reference_furnace_is_analytic_through_russian_roulette() {
    check_reference_furnace(12, 3, 0.003, 0.015);
}

#[test]
fn the_device_reference_equals_the_cpu_reference() {
    let Some(gpu) = common::gpu_or_skip("the_device_reference_equals_the_cpu_reference") else {
        return;
    };
    let scene = SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell").unwrap();
    let s = settings("cornell", 16, 5, 32, 4);
    let cpu = render_reference(&scene, &s, None, 16, |_| {}).unwrap().rgb;
    let dev = render_reference(&scene, &s, Some(&gpu), 16, |_| {}).unwrap().rgb;
    let differ = cpu
        .iter()
        .zip(&dev)
        .filter(|(a, b)| (**a - **b).abs() > 1e-3 * a.abs().max(b.abs()).max(1e-3))
        .count();
    println!("reference pixels differing between device and CPU: {differ} of {}", cpu.len());
    assert!(differ <= cpu.len() / 200, "{differ} values differ");
}

/// The reference's estimate of its own noise (from the spread of its passes) predicts the RMSE
/// between two independent references: √2 times the noise of one.
#[test]
fn the_reference_knows_its_own_noise() {
    let scene = SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell").unwrap();
    let a = render_reference(&scene, &settings("cornell", 24, 5, 96, 1), None, 6, |_| {}).unwrap();
    let b = render_reference(&scene, &settings("cornell", 24, 5, 96, 2), None, 6, |_| {}).unwrap();
    let e = smlt_bench::metrics::errors(&a.rgb, &b.rgb);
    let predicted = (a.noise_rmse.powi(2) + b.noise_rmse.powi(2)).sqrt();
    println!("RMSE between references {:.5}, predicted from their noise {predicted:.5}", e.rmse);
    assert!(a.noise_rmse > 0.0 && b.noise_rmse > 0.0);
    assert!((e.rmse / predicted - 1.0).abs() < 0.2, "{} vs {predicted}", e.rmse);
    // Four times the samples: half the noise.
    let c = render_reference(&scene, &settings("cornell", 24, 5, 384, 3), None, 6, |_| {}).unwrap();
    let ratio = c.noise_rmse / a.noise_rmse;
    assert!((ratio - 0.5).abs() < 0.1, "noise ratio {ratio} for 4× the samples");
}

/// MMLT (naive and s3) and the independent path tracer agree on the default scene: every 4×4
/// block within 5 standard errors of the difference, the noise of each side measured from
/// independent runs.
#[test]
fn the_reference_and_mmlt_agree_on_the_default_scene() {
    let scene = SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell").unwrap();
    let (size, k) = (32, 5);
    let reference: Vec<Vec<f64>> = (0..4)
        .map(|seed| {
            block_means(
                &render_reference(&scene, &settings("cornell", size, k, 256, 10 + seed), None, 16, |_| {})
                    .unwrap()
                    .rgb,
                size,
            )
        })
        .collect();
    for method in ["naive", "s3"] {
        let mmlt: Vec<Vec<f64>> = (0..5)
            .map(|seed| {
                let s = Settings {
                    width: size,
                    height: size,
                    max_depth: k,
                    seed: 60 + seed,
                    integrator: Integrator::new(
                        method.parse().unwrap(),
                        ChainSettings { bootstrap_samples: 1 << 17, ..Default::default() },
                    ),
                    budget: Budget::MutationsPerPixel(256.0),
                    candidates: 4096,
                    ..Default::default()
                };
                let p = render::base_params(&scene, &s);
                let r =
                    render::render(&scene, &s, &mut CpuBackend::new(&scene, &p, 2).unwrap(), |_| {}).unwrap();
                block_means(&r.rgb, size)
            })
            .collect();
        let mut worst = 0.0f64;
        for b in 0..16 {
            let (mr, mm, z) = stats::z_score(&reference, &mmlt, b);
            worst = worst.max(z.abs());
            assert!(z.abs() < 5.0, "{method} block {b}: reference {mr:.5}, MMLT {mm:.5} (z = {z:.2})");
        }
        println!("reference vs {method}: worst block |z| = {worst:.2}");
    }
}
