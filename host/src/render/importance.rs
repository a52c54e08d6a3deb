//! The pixel importance Ĩ (`shared::layout::pack_over_importance`): a short path-traced
//! estimate of every pixel's luminance, smoothed and mixed with its mean, made on the host
//! before the chains start. Like the bootstrap, a render's estimate casts its rays through the
//! device's own traversal ([`Preparation::Reproducible`]) and its samples are keyed by the seed
//! alone, so every shard of a render, on any machine, uses the very same Ĩ (auto's pilot, which
//! no shard shares, casts through the fastest host caster). Ĩ only reshapes the chains' target:
//! any positive Ĩ gives the same image.

use rayon::prelude::*;
use shared::color::luminance;
use shared::path_tracer::{pixel_round, PathTracerParams};
use shared::ray_caster::RayCaster;
use shared::scene::Scene;

use super::{path_params, Estimator, Metropolis, Preparation, Settings};
use crate::scene::SceneData;

/// Samples per pixel of the estimate.
pub const IMPORTANCE_SPP: u32 = 4;
/// The estimate's round: its sample numbers start at 2^31, which no render of the path tracer
/// (numbered from 0) reaches, so it is independent of `--method pt` and of references.
const IMPORTANCE_ROUND: u32 = (1 << 31) / IMPORTANCE_SPP;

/// What is added to the estimate, as a fraction of the image's mean (a defensive mixture),
/// for chains of `estimator`: pixels much brighter than that get about equal shares of the
/// chains' steps, pixels much darker a share in proportion to their light, and a pixel the
/// short estimate found (wrongly) black never a runaway weight.
///
/// The multiplexed estimator's mixture is four times the path estimator's, a milder reshaping:
/// with the path estimator's, its efficiency fell to 0.57× and 0.63× the luminance target's on
/// `sunblind` and `slit` (light through gaps); with 4 it is level with the luminance target
/// there and keeps the gains elsewhere (Sponza 1.55×, the banner view 1.30×; measured, the
/// cause not found: `results/cpu-path/mmlt_target/`).
pub fn importance_mix(estimator: Estimator) -> f32 {
    match estimator {
        Estimator::Path => 1.0,
        Estimator::Multiplexed => 4.0,
    }
}

/// Ĩ for the chains `m` of a render with settings `s`: [`IMPORTANCE_SPP`] path-traced samples
/// of every pixel on the current rayon pool (or the luminance [`Preparation::FastFrom`] gives,
/// where it is of the render's size), then [`smooth_and_mix`].
pub fn estimate_pixel_importance(
    scene: &SceneData,
    s: &Settings,
    m: &Metropolis,
    preparation: Preparation<'_>,
) -> Vec<f32> {
    let params = PathTracerParams {
        samples: IMPORTANCE_SPP,
        samples_per_round: IMPORTANCE_SPP,
        round: IMPORTANCE_ROUND,
        ..path_params(scene, s)
    };
    let pixels = s.width * s.height;
    let estimate: Vec<f32> = match preparation {
        Preparation::FastFrom(luminance) if luminance.len() == pixels as usize => luminance.to_vec(),
        p if p.fast() => luminances(&params, scene.shared(), pixels),
        _ => luminances(&params, scene.device_view(), pixels),
    };
    smooth_and_mix(&estimate, s.width, s.height, importance_mix(m.estimator))
}

/// The mean luminance of `params.samples` path-traced samples of each of `pixels` pixels, on
/// the current rayon pool.
fn luminances<R: RayCaster + Sync>(params: &PathTracerParams, view: Scene<R>, pixels: u32) -> Vec<f32> {
    (0..pixels)
        .into_par_iter()
        .map(|j| luminance(pixel_round(params, view, j)) / params.samples as f32)
        .collect()
}

/// Ĩ from a noisy luminance estimate `l` (row-major, `width`×`height`): the mean of each pixel's
/// 3×3 neighbourhood (clipped at the image's edges) plus `mix` times the image's mean; all
/// ones where the estimate is zero everywhere.
pub fn smooth_and_mix(l: &[f32], width: u32, height: u32, mix: f32) -> Vec<f32> {
    let (w, h) = (width as i64, height as i64);
    let mean = l.iter().map(|&v| v as f64).sum::<f64>() / l.len().max(1) as f64;
    if !(mean > 0.0) {
        return vec![1.0; l.len()];
    }
    let added = (mix as f64 * mean) as f32;
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let (mut sum, mut count) = (0.0f32, 0.0f32);
            for (dx, dy) in (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| (dx, dy))) {
                let (nx, ny) = (x + dx, y + dy);
                if (0..w).contains(&nx) && (0..h).contains(&ny) {
                    let v = l[(nx + ny * w) as usize];
                    if v.is_finite() {
                        sum += v;
                        count += 1.0;
                    }
                }
            }
            sum / count.max(1.0) + added
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 3×3 mean, clipped at the edges, plus a fraction of the mean; a black estimate gives
    /// ones (nothing to shape).
    #[test]
    fn smoothing_averages_neighbours_and_adds_the_mean() {
        // 3×2 image: one bright pixel at (1, 0).
        let l = [0.0, 9.0, 0.0, 0.0, 0.0, 0.0];
        let i = smooth_and_mix(&l, 3, 2, 0.1);
        // Corner (0, 0): neighbours (0,0), (1,0), (0,1), (1,1): 9 / 4, plus 0.1 × the mean 1.5.
        assert_eq!(i[0], 2.25 + 0.15);
        // (1, 1) sees all six pixels: 9 / 6.
        assert_eq!(i[4], 1.5 + 0.15);
        // (0, 1) sees (0,0), (1,0), (0,1), (1,1).
        assert_eq!(i[3], 2.25 + 0.15);
        assert_eq!(smooth_and_mix(&[0.0; 6], 3, 2, 0.1), vec![1.0; 6]);
        let with_nan = smooth_and_mix(&[1.0, f32::NAN, 1.0, 1.0], 2, 2, 0.1);
        assert!(with_nan.iter().all(|v| v.is_finite()), "{with_nan:?}");
    }
}
