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

use glam::Vec4;
use rayon::prelude::*;
use shared::mmlt::{vertex_slots, ChainState, PathInfo, PathVertex, RenderParams, Scene};

use super::{Accumulation, Backend, RenderError};
use crate::passes::{self, Stage};
use crate::scene::SceneData;

/// Candidates per group of chains (at least one chain per group).
pub const GROUP_CANDIDATES: u32 = 128;

/// One group's host buffers (the same layout as the device's), and the stages over them.
pub struct CpuBuffers<'a> {
    scene: &'a SceneData,
    /// Chain samples, SoA.
    pub chain_u: Vec<f32>,
    /// Chain states.
    pub chains: Vec<ChainState>,
    /// Candidate samples, SoA.
    pub cand_u: Vec<f32>,
    /// Candidate path depths.
    pub cand_depth: Vec<u32>,
    /// Subpath vertices, SoA.
    pub vertices: Vec<PathVertex>,
    /// Path infos.
    pub paths: Vec<PathInfo>,
    /// Packed contributions.
    pub contributions: Vec<Vec4>,
    /// Splat records.
    pub splats: Vec<Vec4>,
}

impl<'a> CpuBuffers<'a> {
    /// Allocates the buffers for `params`.
    pub fn new(scene: &'a SceneData, params: &RenderParams) -> Self {
        let c = params.candidates as usize;
        let n = params.chains as usize;
        let dims = params.dims as usize;
        Self {
            scene,
            chain_u: vec![0.0; n * dims],
            chains: vec![ChainState::default(); n],
            cand_u: vec![0.0; c * dims],
            cand_depth: vec![0; c],
            vertices: vec![PathVertex::default(); c * vertex_slots(params.max_depth) as usize],
            paths: vec![PathInfo::default(); c],
            contributions: vec![Vec4::ZERO; c],
            splats: vec![Vec4::ZERO; kernels::splat::splat_records(params) as usize],
        }
    }

    fn scene(&self) -> Scene<'a> {
        self.scene.shared()
    }

    /// The `mutate` stage.
    pub fn mutate(&mut self, params: &RenderParams) {
        passes::mutate::cpu(params, &self.chains, &self.chain_u, &mut self.cand_u, &mut self.cand_depth);
    }

    /// The `trace` stage.
    pub fn trace(&mut self, params: &RenderParams) {
        let scene = self.scene();
        passes::trace::cpu(
            params,
            &self.cand_depth,
            &self.cand_u,
            scene,
            &mut self.vertices,
            &mut self.paths,
        );
    }

    /// The `connect` stage.
    pub fn connect(&mut self, params: &RenderParams) {
        let scene = self.scene();
        passes::connect::cpu(
            params,
            &self.cand_u,
            scene,
            &self.vertices,
            &self.paths,
            &mut self.contributions,
        );
    }

    /// The `select` stage.
    pub fn select(&mut self, params: &RenderParams) {
        passes::select::cpu(
            params,
            &mut self.chains,
            &mut self.chain_u,
            &self.cand_u,
            &self.cand_depth,
            &self.contributions,
            &mut self.splats,
        );
    }

    /// Runs `stage` over these buffers (the splat stage adds the records to `image`, an f64
    /// rgb image).
    pub fn run(&mut self, stage: Stage, params: &RenderParams, image: &mut [f64]) {
        match stage {
            Stage::Mutate => self.mutate(params),
            Stage::Trace => self.trace(params),
            Stage::Connect => self.connect(params),
            Stage::Select => self.select(params),
            Stage::Splat => passes::splat::cpu(params, &self.splats, image),
        }
    }

    /// Traces `params.candidates` bootstrap samples (mutate, trace and connect in bootstrap
    /// mode) and returns their contributions.
    pub fn bootstrap(&mut self, params: &RenderParams) -> Vec<Vec4> {
        for stage in [Stage::Mutate, Stage::Trace, Stage::Connect] {
            self.run(stage, params, &mut []);
        }
        self.contributions[..params.candidates as usize].to_vec()
    }
}

/// One group of chains: its part of the dispatch and its buffers.
struct Group<'a> {
    /// First chain of the group within the backend's chains.
    first: u32,
    /// Chains in the group.
    chains: u32,
    buffers: CpuBuffers<'a>,
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
    groups: Vec<Group<'a>>,
    pool: rayon::ThreadPool,
    threads: usize,
    chains: u32,
    dims: u32,
    image: Vec<f64>,
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
        let per_group = (GROUP_CANDIDATES / params.candidates_per_chain()).max(1);
        let mut groups = Vec::new();
        let mut first = 0;
        while first < params.chains {
            let chains = per_group.min(params.chains - first);
            let buffers = CpuBuffers::new(scene, &group_params(params, first, chains));
            groups.push(Group { first, chains, buffers });
            first += chains;
        }
        Ok(Self {
            groups,
            pool: thread_pool(threads)?,
            threads,
            chains: params.chains,
            dims: params.dims,
            image: vec![0.0; (params.width * params.height) as usize * 3],
        })
    }
}

impl Backend for CpuBackend<'_> {
    fn start(&mut self, chain_u: &[f32], chains: &[ChainState]) -> Result<(), RenderError> {
        let n = self.chains as usize;
        for g in &mut self.groups {
            let (first, count) = (g.first as usize, g.chains as usize);
            g.buffers.chains.copy_from_slice(&chains[first..first + count]);
            for dim in 0..self.dims as usize {
                g.buffers.chain_u[dim * count..(dim + 1) * count]
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
            for chain in &mut g.buffers.chains {
                acc.drain_chain(chain);
            }
        }
        Ok(())
    }

    fn thread_pool(&self) -> Option<&rayon::ThreadPool> {
        Some(&self.pool)
    }

    fn describe(&self) -> String {
        format!(
            "CPU ({} thread{}; the kernel bodies on the host)",
            self.threads,
            if self.threads == 1 { "" } else { "s" }
        )
    }
}
