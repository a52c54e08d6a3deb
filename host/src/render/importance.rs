//! The pixel importance Ĩ (`shared::layout::pack_over_importance`): a short path-traced
//! estimate of every pixel's luminance, smoothed and mixed with its mean, made on the host
//! before the chains start. Like the bootstrap, a render's estimate casts its rays through the
//! device's own traversal ([`Preparation::Reproducible`]) and its samples are keyed by the seed
//! alone, so every shard of a render, on any machine, uses the very same Ĩ (auto's pilot, which
//! no shard shares, casts through the fastest host caster). Ĩ only reshapes the chains' target:
//! any positive Ĩ gives the same image.
//!
//! Its cost is bounded ([`IMPORTANCE_SAMPLES`]): a large image is estimated per square block of
//! pixels ([`block_side`]), as a smaller image would be. At 1920×1080 four samples of every pixel
//! took 39 s on 2 CPUs before a render's clock started (Sibenik, `naive`), longer than many
//! renders; one estimate per 3×3 block takes a ninth of that.

use rayon::prelude::*;
use shared::color::luminance;
use shared::path_tracer::{pixel_round, pixel_sample, PathTracerParams};
use shared::ray_caster::RayCaster;
use shared::scene::Scene;

use super::{path_params, Estimator, Metropolis, Preparation, Settings};
use crate::scene::SceneData;

/// Samples per pixel of the estimate.
pub const IMPORTANCE_SPP: u32 = 4;
/// The most path-traced samples the estimate takes: [`IMPORTANCE_SPP`] for every pixel of an
/// image of up to 2^18 pixels (512×512; every render the bench measures), then as many for
/// every block of [`block_side`]² pixels.
pub const IMPORTANCE_SAMPLES: u64 = 1 << 20;

/// The side of the square blocks of pixels that share one estimate in a `width`×`height` image:
/// the least whose blocks take at most [`IMPORTANCE_SAMPLES`] samples (1: every pixel its own).
pub fn block_side(width: u32, height: u32) -> u32 {
    let mut side = 1;
    while width.div_ceil(side) as u64 * height.div_ceil(side) as u64 * IMPORTANCE_SPP as u64
        > IMPORTANCE_SAMPLES
    {
        side += 1;
    }
    side
}

/// The pixel that sample `k` of a block takes: of the block's `w`×`h` pixels (inside the image)
/// in row-major order, the `k`-th of [`IMPORTANCE_SPP`] at an even stride, so that a 2×2 block's
/// four samples take its four pixels; as (x, y) within the block.
pub fn block_sample_pixel(w: u32, h: u32, k: u32) -> (u32, u32) {
    let i = (k as u64 * (w * h) as u64 / IMPORTANCE_SPP as u64) as u32;
    (i % w, i / w)
}

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
    let mix = importance_mix(m.estimator);
    let side = block_side(s.width, s.height);
    if side > 1 {
        let (w, h) = (s.width.div_ceil(side), s.height.div_ceil(side));
        let estimate = if preparation.fast() {
            block_luminances(&params, scene.shared(), s.width, s.height, side)
        } else {
            block_luminances(&params, scene.device_view(), s.width, s.height, side)
        };
        let blocks = smooth_and_mix(&estimate, w, h, mix);
        return (0..pixels)
            .map(|p| blocks[((p / s.width / side) * w + p % s.width / side) as usize])
            .collect();
    }
    let estimate: Vec<f32> = match preparation {
        Preparation::FastFrom(luminance) if luminance.len() == pixels as usize => luminance.to_vec(),
        p if p.fast() => luminances(&params, scene.shared(), pixels),
        _ => luminances(&params, scene.device_view(), pixels),
    };
    smooth_and_mix(&estimate, s.width, s.height, mix)
}

/// The mean luminance of [`IMPORTANCE_SPP`] path-traced samples of each `side`×`side` block of
/// a `width`×`height` image (row-major, the blocks at its right and bottom edges cut by them),
/// each sample through one of the block's pixels ([`block_sample_pixel`]), numbered as the
/// per-pixel estimate numbers its samples; on the current rayon pool.
fn block_luminances<R: RayCaster + Sync>(
    params: &PathTracerParams,
    view: Scene<R>,
    width: u32,
    height: u32,
    side: u32,
) -> Vec<f32> {
    let blocks_wide = width.div_ceil(side);
    (0..blocks_wide * height.div_ceil(side))
        .into_par_iter()
        .map(|b| {
            let (x0, y0) = (b % blocks_wide * side, b / blocks_wide * side);
            let (w, h) = (side.min(width - x0), side.min(height - y0));
            let mut sum = 0.0;
            for k in 0..IMPORTANCE_SPP {
                let (x, y) = block_sample_pixel(w, h, k);
                let pixel = (y0 + y) * width + x0 + x;
                let l = pixel_sample(params, view, pixel, params.round * params.samples_per_round + k);
                // A NaN or infinite sample is dropped, as `pixel_round` drops it.
                if l.is_finite() {
                    sum += luminance(l);
                }
            }
            sum / IMPORTANCE_SPP as f32
        })
        .collect()
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

    /// Every pixel its own estimate up to 512×512 (the bench's 128×72 and the default 256×256
    /// among them); 1080p in 3×3 blocks, 4K in 6×6, each within the budget.
    #[test]
    fn blocks_keep_the_estimate_within_its_budget() {
        for (w, h) in [(128, 72), (256, 256), (512, 512), (1, 1)] {
            assert_eq!(block_side(w, h), 1, "{w}×{h}");
        }
        assert_eq!(block_side(513, 512), 2);
        assert_eq!(block_side(1920, 1080), 3);
        assert_eq!(block_side(3840, 2160), 6);
        for (w, h) in [(1920, 1080), (3840, 2160), (16384, 16384), (16384, 1), (700, 701)] {
            let side = block_side(w, h);
            let samples =
                |side: u32| w.div_ceil(side) as u64 * h.div_ceil(side) as u64 * IMPORTANCE_SPP as u64;
            assert!(samples(side) <= IMPORTANCE_SAMPLES, "{w}×{h}: {}", samples(side));
            assert!(
                side == 1 || samples(side - 1) > IMPORTANCE_SAMPLES,
                "{w}×{h}: side {side} is not the least"
            );
        }
    }

    /// A 2×2 block's four samples take its four pixels; the samples of any block, a cut one at
    /// the image's edge included, stay inside it.
    #[test]
    fn a_blocks_samples_spread_over_its_pixels() {
        let taken: Vec<_> = (0..IMPORTANCE_SPP).map(|k| block_sample_pixel(2, 2, k)).collect();
        assert_eq!(taken, [(0, 0), (1, 0), (0, 1), (1, 1)]);
        for (w, h) in [(3, 3), (1, 1), (1, 3), (6, 2), (2, 1)] {
            for k in 0..IMPORTANCE_SPP {
                let (x, y) = block_sample_pixel(w, h, k);
                assert!(x < w && y < h, "{w}×{h} sample {k}: ({x}, {y})");
            }
        }
    }

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
