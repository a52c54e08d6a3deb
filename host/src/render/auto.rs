//! `--method auto` (the default): the method chosen for the view at hand from the scene itself,
//! with no reference image. Which estimator wins depends on the light: the path tracer on
//! interiors under a broad sky, the path estimator's chains on light through gaps, the
//! multiplexed chains on caustics (docs/results.md, "where each method wins").
//!
//! A **pilot** renders each candidate ([`CANDIDATES`]) at a reduced size ([`pilot_settings`])
//! as two independent halves (two seeds), one after the other, each for an equal share of the
//! pilot's time. Each candidate's error after its pilot time is estimated in two parts
//! ([`assess`]):
//! - its variance, from its own halves: half the squared difference of two independent
//!   estimates is an unbiased estimate of their mean's variance;
//! - the light it misses, against the other candidates. This is the guard against heavy tails:
//!   a path tracer's short pilot that has not yet met a caustic's rare paths has halves that
//!   agree (both miss the caustic) and looks better than it is; beside a Metropolis image that
//!   holds the caustic it is darker by more than both images' noise. Every estimator is
//!   unbiased and adds non-negative contributions, so an unsampled tail shows as missing light
//!   only, which tells the candidate that misses it from the one that holds it.
//!
//! From them each candidate's relMSE (as the bench measures it) is predicted for the render
//! ahead ([`Assessment::predicted_relmse`]: the variance scaled to the render's time and
//! pixels, the light missing kept), and the candidate predicted best renders the image: the render is
//! exactly `--method <chosen>`'s with the same seed, so that it can be reproduced, and the
//! pilot's samples are not kept (its images are smaller than the render's, and a Metropolis
//! pilot's chains are not the render's). The pilot's wall time counts against a `--time`
//! budget. Its Metropolis renders prepare their chains (the pixel importance and the bootstrap)
//! through the CPU's fastest caster ([`Preparation::Fast`]): a pilot is never sharded, and
//! through the device's own traversal, which a render's preparation takes so that its shards
//! agree, the four preparations were most of the pilot (2.7 s of an 8 s render on Sibenik,
//! 0.84 s of it rendering).

use std::time::Instant;

use shared::params::RenderParams;

use super::{
    render_with, Backend, Budget, Estimator, Method, Preparation, RenderError, Schedule, Settings, Shard,
    DEFAULT_BOOTSTRAP,
};
use crate::scene::SceneData;

/// The methods the pilot weighs: the path tracer, and naive chains over each estimator (the
/// speculative trees and reject chains parallelise the same chains; on these cores they do not
/// pay, docs/results.md).
pub const CANDIDATES: [Method; 3] = [
    Method::PathTracer,
    Method::NAIVE,
    Method::Metropolis { schedule: Schedule::NAIVE, estimator: Estimator::Path },
];

/// The widest pilot image: the pilot renders the view at most this wide (its aspect kept), so
/// that a short pilot has enough samples in each pixel to compare.
pub const PILOT_WIDTH: u32 = 128;

/// The share of a `--time` budget the pilot's renders take (at least [`PILOT_MIN_SECONDS`]).
pub const PILOT_SHARE: f64 = 0.1;

/// The least render time of a `--time` pilot, all its renders together.
pub const PILOT_MIN_SECONDS: f64 = 0.6;

/// The share of a `--mutations-per-pixel` budget each pilot render traces, at the pilot's size.
pub const PILOT_MUTATIONS_SHARE: f64 = 0.125;

/// One candidate's pilot: its two independent halves and their render seconds together.
#[derive(Clone, Debug)]
pub struct PilotRun {
    #[allow(missing_docs)] // the candidate
    pub method: Method,
    /// Linear rgb of the two halves, at the pilot's size.
    pub halves: [Vec<f32>; 2],
    /// Render seconds of both halves (their iterations, as the bench counts time).
    pub seconds: f64,
}

