//! Multiplexed MLT path sampling (Hachisuka et al. 2014, as pbrt-v3's `MLTIntegrator`): a chain
//! of fixed path depth k (bounces; k + 1 segments) maps its primary samples u to one of the
//! k + 2 ways of splitting the path into a light subpath of s vertices and a camera subpath of
//! t = k + 2 − s vertices, traces both, connects only their end points, and weighs the result
//! with the balance heuristic over all k + 2 techniques:
//!
//! `F(u) = f(x̄) · w_s(x̄) · (k + 2) / p_s(x̄)`, scalar target `c(u) = luminance(F)/Ĩ_j`,
//!
//! with Ĩ_j the pixel importance of the pixel j it lands on
//! ([`crate::layout::pack_over_importance`], as the path estimator's): every pixel gets about the same share of the chains' steps.
//! All Ĩ_j = 1 is the paper's target, the luminance (`smlt render --no-pixel-importance`).
//!
//! The technique is chosen by u[0] (so mutations can change it). s = 1 resamples the light
//! point with its own samples and t = 1 connects to the pinhole, landing on the pixel the
//! light subpath projects to. t = 0 is impossible with a pinhole and is excluded.
//!
//! The stages of the wavefront live here as plain functions: [`trace_candidate`] builds both
//! subpaths into the vertex buffer (kernel `trace`), [`connect_candidate`] makes the connection
//! and the MIS weight (kernel `connect`).
//!
//! **Vertex densities.** Each vertex stores `pdf_fwd`, the area density with which its own
//! subpath generated it, and `pdf_rev`, the area density with which the other subpath would
//! have; the balance heuristic is `1 / (1 + Σ_{s'≠s} p_{s'}/p_s)`, the ratios being running
//! products of `pdf_rev/pdf_fwd` along each subpath (pbrt-v3's `MISWeight`). The connection
//! changes `pdf_rev` of the two last vertices of each subpath; they are recomputed in the
//! connection.
//!
//! **Punctual lights** (`crate::punctual`) are deltas, handled as pbrt-v4's BDPT does: no
//! camera subpath hits one, so the technique s = 0 has density 0 for a path that starts on one
//! and is left out of the weight's sum; s = 1 connects to the light's position (or, for a
//! directional light, along its direction, `PunctualLight::incident`), and t = 1 with s = 1 (the
//! camera seeing the light itself) carries nothing. A light subpath leaves a point or spot
//! light by its emission density; a directional light's starts on its disk, and its first
//! vertex's density is the disk's, projected (no inverse square).
//!
//! **The environment light** (`crate::environment`) is at infinity, as pbrt's BDPT treats an
//! infinite light: a camera subpath that leaves the scene ends on a light vertex whose forward
//! density is the direction's in solid angle ([`is_at_infinity`]); a light subpath starts on
//! the disk of the bounding sphere perpendicular to a sampled direction, its origin's density
//! the direction's (with the pick) and its first vertex's the disk's, projected; densities
//! towards it stay solid-angle densities. The camera sees it only by itself (s = 0): the
//! technique (1, 1) has density 0 for such a path and is left out of the weight's sum.

mod chain;
mod connect;
mod dimensions;
mod trace;
mod vertex;

pub use chain::*;
pub use connect::*;
pub use dimensions::*;
pub use trace::*;
pub use vertex::*;

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests;
