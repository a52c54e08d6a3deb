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
//! Both are relative errors against the pilot's own [`reference()`], the median of the halves. A
//! path tracer whose error sits in a few fireflies has met a tail its pilot cannot measure
//! ([`Assessment::met_fireflies`]) and is not chosen while another candidate has a prediction.
//!
//! From them each candidate's relMSE (as the bench measures it) is predicted for the render
//! ahead ([`Assessment::predicted_relmse`]: the variance scaled to the render's time and
//! pixels, the light missing kept), and the candidate predicted best renders the image: the render is
//! `--method <chosen>`'s with the same seed, so that it can be reproduced, and where the pilot
//! rendered at the render's size (a render at most [`PILOT_WIDTH`] wide, not a shard) the
//! chosen candidate's pilot image is pooled into it ([`KeptPilot`]); a larger render's pilot is
//! smaller than its image and is not kept. The pilot's wall time counts against a `--time`
//! budget. Its Metropolis renders prepare their chains (the pixel importance and the bootstrap)
//! through the CPU's fastest caster: a pilot is never sharded, and through the device's own
//! traversal, which a render's preparation takes so that its shards agree, the four
//! preparations were most of the pilot (2.7 s of an 8 s render on Sibenik, 0.84 s of it
//! rendering). Their pixel importance is the path tracer's pilot image, which the pilot renders
//! first ([`Preparation::FastFrom`]): each estimating its own took as long again as it rendered.

use std::borrow::Cow;
use std::time::Instant;

use glam::Vec3;
use shared::color::luminance;
use shared::params::RenderParams;

use super::{
    render_with, Backend, Budget, Method, Preparation, RenderError, Rendered, Settings, Shard,
    DEFAULT_BOOTSTRAP,
};
use crate::scene::SceneData;

/// The methods the pilot weighs: the path tracer, and the paper's naive chains (the
/// speculative trees and reject chains parallelise the same chains; on these cores they do not
/// pay, docs/results.md).
///
/// Not the chains over the path tracer's estimate (`path-naive`), though they are the best
/// method on `sunblind` (1.5× `pt`): their chains stick on the path tracer's fireflies — a
/// chain started on one (the bootstrap draws start states in proportion to their values) stays
/// there for thousands of steps — and no pilot sees it. On the atrium's views 5 of 6 renders of
/// 8 s carried such a blot (relMSE 0.05–0.49 against naive's 0.009–0.019) and 16 of 16 pilots
/// showed none; with the render's 65 536 bootstrap samples 2 of 6 two-second renders of the
/// atrium did (0.16 and 3.0), with the pilot's 8192 none (0.021–0.024,
/// `results/cpu-path/auto/pilot_reference.md`). Chosen on the banner view by one pilot of
/// three, it rendered at a quarter of `pt`'s efficiency.
pub const CANDIDATES: [Method; 2] = [Method::PathTracer, Method::NAIVE];

/// The widest pilot image: the pilot renders the view at most this wide (its aspect kept), so
/// that a short pilot has enough samples in each pixel to compare.
pub const PILOT_WIDTH: u32 = 128;

/// The pilot's render seconds for a `--time` budget of t seconds are √(PILOT_SCALE_SECONDS · t)
/// (at least [`PILOT_MIN_SECONDS`]): a tenth of an 8 s render, 2.2 s (4 %) of a minute's, 6.9 s
/// (1 %) of ten minutes'. Its choice grows surer with its length, and what it costs the render
/// is its share: a fixed share (it was a tenth) spent a minute of a ten-minute render on a
/// 128-pixel pilot, and capped at 0.9 auto's efficiency against the best method's.
pub const PILOT_SCALE_SECONDS: f64 = 0.08;

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
    /// Candidates (paths, for the path tracer) each half traced.
    pub candidates: [u64; 2],
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
    /// The share of `halves_relmse` in its largest [`FIREFLY_VALUES`] of the values
    /// ([`firefly_share`]).
    pub firefly_share: f64,
}