/// What the pilot estimated of one candidate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Assessment {
    #[allow(missing_docs)] // the candidate
    pub method: Method,
    /// Render seconds of its pilot.
    pub seconds: f64,
    /// Its pilot image's relMSE estimated from its own halves.
    pub halves_relmse: f64,
    /// The relMSE of the light its pilot image misses against another candidate's ([`assess`]):
    /// the squared bias a heavy tail not yet sampled leaves, which its halves do not see.
    pub missing_relmse: f64,
}

impl Assessment {
    /// The relMSE it is predicted to reach in a render of `seconds` with `pixels` times the
    /// pilot's pixels: its variance falls as 1/seconds and grows with the pixels (fewer
    /// samples each), and the light it misses stays. (A tail not yet sampled does shrink in
    /// time, but no pilot can say when; light no path of the method carries — a point lamp's
    /// caustic through glass, for the path tracer — never does.)
    pub fn predicted_relmse(&self, seconds: f64, pixels: f64) -> f64 {
        self.halves_relmse * self.seconds / seconds * pixels + self.missing_relmse
    }
}

/// The pilot's outcome.
#[derive(Clone, Debug)]
pub struct Choice {
    /// The most efficient candidate.
    pub method: Method,
    /// Every candidate's assessment, in [`CANDIDATES`]' order.
    pub assessments: Vec<Assessment>,
    /// Wall seconds of the whole pilot (its bootstraps and pixel importance included, the
    /// kernels' compilation not).
    pub seconds: f64,
    /// The pilot's image size.
    pub width: u32,
    #[allow(missing_docs)]
    pub height: u32,
    /// The render's seconds that the choice is for (predicted for a `--mutations-per-pixel`
    /// budget).
    pub render_seconds: f64,
    /// The render's pixels over the pilot's.
    pub pixels: f64,
}

impl Choice {
    /// One line for the render summary: what was chosen, and why.
    pub fn describe(&self) -> String {
        let each: Vec<String> = self
            .assessments
            .iter()
            .map(|a| {
                let guard = if a.missing_relmse > a.halves_relmse { ", missing light" } else { "" };
                format!("{} {:.2e}{guard}", a.method, a.predicted_relmse(self.render_seconds, self.pixels))
            })
            .collect();
        format!(
            "{} (pilot {:.2} s at {}×{}; predicted relMSE after {:.1} s: {})",
            self.method,
            self.seconds,
            self.width,
            self.height,
            self.render_seconds,
            each.join(", ")
        )
    }
}

/// relMSE's denominator term: (x − r)² / (r² + [`RELMSE_FLOOR`]), as the bench's metric.
pub const RELMSE_FLOOR: f64 = 0.01;

/// Each run's image I = (A + B)/2 and, per value, the variance of I estimated from its halves,
/// V = (A − B)²/4.
fn means_and_variances(runs: &[PilotRun]) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let per_value = |f: &dyn Fn(f64, f64) -> f64| -> Vec<Vec<f64>> {
        runs.iter()
            .map(|r| r.halves[0].iter().zip(&r.halves[1]).map(|(a, b)| f(*a as f64, *b as f64)).collect())
            .collect()
    };
    (per_value(&|a, b| 0.5 * (a + b)), per_value(&|a, b| 0.25 * (a - b) * (a - b)))
}

/// mean_j x_j / (r_j² + 0.01): relMSE's form over the values `x` against the reference `r`.
fn relative(x: impl Iterator<Item = f64>, reference: &[f64]) -> f64 {
    let sum: f64 = x.zip(reference).map(|(x, r)| x / (r * r + RELMSE_FLOOR)).sum();
    sum / reference.len().max(1) as f64
}

