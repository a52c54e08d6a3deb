//! The bootstrap: independent samples of uniform (u, depth) give the first estimate of the
//! normalisation b and the chains' start states, drawn in proportion to their targets c.
//!
//! It always runs on the host, with the kernel bodies on a thread pool, in a fixed order. A
//! render's casts its rays through the device's own traversal (`shared::cwbvh`, plain Rust,
//! whatever host caster the CPU backend uses; [`Preparation::Reproducible`]): it is a function
//! of the scene and the settings alone, so every shard of a render — on any device, with any
//! thread count, on any machine — computes the very same bootstrap (the part files carry its
//! moments, and `smlt merge` checks that they agree). Auto's pilot, which no shard shares,
//! casts through the fastest host caster ([`Preparation::Fast`]).

use std::sync::Arc;
use std::time::Instant;

use glam::Vec4;
use rayon::prelude::*;
use shared::color::luminance;
use shared::mmlt::ChainState;
use shared::normalisation::{normalisation_sample, Moments};
use shared::params::{bootstrap_sample, RenderParams, BOOTSTRAP_ITERATION, MODE_BOOTSTRAP};
use shared::ray_caster::RayCaster;
use shared::rng::{self, RngKey};
use shared::scene::Scene;

use super::cpu::CpuBuffers;
use super::{base_params, Metropolis, RenderError, Settings};
use crate::scene::SceneData;

/// Samples traced per task of the pool.
const BATCH: u32 = 4096;

/// How the host prepares the chains (the pixel importance and the bootstrap): which traversal
/// it casts its rays through, and whether the pixel importance is made from an estimate the
/// caller already holds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Preparation<'a> {
    /// The device's own traversal (`shared::cwbvh`): the same on every machine and backend,
    /// whatever host caster is installed, so that every shard of a render starts the same
    /// chains and the parts merge exactly. Every render's.
    #[default]
    Reproducible,
    /// The CPU backend's fastest caster (Embree where it is installed; 2–4× the device's
    /// traversal on the host): for renders that no other process must repeat exactly — auto's
    /// pilot, whose Metropolis candidates each prepare their chains twice.
    Fast,
    /// [`Preparation::Fast`], with the pixel importance made from this estimate of each
    /// pixel's luminance (row-major, at the render's size) instead of its own path-traced
    /// samples (`super::importance`): auto's pilot gives its path tracer's images to its
    /// Metropolis candidates, which saves each render its own estimate (on Sibenik 0.085 s, as
    /// long as the 0.14 s it then renders).
    FastFrom(&'a [f32]),
}

impl Preparation<'_> {
    /// Whether it casts through the CPU backend's fastest caster rather than the device's own
    /// traversal.
    pub fn fast(&self) -> bool {
        !matches!(self, Preparation::Reproducible)
    }
}

/// The bootstrap of a render, for the chains of its shard.
#[derive(Clone, Debug)]
pub struct Bootstrap {
    /// Moments of the bootstrap samples' targets.
    pub moments: Moments,
    /// The shard's chains' start samples, SoA (`p + i·N`).
    pub chain_u: Vec<f32>,
    /// The shard's chains' start states.
    pub chains: Vec<ChainState>,
    /// Wall seconds it took.
    pub seconds: f64,
}

/// One batch of bootstrap samples (`params` in bootstrap mode) over `view`: their contributions
/// and depths.
fn trace<R: RayCaster + Sync>(
    view: Scene<R>,
    params: &RenderParams,
    importance: &Arc<[f32]>,
) -> (Vec<Vec4>, Vec<u32>) {
    CpuBuffers::new(view, params, importance.clone()).bootstrap(params)
}

/// Traces `max(bootstrap samples, chains)` samples for the chains `m` of a render with settings
/// `s` on the current rayon pool and starts the shard's chains; the contributions are divided by
/// the pixel importance `importance` (`super::importance`).
pub fn bootstrap(
    scene: &SceneData,
    s: &Settings,
    m: &Metropolis,
    importance: &[f32],
    preparation: Preparation<'_>,
) -> Result<Bootstrap, RenderError> {
    let start = Instant::now();
    let base = base_params(scene, s);
    let importance: Arc<[f32]> = importance.into();
    let total = m.chains.bootstrap_samples.max(s.chains());
    let batches: Vec<u32> = (0..total.div_ceil(BATCH)).collect();
    let (contributions, depths): (Vec<Vec4>, Vec<u32>) = {
        let traced: Vec<(Vec<Vec4>, Vec<u32>)> = batches
            .par_iter()
            .map(|&i| {
                let offset = i * BATCH;
                let params = RenderParams {
                    mode: MODE_BOOTSTRAP,
                    chains: 1,
                    candidates: BATCH.min(total - offset),
                    sample_offset: offset,
                    ..base
                };
                if preparation.fast() {
                    trace(scene.shared(), &params, &importance)
                } else {
                    trace(scene.device_view(), &params, &importance)
                }
            })
            .collect();
        let (c, d): (Vec<_>, Vec<_>) = traced.into_iter().unzip();
        (c.concat(), d.concat())
    };
    let mut moments = Moments::default();
    let mut cdf = Vec::with_capacity(contributions.len());
    let mut running = 0.0f64;
    for v in &contributions {
        let c = luminance(v.truncate());
        moments.add(c);
        running += normalisation_sample(c) as f64;
        cdf.push(running);
    }
    if !(running > 0.0) {
        return Err(RenderError::NothingVisible(total as u64));
    }
    let shard = s.shard_chains();
    let n = base.chains;
    let mut chain_u = vec![0.0f32; (n * base.dims) as usize];
    let mut chains = vec![ChainState::default(); n as usize];
    for p in 0..n {
        let key = RngKey {
            seed: s.seed,
            chain: shard.start + p,
            iteration: BOOTSTRAP_ITERATION,
            dimension: rng::dimension(rng::STREAM_CONTROL, rng::CONTROL_BOOTSTRAP_PICK),
        };
        let target = rng::uniform(key) as f64 * running;
        let g = cdf.partition_point(|&x| x <= target).min(cdf.len() - 1) as u32;
        for dim in 0..base.dims {
            chain_u[(p + dim * n) as usize] = bootstrap_sample(s.seed, g, dim);
        }
        chains[p as usize] = ChainState {
            contribution: contributions[g as usize].to_array(),
            depth: depths[g as usize],
            ..Default::default()
        };
    }
    Ok(Bootstrap { moments, chain_u, chains, seconds: start.elapsed().as_secs_f64() })
}
