//! The state of one chain besides its primary samples.

/// The state of one chain besides its primary samples (uploaded and updated on the device).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ChainState {
    /// The current state's contribution F (rgb) and pixel (bits of w).
    pub contribution: [f32; 4],
    /// Path depth k of the chain (the path estimator's: the vertices whose uniforms its path read).
    pub depth: u32,
    /// Expected number of accepted steps since the last drain.
    pub accepted: f32,
    /// Candidates rejected because their contribution was NaN or infinite, since the last drain.
    pub invalid: u32,
    /// Expected Markov steps advanced since the host last drained the image (the splat weight
    /// written: d per iteration for a tree, Σ R_i for a reject chain).
    pub steps: f32,
    /// Large-step candidates since the last drain (their targets estimate b:
    /// `crate::normalisation`).
    pub large_count: u32,
    /// Σ c of those candidates.
    pub large_sum: f32,
    /// Σ c² of those candidates.
    pub large_sum_sq: f32,
    /// Padding to 48 bytes.
    pub _pad: u32,
}
