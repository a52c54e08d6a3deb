//! The missing-light test of `--method auto` as it is (`auto::assess`), beside a variant that
//! counts a block only where both halves of the candidate fall short of both halves of the other,
//! for three candidates (pt, naive, path-naive) at a three-way pilot's length for an 8 s render.
//! Not built with the workspace; to run it, copy it into host/examples/ and
//!   cargo run --release --example missing_halves -- SCENE VIEW REF.exr MAX_DEPTH REPEATS
use std::path::Path;

use glam::Vec3;
use smlt::render::{self, auto, Budget, Method, Preparation, Settings};
use smlt::scene::SceneData;

const PATH_NAIVE: Method =
    Method::Metropolis { schedule: render::Schedule::NAIVE, estimator: render::Estimator::Path };

fn blocks(values: usize, width: usize) -> Vec<Vec<usize>> {
    let height = (values / 3).div_ceil(width);
    let mut out = Vec::new();
    for by in (0..height).step_by(4) {
        for bx in (0..width).step_by(4) {
            for c in 0..3 {
                let b: Vec<usize> = (by..(by + 4).min(height))
                    .flat_map(|y| (bx..(bx + 4).min(width)).map(move |x| 3 * (y * width + x) + c))
                    .collect();
                out.push(b);
            }
        }
    }
    out
}

fn main() -> anyhow::Result<()> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let mut scene = SceneData::load(Path::new(&a[0]))?;
    scene.select_view(a[1].parse()?)?;
    let (width, height, truth) = smlt::output::read_exr(Path::new(&a[2]))?;
    let truth: Vec<f64> = truth.iter().map(|&v| v as f64).collect();
    let max_depth: u32 = a[3].parse()?;
    let repeats: u32 = a[4].parse()?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let methods = [Method::PathTracer, Method::NAIVE, PATH_NAIVE];
    let half_budget = Budget::Seconds((0.08f64 * 8.0).sqrt() / 6.0);
    let render_seconds = 8.0 - 0.9;
    println!("repeat,method,halves,missing_now,missing_both_halves,predicted_now,predicted_both,pilot_true");
    for repeat in 0..repeats {
        let s = Settings { width, height, max_depth, seed: 2000 + repeat, ..Settings::default() };
        let mut runs = Vec::new();
        let mut lum: Option<Vec<f32>> = None;
        for m in methods {
            let mut halves = [Vec::new(), Vec::new()];
            let mut candidates = [0; 2];
            let mut seconds = 0.0;
            for half in 0..2 {
                let p = auto::pilot_settings(&s, m, half, half_budget);
                let mut b = render::new_backend(None, &scene, &render::base_params(&scene, &p), threads)?;
                let prep = lum.as_deref().map_or(Preparation::Fast, Preparation::FastFrom);
                let image = render::render_with(&scene, &p, b.as_mut(), |_: f64| {}, prep)?;
                seconds += image.stats.render_seconds;
                candidates[half as usize] = image.stats.candidates;
                halves[half as usize] = image.rgb;
            }
            if m == Method::PathTracer {
                let l = |h: &Vec<f32>| -> Vec<f32> {
                    h.chunks(3).map(|c| shared::color::luminance(Vec3::new(c[0], c[1], c[2]))).collect()
                };
                let (x, y) = (l(&halves[0]), l(&halves[1]));
                lum = Some(x.iter().zip(&y).map(|(a, b)| 0.5 * (a + b)).collect());
            }
            runs.push(auto::PilotRun { method: m, halves, seconds, candidates });
        }
        let assessed = auto::assess(&runs, width);
        let r = auto::reference(&runs);
        let bl = blocks(r.len(), width as usize);
        let n = r.len() as f64;
        for (k, ak) in assessed.iter().enumerate() {
            let mut variant: f64 = 0.0;
            for (o, _) in runs.iter().enumerate().filter(|(o, _)| *o != k) {
                let mut sum = 0.0;
                for b in &bl {
                    let m = b.len() as f64;
                    let bm = |img: &[f32]| b.iter().map(|&j| img[j] as f64).sum::<f64>() / m;
                    let (k0, k1) = (bm(&runs[k].halves[0]), bm(&runs[k].halves[1]));
                    let (o0, o1) = (bm(&runs[o].halves[0]), bm(&runs[o].halves[1]));
                    let d = 0.5 * (o0 + o1) - 0.5 * (k0 + k1);
                    let var = |x: f64, y: f64| 0.25 * (x - y) * (x - y);
                    let v = b
                        .iter()
                        .map(|&j| {
                            let (a, bb) = (runs[o].halves[0][j] as f64, runs[o].halves[1][j] as f64);
                            let (c, e) = (runs[k].halves[0][j] as f64, runs[k].halves[1][j] as f64);
                            var(a, bb) + var(c, e)
                        })
                        .sum::<f64>()
                        / (m * m);
                    let rb = b.iter().map(|&j| r[j]).sum::<f64>() / m;
                    let both = o0.min(o1) > k0.max(k1);
                    let term = if both { auto::missing_in_block(d, v) } else { 0.0 };
                    sum += m * term / (rb * rb + auto::RELMSE_FLOOR);
                }
                variant = variant.max(sum / n);
            }
            let scale = ak.seconds / render_seconds;
            let pilot_true = auto::relative(
                runs[k].halves[0]
                    .iter()
                    .zip(&runs[k].halves[1])
                    .zip(&truth)
                    .map(|((a, b), t)| (0.5 * (a + b) as f64 - t).powi(2)),
                &truth,
            );
            println!(
                "{repeat},{},{:.3e},{:.3e},{:.3e},{:.3e},{:.3e},{:.3e}",
                ak.method,
                ak.halves_relmse,
                ak.missing_relmse,
                variant,
                ak.halves_relmse * scale + ak.missing_relmse,
                ak.halves_relmse * scale + variant,
                pilot_true
            );
        }
    }
    Ok(())
}
