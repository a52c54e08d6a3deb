//! The CPU backend (`--device cpu`): the very kernel bodies the device runs, over host buffers.
//!
//! The chains are cut into fixed groups of about [`GROUP_CANDIDATES`] candidates each
//! ([`CpuBuffers`]: one group's buffers, the same layout as the device's). An iteration walks
//! the same [`Stage`]s as the device: `mutate`, `trace`, `connect` and `select` of each group
//! run as one task on a rayon pool of `--threads` threads (the groups in parallel, so threads
//! meet once per iteration), and `splat` adds the groups' records to the f64 image one group
//! after the other.
//! The partition does not depend on the thread count and the sums run in a fixed order, so the
//! image is the same bit for bit with any number of threads.

use std::sync::Arc;

use glam::Vec4;
use rayon::prelude::*;
use shared::mmlt::ChainState;
use shared::params::RenderParams;
use shared::path_tracer::PathTracerParams;
use shared::ray_caster::RayCaster;
use shared::scene::Scene;

use kernels::connect::ConnectIo;
use kernels::mutate::MutateIo;
use kernels::select::SelectIo;
use kernels::splat::SplatIo;
use kernels::stage::Bound;
use kernels::trace::TraceIo;

use super::{Accumulation, Backend, RenderError};
use crate::caster::HostCaster;
use crate::passes::buffers::{IterationBuffers, OnHost};
use crate::passes::{self, Stage};
use crate::render::gpu::PassTimes;
use crate::scene::SceneData;

/// Candidates per group of chains (at least one chain per group).
pub const GROUP_CANDIDATES: u32 = 128;

/// One group's host buffers (the device's layout, `passes::buffers`) over a scene with its
/// ray caster, and the stages over them.
pub struct CpuBuffers<'a, R> {
    scene: Scene<'a, R>,
    /// What the stages read and write.
    pub iteration: IterationBuffers<OnHost>,
    /// Ĩ per pixel (the pixel importance), shared by every group.
    pub importance: Arc<[f32]>,
}

impl<'a, R: RayCaster + Sync> CpuBuffers<'a, R> {
    /// Allocates the buffers for `params`, reading the pixel importance `importance`.
    pub fn new(scene: Scene<'a, R>, params: &RenderParams, importance: Arc<[f32]>) -> Self {
        Self { scene, iteration: IterationBuffers::new(&mut OnHost, params), importance }
    }

    /// Runs `stage` over these buffers: the kernel body once per invocation, in order, over
    /// the bindings its declaration takes by name (the splat stage adds the records to `image`,
    /// an f64 rgb image).
    pub fn run(&mut self, stage: Stage, params: &RenderParams, image: &mut [f64]) {
        let b = &mut self.iteration;
        let bound = Bound {
            params,
            chain_u: &mut b.chain_u,
            chains: &mut b.chains,
            cand_u: &mut b.cand_u,
            cand_depth: &mut b.cand_depth,
            vertices: &mut b.vertices,
            paths: &mut b.paths,
            contributions: &mut b.contributions,
            splats: &mut b.splats,
            importance: &self.importance,
            image,
            scene: self.scene,
        };
        let n = stage.invocations(params) as usize;
        match stage {
            Stage::Mutate => MutateIo::from_bound(bound).run(n),
            Stage::Trace => TraceIo::from_bound(bound).run(n),
            Stage::Connect => ConnectIo::from_bound(bound).run(n),
            Stage::Select => SelectIo::from_bound(bound).run(n),
            Stage::Splat => SplatIo::from_bound(bound).run(n),
        }
    }

    /// Traces `params.candidates` bootstrap samples (mutate, trace and connect in bootstrap
    /// mode) and returns their contributions and depths (the multiplexed sample's path depth;
    /// the path estimator's vertices read, which its chain starts from).
    pub fn bootstrap(&mut self, params: &RenderParams) -> (Vec<Vec4>, Vec<u32>) {
        for stage in [Stage::Mutate, Stage::Trace, Stage::Connect] {
            self.run(stage, params, &mut []);
        }
        let c = params.candidates as usize;
        (self.iteration.contributions[..c].to_vec(), self.iteration.cand_depth[..c].to_vec())
    }
}

/// One group of chains: its part of the dispatch and its buffers.
struct Group<'a> {
    /// First chain of the group within the backend's chains.
    first: u32,
    /// Chains in the group.
    chains: u32,
    buffers: CpuBuffers<'a, HostCaster<'a>>,
}

/// The dispatch parameters of `chains` chains from `first` on within `params`.
fn group_params(params: &RenderParams, first: u32, chains: u32) -> RenderParams {
    RenderParams {
        chains,
        candidates: chains * params.candidates_per_chain(),
        chain_offset: params.chain_offset + first,
        ..*params
    }
}

impl Group<'_> {
    /// The dispatch parameters of this group within `params` (the backend's chains).
    fn params(&self, params: &RenderParams) -> RenderParams {
        group_params(params, self.first, self.chains)
    }
}

/// The host backend: groups of chains on a pool of threads.
pub struct CpuBackend<'a> {
    scene: Scene<'a, HostCaster<'a>>,
    groups: Vec<Group<'a>>,
    pool: rayon::ThreadPool,
    threads: usize,
    chains: u32,
    dims: u32,
    image: Vec<f64>,
    /// The path tracer's round, summed per pixel in f32 as the kernel body does, then added to
    /// the f64 image (a device sums several rounds in f32 before its drain).
    round: Vec<f32>,
}

/// Threads of `--threads` when absent: every core.
pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// A pool of `threads` threads.
pub fn thread_pool(threads: usize) -> Result<rayon::ThreadPool, RenderError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| RenderError::Threads(e.to_string()))
}

