//! The device self-test: evaluates the speculative-tree, reject-chain, acceptance, mutation,
//! random-number and packing functions of `shared` for a batch of cases, so the host can check
//! that the device computes what the CPU computes (the first difftest, and what
//! `smlt selftest` runs on the chosen adapter).
//!
//! Outputs per case kind, at the case's `output` offset of `out_f` and at `8·index` of `out_u`:
//! - [`CASE_TREE`] (size = depth d): acceptances (2^d − 1), leaf probabilities (2^d), weights
//!   (2^d); `out_u[8i]` = next state for `xi`.
//! - [`CASE_REJECT_CHAIN`] (size = length l): acceptances (l), next-state probabilities
//!   (l + 1), weights (l + 1), expected steps (1); `out_u[8i]` = next state for `xi`.
//! - [`CASE_SCALAR`]: acceptance(in[0], in[1]), the small-step offset for `xi`, the small step
//!   of in[2] by it, the uniform for the case's key, and the xyz of the packed contribution
//!   (in[3..6] weighted by `xi`); `out_u[8i..8i+4]` = pcg4d of the key, `out_u[8i+4]` = the
//!   packed pixel bits read back.

use shared::acceptance::acceptance;
use shared::glam::Vec3;
use shared::layout::{pack_contribution, unpack_contribution};
use shared::mutation::{small_step, small_step_offset, MutationParams};
use shared::reject_chain::{self, MAX_REJECT_CHAIN, MAX_REJECT_CHAIN_STATES};
use shared::rng::{self, RngKey};
use shared::tree::{self, MAX_TREE_CANDIDATES, MAX_TREE_LEAVES, MAX_TREE_STATES};

/// A speculative tree case.
pub const CASE_TREE: u32 = 0;
/// A reject-chain case.
pub const CASE_REJECT_CHAIN: u32 = 1;
/// A case of the scalar functions (acceptance, mutation, rng, packing).
pub const CASE_SCALAR: u32 = 2;
/// Words of `out_u` per case.
pub const U32_OUTPUTS_PER_CASE: usize = 8;

/// One self-test case.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SelfTestCase {
    /// [`CASE_TREE`], [`CASE_REJECT_CHAIN`] or [`CASE_SCALAR`].
    pub kind: u32,
    /// Tree depth or reject-chain length.
    pub size: u32,
    /// Offset of the case's inputs (targets c, or scalar arguments) in `inputs`.
    pub input: u32,
    /// Offset of the case's float outputs in `out_f`.
    pub output: u32,
    /// The uniform that selects the next state (and the mutation's ξ).
    pub xi: f32,
    /// Seed of the random key (and the pixel index of the packing test).
    pub seed: u32,
    /// Chain word of the random key.
    pub chain: u32,
    /// Iteration word of the random key.
    pub iteration: u32,
}

impl SelfTestCase {
    /// Number of float outputs this case writes.
    pub fn float_outputs(&self) -> usize {
        match self.kind {
            CASE_TREE => 3 * (1usize << self.size) - 1,
            CASE_REJECT_CHAIN => 3 * self.size as usize + 3,
            _ => 7,
        }
    }

    /// Number of inputs this case reads.
    pub fn inputs(&self) -> usize {
        match self.kind {
            CASE_TREE => 1usize << self.size,
            CASE_REJECT_CHAIN => self.size as usize + 1,
            _ => 6,
        }
    }
}

/// The first `n` values of `src` from `start`, in a zero-padded local array.
fn load<const N: usize>(src: &[f32], start: usize, n: usize) -> [f32; N] {
    let mut out = [0.0f32; N];
    let mut i = 0;
    while i < n {
        out[i] = src[start + i];
        i += 1;
    }
    out
}

/// Writes the first `n` values of `src` to `dst` from `start`.
fn store<const N: usize>(dst: &mut [f32], start: usize, src: &[f32; N], n: usize) {
    let mut i = 0;
    while i < n {
        dst[start + i] = src[i];
        i += 1;
    }
}

stage! {
    /// What `selftest` binds.
    pub struct SelftestIo<'a> {
        0 cases: read SelfTestCase,
        1 inputs: read f32,
        /// The float results, [`SelfTestCase::float_outputs`] a case.
        2 out_f: write f32,
        /// The integer results.
        3 out_u: write u32,
    }
    entry "selftest_cs" (threads 64) => selftest;
}

/// The kernel body: evaluates case `index`.
pub fn selftest(index: usize, io: SelftestIo) {
    let SelftestIo { cases, inputs, out_f, out_u } = io;
    if index >= cases.len() {
        return;
    }
    let case = cases[index];
    let input = case.input as usize;
    let output = case.output as usize;
    let u = index * U32_OUTPUTS_PER_CASE;
    if case.kind == CASE_TREE {
        let depth = case.size;
        let states = 1usize << depth;
        let c: [f32; MAX_TREE_STATES] = load(inputs, input, states);
        let mut accept = [0.0f32; MAX_TREE_CANDIDATES];
        let mut leaf = [0.0f32; MAX_TREE_LEAVES];
        let mut weight = [0.0f32; MAX_TREE_STATES];
        tree::evaluate_tree(depth, &c, &mut accept, &mut leaf, &mut weight);
        store(out_f, output, &accept, states - 1);
        store(out_f, output + states - 1, &leaf, states);
        store(out_f, output + 2 * states - 1, &weight, states);
        out_u[u] = tree::select_next_state(depth, &leaf, case.xi);
    } else if case.kind == CASE_REJECT_CHAIN {
        let length = case.size;
        let l = length as usize;
        let c: [f32; MAX_REJECT_CHAIN_STATES] = load(inputs, input, l + 1);
        let mut accept = [0.0f32; MAX_REJECT_CHAIN as usize];
        let mut next = [0.0f32; MAX_REJECT_CHAIN_STATES];
        let mut weight = [0.0f32; MAX_REJECT_CHAIN_STATES];
        let steps = reject_chain::evaluate_reject_chain(length, &c, &mut accept, &mut next, &mut weight);
        store(out_f, output, &accept, l);
        store(out_f, output + l, &next, l + 1);
        store(out_f, output + 2 * l + 1, &weight, l + 1);
        out_f[output + 3 * l + 2] = steps;
        out_u[u] = reject_chain::select_next_state(length, &next, case.xi);
    } else {
        let params = MutationParams::default();
        let key = RngKey {
            seed: case.seed,
            chain: case.chain,
            iteration: case.iteration,
            dimension: rng::dimension(rng::STREAM_SELFTEST, index as u32),
        };
        let offset = small_step_offset(case.xi, params.s1, params.s2);
        out_f[output] = acceptance(inputs[input], inputs[input + 1]);
        out_f[output + 1] = offset;
        out_f[output + 2] = small_step(inputs[input + 2], offset);
        out_f[output + 3] = rng::uniform(key);
        let rgb = Vec3::new(inputs[input + 3], inputs[input + 4], inputs[input + 5]);
        let (packed_rgb, pixel) = unpack_contribution(pack_contribution(rgb, case.xi, case.seed));
        out_f[output + 4] = packed_rgb.x;
        out_f[output + 5] = packed_rgb.y;
        out_f[output + 6] = packed_rgb.z;
        let words = rng::random_u32x4(key);
        out_u[u] = words[0];
        out_u[u + 1] = words[1];
        out_u[u + 2] = words[2];
        out_u[u + 3] = words[3];
        out_u[u + 4] = pixel;
    }
}