/// The pilot's reference image, for relMSE's denominators: the runs' images combined with
/// weights 1/(the halves' relMSE estimate against their plain average), so that the least
/// noisy image dominates (a noisy reference would put its noise, correlated with the images
/// it is made of, into every denominator). A run whose halves agree exactly (a black image)
/// weighs nothing, unless all do.
pub fn reference(runs: &[PilotRun]) -> Vec<f64> {
    let (mean, variance) = means_and_variances(runs);
    let n = mean.first().map_or(0, Vec::len);
    let combine = |weights: &[f64]| -> Vec<f64> {
        let total: f64 = weights.iter().sum();
        (0..n).map(|j| weights.iter().zip(&mean).map(|(w, m)| w * m[j]).sum::<f64>() / total).collect()
    };
    let average = combine(&vec![1.0; runs.len()]);
    let weights: Vec<f64> = variance
        .iter()
        .map(|v| relative(v.iter().copied(), &average))
        .map(|h| if h > 0.0 { 1.0 / h } else { 0.0 })
        .collect();
    if weights.iter().all(|w| *w == 0.0) {
        average
    } else {
        combine(&weights)
    }
}

/// Each candidate's error after its pilot ([`Assessment`]), from the halves A, B of every run
/// (all the same size), per value j (a pixel's channel), with I, V as [`means_and_variances`]
/// and R the pilot's [`reference`]:
/// - the halves' estimate mean_j V_j / (R_j² + 0.01);
/// - the light it misses: the largest over the other runs o of the mean over [`BLOCK`]² pixel
///   blocks b (each channel, each block weighted by its values) of
///   [`missing_in_block`]`(D_b, Var(D_b))` / (R_b² + 0.01), with D_b the block's mean of
///   I_o − I, its variance from the halves Σ_b (V_o + V) / |b|², and R_b the block's mean
///   reference (at least 0): the squared light missing where a block's deficit is significant.
///   Over a block, not a pixel: a pixel of a short pilot has a few samples, and their
///   distribution is skewed (mostly dim, now and then bright), which would read as light
///   missing; a block's mean of many is nearly symmetric. Every candidate is
///   unbiased and every contribution non-negative, so a short pilot's heavy tail shows as light
///   missing — an image darker than another's by more than their noise — never as light in
///   excess. (Another run's firefly is held half against this one; its own halves hold it whole
///   against it. The reference's own noise, correlated with the images compared, leaves a bias
///   of about 1 % of the noisier image's variance, `tests`.)
pub fn assess(runs: &[PilotRun], width: u32) -> Vec<Assessment> {
    let (mean, variance) = means_and_variances(runs);
    let r = reference(runs);
    let blocks = blocks(r.len(), width);
    (0..runs.len())
        .map(|k| {
            let halves_relmse = relative(variance[k].iter().copied(), &r);
            let missing_relmse = (0..runs.len())
                .filter(|o| *o != k)
                .map(|o| {
                    // Over each block: the mean difference, the variance of that mean, the
                    // reference's mean; each block's term counts for its values.
                    let sum: f64 = blocks
                        .iter()
                        .map(|values| {
                            let m = values.len() as f64;
                            let d = values.iter().map(|&j| mean[o][j] - mean[k][j]).sum::<f64>() / m;
                            let v = values.iter().map(|&j| variance[o][j] + variance[k][j]).sum::<f64>()
                                / (m * m);
                            let rb = values.iter().map(|&j| r[j]).sum::<f64>() / m;
                            m * missing_in_block(d, v) / (rb * rb + RELMSE_FLOOR)
                        })
                        .sum();
                    sum / r.len().max(1) as f64
                })
                .fold(0.0, f64::max);
            Assessment { method: runs[k].method, seconds: runs[k].seconds, halves_relmse, missing_relmse }
        })
        .collect()
}

/// How many of its standard deviations a block's deficit must exceed to count as light missing
/// ([`missing_in_block`]).
pub const MISSING_SIGNIFICANCE: f64 = 3.0;

