//! How well `--method auto`'s pilot measures each candidate's error: the pilot of a render of
//! `--time T` at the reference's size, repeated with other seeds, and each candidate's error
//! estimated from its halves against three denominators — the pilot's own reference (the
//! median of the halves, `auto::reference`), the first pilot's (the runs' means weighted by
//! their precision), and the true image — beside the pilot image's true relMSE. Not a test: the
//! evidence behind the pilot's reference (`results/cpu-path/auto/pilot_reference.md`).
//!
//! ```sh
//! cargo run --release --example pilot -- SCENE.gltf VIEW REFERENCE.exr [REPEATS] [T] [CANDIDATES]
//! ```

use std::path::Path;

use smlt::render::{self, auto, Budget, Settings};
use smlt::scene::SceneData;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [scene, view, reference] = [0, 1, 2].map(|i| args.get(i).cloned().unwrap_or_default());
    let repeats: u32 = args.get(3).map_or(Ok(3), |a| a.parse())?;
    let seconds: f64 = args.get(4).map_or(Ok(8.0), |a| a.parse())?;
    let candidates: u32 = args.get(5).map_or(Ok(render::default_candidates(None)), |a| a.parse())?;
    let mut scene = SceneData::load(Path::new(&scene))?;
    scene.select_view(view.parse()?)?;
    let (width, height, truth) = smlt::output::read_exr(Path::new(&reference))?;
    let truth: Vec<f64> = truth.iter().map(|&v| v as f64).collect();
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!("repeat,method,halves_median,halves_weighted,halves_truth,pilot_truth,missing,predicted,chosen,firefly_share");
    for repeat in 0..repeats {
        let s = Settings {
            width,
            height,
            seed: 1000 + repeat,
            budget: Budget::Seconds(seconds),
            candidates,
            ..Settings::default()
        };
        let pilot = auto::run_pilot(&scene, &s, &mut |p| render::new_backend(None, &scene, p, threads))?;
        let runs = &pilot.runs;
        let assessed = auto::assess(runs, width);
        let left = match auto::remaining_budget(s.budget, 0.0) {
            Budget::Seconds(t) => t,
            _ => unreachable!(),
        };
        let chosen = auto::most_efficient(&assessed, left, 1.0);
        let medians = auto::reference(runs);
        let weighted = precision_weighted(runs, &medians);
        for (run, a) in runs.iter().zip(&assessed) {
            let halves = |denominators: &[f64]| {
                relmse(
                    run.halves[0].iter().zip(&run.halves[1]).map(|(a, b)| 0.5 * (a - b) as f64),
                    denominators,
                )
            };
            let mean = run.halves[0]
                .iter()
                .zip(&run.halves[1])
                .zip(&truth)
                .map(|((a, b), t)| 0.5 * (a + b) as f64 - t);
            println!(
                "{repeat},{},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e},{},{:.3}",
                run.method,
                halves(&medians),
                halves(&weighted),
                halves(&truth),
                relmse(mean, &truth),
                a.missing_relmse,
                a.predicted_relmse(left, 1.0),
                chosen,
                a.firefly_share
            );
        }
    }
    Ok(())
}

/// relMSE of the errors `e` against the denominators `r` (auto's own form).
fn relmse(errors: impl Iterator<Item = f64>, r: &[f64]) -> f64 {
    auto::relative(errors.map(|e| e * e), r)
}

/// The first pilot's reference: the runs' means weighted by 1 / their halves' relMSE against
/// the runs' plain average.
fn precision_weighted(runs: &[auto::PilotRun], like: &[f64]) -> Vec<f64> {
    let means: Vec<Vec<f64>> = runs
        .iter()
        .map(|r| r.halves[0].iter().zip(&r.halves[1]).map(|(a, b)| 0.5 * (a + b) as f64).collect())
        .collect();
    let average: Vec<f64> =
        (0..like.len()).map(|j| means.iter().map(|m| m[j]).sum::<f64>() / means.len() as f64).collect();
    let weights: Vec<f64> = runs
        .iter()
        .map(|r| relmse(r.halves[0].iter().zip(&r.halves[1]).map(|(a, b)| 0.5 * (a - b) as f64), &average))
        .map(|h| if h > 0.0 { 1.0 / h } else { 0.0 })
        .collect();
    let total: f64 = weights.iter().sum();
    (0..like.len()).map(|j| weights.iter().zip(&means).map(|(w, m)| w * m[j]).sum::<f64>() / total).collect()
}