impl Assessment {
    /// Whether its pilot met fireflies: a path tracer (independent samples: for chains, whose
    /// images are clumped, a concentrated error is their nature and their halves measure it) whose
    /// halves' error lies at least [`FIREFLY_SHARE`] in its largest [`FIREFLY_VALUES`] of the
    /// values. Such an error is a handful of rare samples: the pilot cannot say how rare or how
    /// large the next ones are, so its prediction is no measurement ([`most_efficient`]).
    /// Measured: on the atrium, where the sun's caustic off the banner makes the path tracer
    /// 12× less efficient than the naive chains after 8 s, 7 of 8 pilots had 0.96–0.999 of its
    /// error in 0.1 % of the values; on Sibenik, Sponza, the banner view, `sunblind` and `slit`
    /// 0.07–0.43 (`results/cpu-path/auto/pilot_reference.md`).
    pub fn met_fireflies(&self) -> bool {
        self.method == Method::PathTracer && self.firefly_share >= FIREFLY_SHARE
    }
}

/// The share of the values ([`Assessment::firefly_share`]) whose error makes a firefly: 0.1 %.
pub const FIREFLY_VALUES: f64 = 0.001;

/// The share of a path tracer's error in its largest [`FIREFLY_VALUES`] of the values beyond
/// which its pilot met fireflies ([`Assessment::met_fireflies`]).
pub const FIREFLY_SHARE: f64 = 0.9;

/// The share of the sum of the non-negative `terms` in its largest ⌈[`FIREFLY_VALUES`] · n⌉
/// (0 for a zero sum); reorders `terms`.
pub fn firefly_share(terms: &mut [f64]) -> f64 {
    let total: f64 = terms.iter().sum();
    if !(total > 0.0) {
        return 0.0;
    }
    let top = ((terms.len() as f64 * FIREFLY_VALUES).ceil() as usize).clamp(1, terms.len());
    terms.select_nth_unstable_by(top - 1, |a, b| b.total_cmp(a));
    terms[..top].iter().sum::<f64>() / total
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
    /// The chosen candidate's pilot samples, where the render keeps them ([`KeptPilot::of`]).
    pub kept: Option<KeptPilot>,
}

/// The chosen candidate's pilot image, which the render keeps: both halves are the chosen
/// method's own estimates of the render's pixels, rendered with seeds of their own, so pooled
/// with the render's image ([`pooled`]) they are as unbiased as it is and less noisy. A path
/// tracer's pilot is pooled exactly (its paths are the render's kind); a Metropolis pilot's
/// chains are fewer than the render's ([`pilot_settings`]) but estimate the same image, and its
/// weight is its share of the candidates (some 5 % in an 8 s render: half of a pilot of a tenth
/// of it; less in longer ones, whose pilot is a smaller share).
#[derive(Clone, Debug)]
pub struct KeptPilot {
    /// Linear rgb: the halves pooled by their candidates.
    pub rgb: Vec<f32>,
    /// Candidates both halves traced.
    pub candidates: u64,
}

impl KeptPilot {
    /// The pilot of `chosen` among `runs`, for a render of `s` at the pilot's size
    /// (`width` × `height`): kept where the pilot's image is the render's (a render at most
    /// [`PILOT_WIDTH`] wide) and the render is whole. A shard's pilot is not kept: every shard
    /// renders its own, and the parts merge into the unsplit render of the method chosen
    /// (`smlt merge`), which has none.
    pub fn of(runs: &[PilotRun], chosen: Method, s: &Settings, width: u32, height: u32) -> Option<KeptPilot> {
        if (width, height) != (s.width, s.height) || s.shard != Shard::WHOLE {
            return None;
        }
        let run = runs.iter().find(|r| r.method == chosen)?;
        let halves = [(&run.halves[0][..], run.candidates[0]), (&run.halves[1][..], run.candidates[1])];
        Some(KeptPilot { rgb: pooled(&halves), candidates: run.candidates.iter().sum() })
    }

    /// The render's image `rgb`, of `candidates` candidates, with the pilot's pooled in
    /// ([`pooled`]).
    pub fn pooled_with(&self, rgb: &[f32], candidates: u64) -> Vec<f32> {
        pooled(&[(&self.rgb, self.candidates), (rgb, candidates)])
    }

    /// The linear rgb of `rendered` with `kept` pooled in where there is one.
    pub fn image<'r>(kept: Option<&KeptPilot>, rendered: &'r Rendered) -> Cow<'r, [f32]> {
        match kept {
            Some(k) => Cow::Owned(k.pooled_with(&rendered.rgb, rendered.stats.candidates)),
            None => Cow::Borrowed(&rendered.rgb),
        }
    }
}

