//! The CPU backend (`--device cpu`): the same kernel bodies over host buffers, pass by pass.

use glam::Vec4;
use shared::mmlt::{vertex_slots, ChainState, PathInfo, PathVertex, RenderParams, Scene};

use super::{Backend, RenderError};
use crate::passes;
use crate::scene::SceneData;

/// The host buffers of a render (the same layout as the device's).
pub struct CpuBackend<'a> {
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
    image: Vec<f64>,
}

impl<'a> CpuBackend<'a> {
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
            image: vec![0.0; (params.width * params.height) as usize * 3],
        }
    }

    fn scene(&self) -> Scene<'a> {
        self.scene.shared()
    }

    /// The mutate, trace and connect passes.
    pub fn candidates_pass(&mut self, params: &RenderParams) {
        let scene = self.scene();
        passes::mutate::cpu(params, &self.chains, &self.chain_u, &mut self.cand_u, &mut self.cand_depth);
        passes::trace::cpu(
            params,
            &self.cand_depth,
            &self.cand_u,
            scene,
            &mut self.vertices,
            &mut self.paths,
        );
        passes::connect::cpu(
            params,
            &self.cand_u,
            scene,
            &self.vertices,
            &self.paths,
            &mut self.contributions,
        );
    }

    /// The select pass.
    pub fn select_pass(&mut self, params: &RenderParams) {
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
}

impl Backend for CpuBackend<'_> {
    fn bootstrap(&mut self, params: &RenderParams) -> Result<Vec<Vec4>, RenderError> {
        self.candidates_pass(params);
        Ok(self.contributions[..params.candidates as usize].to_vec())
    }

    fn start(&mut self, chain_u: &[f32], chains: &[ChainState]) -> Result<(), RenderError> {
        self.chain_u.copy_from_slice(chain_u);
        self.chains.copy_from_slice(chains);
        Ok(())
    }

    fn iterate(&mut self, params: &RenderParams) -> Result<(), RenderError> {
        self.candidates_pass(params);
        self.select_pass(params);
        passes::splat::cpu(params, &self.splats, &mut self.image);
        Ok(())
    }

    fn drain(&mut self, image: &mut [f64]) -> Result<f64, RenderError> {
        for (acc, v) in image.iter_mut().zip(self.image.iter_mut()) {
            *acc += *v;
            *v = 0.0;
        }
        let mut steps = 0.0;
        for chain in &mut self.chains {
            steps += chain.steps as f64;
            chain.steps = 0.0;
        }
        Ok(steps)
    }

    fn chain_states(&mut self) -> Result<Vec<ChainState>, RenderError> {
        Ok(self.chains.clone())
    }

    fn describe(&self) -> String {
        "CPU (the kernel bodies on the host, one thread)".into()
    }
}