impl<'a> CpuBackend<'a> {
    /// Allocates the groups' buffers for `params` and a pool of `threads` threads.
    pub fn new(scene: &'a SceneData, params: &RenderParams, threads: usize) -> Result<Self, RenderError> {
        super::host_memory::check(params.width, params.height, super::host_memory::available())?;
        // The path tracer's parameters hold no chains (and so no candidates per chain): no groups.
        let per_group = (GROUP_CANDIDATES / params.candidates_per_chain().max(1)).max(1);
        let mut groups = Vec::new();
        let mut first = 0;
        let ones: Arc<[f32]> = vec![1.0; (params.width * params.height) as usize].into();
        while first < params.chains {
            let chains = per_group.min(params.chains - first);
            let buffers = CpuBuffers::new(scene.shared(), &group_params(params, first, chains), ones.clone());
            groups.push(Group { first, chains, buffers });
            first += chains;
        }
        Ok(Self {
            scene: scene.shared(),
            groups,
            pool: thread_pool(threads)?,
            threads,
            chains: params.chains,
            dims: params.dims,
            image: vec![0.0; (params.width * params.height) as usize * 3],
            round: Vec::new(),
        })
    }
}

impl CpuBackend<'_> {
    /// One iteration stage by stage — each stage over every group before the next — with each
    /// stage's wall time (the bench's look inside an iteration). The image is the same as
    /// [`Backend::iterate`]'s: every group's stages still run in order, the splats in group order.
    pub fn iterate_timed(&mut self, params: &RenderParams) -> PassTimes {
        let mut times = [0.0; Stage::COUNT];
        for stage in Stage::ITERATION {
            let start = std::time::Instant::now();
            if stage == Stage::Splat {
                for g in &mut self.groups {
                    let p = g.params(params);
                    g.buffers.run(stage, &p, &mut self.image);
                }
            } else {
                let groups = &mut self.groups;
                self.pool.install(|| {
                    groups.par_iter_mut().for_each(|g| {
                        let p = g.params(params);
                        g.buffers.run(stage, &p, &mut []);
                    })
                });
            }
            times[stage.index()] = start.elapsed().as_secs_f64();
        }
        times
    }

    /// Each group's dispatch parameters within `params`, candidate samples and depths (as the
    /// last `mutate` left them; the path estimator's depths as its last `connect` left them).
    pub fn candidates(&self, params: &RenderParams) -> Vec<(RenderParams, &[f32], &[u32])> {
        self.groups
            .iter()
            .map(|g| (g.params(params), &g.buffers.iteration.cand_u[..], &g.buffers.iteration.cand_depth[..]))
            .collect()
    }

    /// Threads in the backend's rayon pool.
    pub fn threads(&self) -> usize {
        self.threads
    }
}

impl Backend for CpuBackend<'_> {
    /// The path tracer's round over the pixels on the pool, into an f32 round (as the device
    /// sums a pixel's samples), added to the f64 image.
    fn trace_path_tracer_round(&mut self, params: &PathTracerParams) -> Result<(), RenderError> {
        self.round.clear();
        self.round.resize(self.image.len(), 0.0);
        let (scene, round) = (self.scene, &mut self.round);
        self.pool.install(|| passes::path_tracer::cpu(params, scene, round));
        for (a, v) in self.image.iter_mut().zip(&self.round) {
            *a += *v as f64;
        }
        Ok(())
    }

    fn start(
        &mut self,
        chain_u: &[f32],
        chains: &[ChainState],
        importance: &[f32],
    ) -> Result<(), RenderError> {
        let n = self.chains as usize;
        let importance: Arc<[f32]> = importance.into();
        for g in &mut self.groups {
            g.buffers.importance = importance.clone();
            let (first, count) = (g.first as usize, g.chains as usize);
            g.buffers.iteration.chains.copy_from_slice(&chains[first..first + count]);
            for dim in 0..self.dims as usize {
                g.buffers.iteration.chain_u[dim * count..(dim + 1) * count]
                    .copy_from_slice(&chain_u[dim * n + first..dim * n + first + count]);
            }
        }
        Ok(())
    }

    fn iterate(&mut self, params: &RenderParams) -> Result<(), RenderError> {
        // Every stage but the splat, group by group in parallel (a group's stages one after the
        // other, so threads meet once per iteration)...
        let (per_group, splat) = Stage::ITERATION.split_at(Stage::Splat.index());
        let groups = &mut self.groups;
        self.pool.install(|| {
            groups.par_iter_mut().for_each(|g| {
                let p = g.params(params);
                for &stage in per_group {
                    g.buffers.run(stage, &p, &mut []);
                }
            })
        });
        // ...then the splats into the one image, group after group: a fixed order of the sums.
        for g in &mut self.groups {
            let p = g.params(params);
            for &stage in splat {
                g.buffers.run(stage, &p, &mut self.image);
            }
        }
        Ok(())
    }

    fn drain(&mut self, acc: &mut Accumulation) -> Result<(), RenderError> {
        for (a, v) in acc.image.iter_mut().zip(self.image.iter_mut()) {
            *a += *v;
            *v = 0.0;
        }
        for g in &mut self.groups {
            for chain in &mut g.buffers.iteration.chains {
                acc.drain_chain(chain);
            }
        }
        Ok(())
    }

    fn thread_pool(&self) -> Option<&rayon::ThreadPool> {
        Some(&self.pool)
    }

    fn describe(&self) -> String {
        let caster = self.scene.caster.describe();
        format!(
            "CPU ({} thread{}; the kernel bodies on the host, rays through {caster})",
            self.threads,
            if self.threads == 1 { "" } else { "s" }
        )
    }
}