/// Images of the same pixels by one method, each with the candidates it traced, pooled: their
/// mean weighted by the candidates. A path tracer's image is its pixels' sample means, so this
/// is the mean of all their samples; for a Metropolis image it weighs each by its share of the
/// mutations. Images with no candidates are left out; none at all give black.
pub fn pooled(images: &[(&[f32], u64)]) -> Vec<f32> {
    let n = images.first().map_or(0, |(rgb, _)| rgb.len());
    let total: u64 = images.iter().map(|(_, c)| c).sum();
    let mut out = vec![0.0f64; n];
    for (rgb, c) in images.iter().filter(|(_, c)| *c > 0) {
        let w = *c as f64 / total as f64;
        for (o, v) in out.iter_mut().zip(rgb.iter()) {
            *o += w * *v as f64;
        }
    }
    out.into_iter().map(|v| v as f32).collect()
}

impl Choice {
    /// One line for the render summary: what was chosen, and why.
    pub fn describe(&self) -> String {
        let each: Vec<String> = self
            .assessments
            .iter()
            .map(|a| {
                let guard = match (a.met_fireflies(), a.missing_relmse > a.halves_relmse) {
                    (true, _) => ", fireflies",
                    (false, true) => ", missing light",
                    (false, false) => "",
                };
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

/// x_j / (r_j² + 0.01) for each value: relMSE's terms of the squared errors `x` against the
/// reference `r`.
pub fn relative_terms(x: impl Iterator<Item = f64>, reference: &[f64]) -> Vec<f64> {
    x.zip(reference).map(|(x, r)| x / (r * r + RELMSE_FLOOR)).collect()
}

/// mean_j x_j / (r_j² + 0.01): relMSE of the squared errors `x` against the reference `r`
/// ([`relative_terms`]' mean).
pub fn relative(x: impl Iterator<Item = f64>, reference: &[f64]) -> f64 {
    relative_terms(x, reference).iter().sum::<f64>() / reference.len().max(1) as f64
}

/// The pilot's reference image, for relMSE's denominators: per value, the median of every
/// run's halves (all candidates' together). A reference for relative errors must not hold the
/// noise of the images it measures: a firefly in its denominator hides itself. The first pilot
/// combined the runs' means weighted by their precision, which let the least noisy run — a
/// path tracer whose half had met a caustic path, or a Metropolis image — dominate, and so
/// measure its own error against itself: on the atrium the path tracer's halves read 0.02
/// where, against the true image, they were 0.6–10; on `sunblind` the naive chains' 0.1 where
/// they were 0.6–1.2. The median of the halves ignores a firefly in any one and carries no
/// run's noise whole; against it every candidate's estimate follows its error against the true
/// image, in the same proportion for all (`results/cpu-path/auto/pilot_reference.md`).
pub fn reference(runs: &[PilotRun]) -> Vec<f64> {
    let n = runs.first().map_or(0, |r| r.halves[0].len());
    let mut values = Vec::with_capacity(2 * runs.len());
    (0..n)
        .map(|j| {
            values.clear();
            values.extend(runs.iter().flat_map(|r| r.halves.iter().map(move |h| h[j] as f64)));
            median(&mut values)
        })
        .collect()
}

/// The median of `values` (the mean of the middle two of an even count; 0 for none), which it
/// reorders.
pub fn median(values: &mut [f64]) -> f64 {
    let n = values.len();
    if n == 0 {
        return 0.0;
    }
    values.sort_unstable_by(f64::total_cmp);
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

/// Each candidate's error after its pilot ([`Assessment`]), from the halves A, B of every run
/// (all the same size), per value j (a pixel's channel), with I, V as `means_and_variances` makes them
/// and R the pilot's [`reference()`]:
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
///   against it.)
pub fn assess(runs: &[PilotRun], width: u32) -> Vec<Assessment> {
    let (mean, variance) = means_and_variances(runs);
    let r = reference(runs);
    let blocks = blocks(r.len(), width);
    (0..runs.len())
        .map(|k| {
            let mut terms = relative_terms(variance[k].iter().copied(), &r);
            let halves_relmse = terms.iter().sum::<f64>() / r.len().max(1) as f64;
            let firefly_share = firefly_share(&mut terms);
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
            Assessment {
                method: runs[k].method,
                seconds: runs[k].seconds,
                halves_relmse,
                missing_relmse,
                firefly_share,
            }
        })
        .collect()
}

/// How many of its standard deviations a block's deficit must exceed to count as light missing
/// ([`missing_in_block`]). At 3 the chance deficits of some 1700 block-channels of a 128×72
/// pilot, estimated from two halves each, read on `slit` as a path tracer's missing light up to
/// 2.4× its variance (the light-through-a-gap view, where nothing is missing; seen choosing
/// `naive` there, at 0.65× `pt`'s efficiency); at 5 at most 0.15 of it, and the spot's
/// caustic through glass that the path tracer cannot render reads the same (5–7 × 10⁻³ in six
/// pilots at 3, 4 and 5: `cargo run --release --example pilot`, with the threshold varied).
pub const MISSING_SIGNIFICANCE: f64 = 5.0;

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
/// with `pixels` times the pilot's pixels ([`Assessment::predicted_relmse`]), among those whose
/// pilot met no fireflies ([`Assessment::met_fireflies`]) where there is one; a candidate whose
/// prediction is not a positive number (an image the pilot found black, say) is never preferred
/// to one whose is, and where none has one, the paper's naive chains.
pub fn most_efficient(assessments: &[Assessment], seconds: f64, pixels: f64) -> Method {
    let predicted = |a: &Assessment| a.predicted_relmse(seconds, pixels);
    let measured = |a: &&Assessment| predicted(a).is_finite() && predicted(a) > 0.0;
    let calm: Vec<&Assessment> = assessments.iter().filter(measured).filter(|a| !a.met_fireflies()).collect();
    let pool = if calm.is_empty() { assessments.iter().filter(measured).collect() } else { calm };
    pool.into_iter().min_by(|a, b| predicted(a).total_cmp(&predicted(b))).map_or(Method::NAIVE, |a| a.method)
}

/// The most bootstrap samples a pilot's Metropolis render traces: an eighth of the default.
/// Its b then carries about 4 % relative error, some 2·10⁻³ of relMSE, against the pilot's own
/// 0.1–5 (`results/cpu-path/auto/pilot_reference.md`), and its four bootstraps cost an eighth
/// as much (with a quarter, 0.2 s of a 1.2 s pilot on Sibenik).
pub const PILOT_BOOTSTRAP: u32 = DEFAULT_BOOTSTRAP / 8;

/// The settings of `method`'s pilot render, half `half` (0 or 1), for a render with `s`: the
/// view at most [`PILOT_WIDTH`] wide, two seeds of its own per candidate, the whole chains (no
/// shard), at most [`PILOT_BOOTSTRAP`] bootstrap samples with as many chains to a sample as the
/// render's, and `budget`.
///
/// Chains that outnumber their bootstrap's samples start on the same samples and err together
/// until they part: the naive chains on the banner view after 2 s had relMSE 0.15–0.25 with
/// 4096 chains from 8192 samples, 0.077–0.098 from 65 536, and 0.080–0.089 with 512 chains
/// from either (`results/cpu-path/auto/pilot_reference.md`). A pilot with fewer samples than the
/// render's runs proportionally fewer chains, or it would measure an error the render does not
/// have (2.5–4× the render's, before).
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
        let render = m.chains.bootstrap_samples.max(1);
        m.chains.bootstrap_samples = render.min(PILOT_BOOTSTRAP);
        let scaled = s.candidates as u64 * m.chains.bootstrap_samples as u64 / render as u64;
        let per_chain = m.schedule.candidates_per_chain();
        pilot.candidates = (scaled as u32).max(per_chain);
    }
    pilot
}

/// Each pilot render's budget for a render with `budget`: an equal share of the pilot's seconds
/// for a `--time` budget ([`PILOT_SCALE_SECONDS`]), or [`PILOT_MUTATIONS_SHARE`] of a
/// `--mutations-per-pixel` budget.
pub fn pilot_budget(budget: Budget) -> Budget {
    let renders = (2 * CANDIDATES.len()) as f64;
    match budget {
        Budget::Seconds(t) => {
            Budget::Seconds((PILOT_SCALE_SECONDS * t).sqrt().max(PILOT_MIN_SECONDS) / renders)
        }
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

/// The luminance of each pixel of the mean of two linear rgb images.
fn mean_luminance(halves: &[Vec<f32>; 2]) -> Vec<f32> {
    let (a, b) = (halves[0].as_chunks::<3>().0, halves[1].as_chunks::<3>().0);
    a.iter()
        .zip(b)
        .map(|(a, b)| 0.5 * (luminance(Vec3::from_array(*a)) + luminance(Vec3::from_array(*b))))
        .collect()
}

/// Makes a backend for a render with the given parameters ([`super::new_backend`]).
pub type MakeBackend<'a> = dyn FnMut(&RenderParams) -> Result<Box<dyn Backend + 'a>, RenderError> + 'a;

/// The pilot's renders: every candidate's two halves, in [`CANDIDATES`]' order.
#[derive(Clone, Debug)]
pub struct Pilot {
    #[allow(missing_docs)]
    pub runs: Vec<PilotRun>,
    /// The pilot's image size.
    pub width: u32,
    #[allow(missing_docs)]
    pub height: u32,
    /// Seconds the backends spent compiling kernels (a Vulkan driver's, first use only), which
    /// are not the pilot's time, as they are not a render's.
    pub compile_seconds: f64,
}

/// Renders the pilot for a render of `scene` with `s` (its method is ignored) on backends that
/// `backend` makes, one at a time.
pub fn run_pilot<'a>(
    scene: &'a SceneData,
    s: &Settings,
    backend: &mut MakeBackend<'a>,
) -> Result<Pilot, RenderError> {
    let budget = pilot_budget(s.budget);
    let mut pilot = Pilot { runs: Vec::new(), width: 0, height: 0, compile_seconds: 0.0 };
    // The path tracer's pilot image, once rendered, is the Metropolis candidates' pixel
    // importance (its luminance: more samples than their own estimate would trace, and free).
    let mut luminance: Option<Vec<f32>> = None;
    for method in CANDIDATES {
        let mut halves = [Vec::new(), Vec::new()];
        let mut candidates = [0; 2];
        let mut seconds = 0.0;
        for half in 0..2 {
            let p = pilot_settings(s, method, half, budget);
            (pilot.width, pilot.height) = (p.width, p.height);
            let mut b = backend(&super::base_params(scene, &p))?;
            let preparation = luminance.as_deref().map_or(Preparation::Fast, Preparation::FastFrom);
            let image = render_with(scene, &p, b.as_mut(), |_: f64| {}, preparation)?;
            seconds += image.stats.render_seconds;
            candidates[half as usize] = image.stats.candidates;
            pilot.compile_seconds += image.stats.compile_seconds.unwrap_or(0.0);
            halves[half as usize] = image.rgb;
        }
        if method == Method::PathTracer {
            luminance = Some(mean_luminance(&halves));
        }
        pilot.runs.push(PilotRun { method, halves, seconds, candidates });
    }
    Ok(pilot)
}

/// Runs the pilot for a render of `scene` with `s` (its method is ignored) on backends that
/// `backend` makes ([`run_pilot`]), and chooses.
pub fn choose<'a>(
    scene: &'a SceneData,
    s: &Settings,
    backend: &mut MakeBackend<'a>,
) -> Result<Choice, RenderError> {
    let begin = Instant::now();
    let pilot = run_pilot(scene, s, backend)?;
    let assessments = assess(&pilot.runs, pilot.width);
    let seconds = begin.elapsed().as_secs_f64() - pilot.compile_seconds;
    let pixels = (s.width as f64 * s.height as f64) / (pilot.width as f64 * pilot.height as f64);
    // A `--mutations-per-pixel` render's seconds: the candidates' pilot halves' mean, scaled
    // from the pilot's share of the work and its pixels.
    let render_seconds = match remaining_budget(s.budget, seconds) {
        Budget::Seconds(t) => t,
        Budget::MutationsPerPixel(_) => {
            let pilot = assessments.iter().map(|a| a.seconds / 2.0).sum::<f64>() / assessments.len() as f64;
            pilot / PILOT_MUTATIONS_SHARE * pixels
        }
    };
    let method = most_efficient(&assessments, render_seconds, pixels);
    Ok(Choice {
        method,
        kept: KeptPilot::of(&pilot.runs, method, s, pilot.width, pilot.height),
        assessments,
        seconds,
        width: pilot.width,
        height: pilot.height,
        render_seconds,
        pixels,
    })
}

#[cfg(test)]
mod tests;