/// The squared light missing from a block whose mean is `d` below another candidate's, the
/// variance of that difference `v` (from the halves): `d² − v/2` where `d` exceeds
/// [`MISSING_SIGNIFICANCE`] standard deviations, else nothing. Without the threshold, the
/// positive part's square less half the variance is unbiased for noise symmetric about 0; but a
/// short pilot's Metropolis image is skewed (its chains visit some blocks often and others not
/// yet), so its blocks are brighter than another's by chance more often than darker, and every
/// other candidate read as missing a little light everywhere (seen: the path tracer "missing" as
/// much as its own variance on Sibenik and Sponza, where it misses nothing, and not chosen there).
/// Light truly missing — a caustic no path of the method carries, a tail not yet sampled — is
/// many deviations beyond the noise in the blocks it lights, and counts whole.
#[inline]
pub fn missing_in_block(d: f64, v: f64) -> f64 {
    if d > MISSING_SIGNIFICANCE * v.max(0.0).sqrt() {
        d * d - 0.5 * v
    } else {
        0.0
    }
}

/// The side of the square blocks of pixels over which [`assess`] compares the candidates' images.
pub const BLOCK: u32 = 4;

/// The values (indices into linear rgb of `values` values, `width` pixels a row) of each
/// [`BLOCK`] × [`BLOCK`] block of pixels, a list per block and channel (the edges' blocks
/// smaller).
fn blocks(values: usize, width: u32) -> Vec<Vec<usize>> {
    let width = width.max(1) as usize;
    let height = (values / 3).div_ceil(width);
    let b = BLOCK as usize;
    let mut out = Vec::new();
    for by in (0..height).step_by(b) {
        for bx in (0..width).step_by(b) {
            for c in 0..3 {
                let block: Vec<usize> = (by..(by + b).min(height))
                    .flat_map(|y| (bx..(bx + b).min(width)).map(move |x| 3 * (y * width + x) + c))
                    .filter(|&j| j < values)
                    .collect();
                if !block.is_empty() {
                    out.push(block);
                }
            }
        }
    }
    out
}

/// The candidate of `assessments` predicted to reach the least relMSE in a render of `seconds`
/// with `pixels` times the pilot's pixels ([`Assessment::predicted_relmse`]); a candidate whose
/// prediction is not a positive number (an image the pilot found black, say) is never preferred
/// to one whose is, and where none has one, the paper's naive chains.
pub fn most_efficient(assessments: &[Assessment], seconds: f64, pixels: f64) -> Method {
    let predicted = |a: &Assessment| a.predicted_relmse(seconds, pixels);
    assessments
        .iter()
        .filter(|a| predicted(a).is_finite() && predicted(a) > 0.0)
        .min_by(|a, b| predicted(a).total_cmp(&predicted(b)))
        .map_or(Method::NAIVE, |a| a.method)
}

/// The most bootstrap samples a pilot's Metropolis render traces: a quarter of the default.
/// Its b then carries about 3 % relative error, some 10⁻³ of relMSE, against the pilot's own
/// 0.1–0.4 (docs/results.md), and its four bootstraps cost a quarter as much.
pub const PILOT_BOOTSTRAP: u32 = DEFAULT_BOOTSTRAP / 4;

/// The settings of `method`'s pilot render, half `half` (0 or 1), for a render with `s`: the
/// view at most [`PILOT_WIDTH`] wide, two seeds of its own per candidate, the whole chains (no
/// shard), at most [`PILOT_BOOTSTRAP`] bootstrap samples, and `budget`.
pub fn pilot_settings(s: &Settings, method: Method, half: u32, budget: Budget) -> Settings {
    let width = s.width.min(PILOT_WIDTH);
    let height = ((s.height as f64 * width as f64 / s.width as f64).round() as u32).max(1);
    let index = CANDIDATES.iter().position(|m| *m == method).unwrap_or(CANDIDATES.len()) as u32;
    let mut pilot = Settings {
        width,
        height,
        seed: s.seed.wrapping_mul(0x9e37_79b9).wrapping_add(0x0a17_0000 + 2 * index + half),
        budget,
        shard: Shard::WHOLE,
        ..s.clone().with_method(method)
    };
    if let Some(m) = pilot.metropolis_mut() {
        m.chains.bootstrap_samples = m.chains.bootstrap_samples.min(PILOT_BOOTSTRAP);
    }
    pilot
}

/// Each pilot render's budget for a render with `budget`: an equal share of [`PILOT_SHARE`] of
/// a `--time` budget (at least [`PILOT_MIN_SECONDS`] in all), or [`PILOT_MUTATIONS_SHARE`] of a
/// `--mutations-per-pixel` budget.
pub fn pilot_budget(budget: Budget) -> Budget {
    let renders = (2 * CANDIDATES.len()) as f64;
    match budget {
        Budget::Seconds(t) => Budget::Seconds((t * PILOT_SHARE).max(PILOT_MIN_SECONDS) / renders),
        Budget::MutationsPerPixel(m) => Budget::MutationsPerPixel(m * PILOT_MUTATIONS_SHARE),
    }
}

/// The budget left for the render after a pilot of `pilot_seconds` (wall): a `--time` budget
/// less the pilot, but never under a quarter of it; a `--mutations-per-pixel` budget whole.
pub fn remaining_budget(budget: Budget, pilot_seconds: f64) -> Budget {
    match budget {
        Budget::Seconds(t) => Budget::Seconds((t - pilot_seconds).max(0.25 * t)),
        b => b,
    }
}

/// Makes a backend for a render with the given parameters ([`super::new_backend`]).
pub type MakeBackend<'a> = dyn FnMut(&RenderParams) -> Result<Box<dyn Backend + 'a>, RenderError> + 'a;

/// Runs the pilot for a render of `scene` with `s` (its method is ignored) on backends that
/// `backend` makes, one at a time, and chooses.
pub fn choose<'a>(
    scene: &'a SceneData,
    s: &Settings,
    backend: &mut MakeBackend<'a>,
) -> Result<Choice, RenderError> {
    let begin = Instant::now();
    let budget = pilot_budget(s.budget);
    let mut runs = Vec::new();
    let mut size = (0, 0);
    // The kernels' compilation (a Vulkan driver's, first use only) is before the clock, as a
    // render's is.
    let mut compile = 0.0;
    for method in CANDIDATES {
        let mut halves = [Vec::new(), Vec::new()];
        let mut seconds = 0.0;
        for half in 0..2 {
            let p = pilot_settings(s, method, half, budget);
            size = (p.width, p.height);
            let mut b = backend(&super::base_params(scene, &p))?;
            let image = render_with(scene, &p, b.as_mut(), |_: f64| {}, Preparation::Fast)?;
            seconds += image.stats.render_seconds;
            compile += image.stats.compile_seconds.unwrap_or(0.0);
            halves[half as usize] = image.rgb;
        }
        runs.push(PilotRun { method, halves, seconds });
    }
    let assessments = assess(&runs, size.0);
    let seconds = begin.elapsed().as_secs_f64() - compile;
    let pixels = (s.width as f64 * s.height as f64) / (size.0 as f64 * size.1 as f64);
    // A `--mutations-per-pixel` render's seconds: the candidates' pilot halves' mean, scaled
    // from the pilot's share of the work and its pixels.
    let render_seconds = match remaining_budget(s.budget, seconds) {
        Budget::Seconds(t) => t,
        Budget::MutationsPerPixel(_) => {
            let pilot = assessments.iter().map(|a| a.seconds / 2.0).sum::<f64>() / assessments.len() as f64;
            pilot / PILOT_MUTATIONS_SHARE * pixels
        }
    };
    Ok(Choice {
        method: most_efficient(&assessments, render_seconds, pixels),
        assessments,
        seconds,
        width: size.0,
        height: size.1,
        render_seconds,
        pixels,
    })
}

#[cfg(test)]
mod tests;
