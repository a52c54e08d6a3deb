//! The layout of a chain's primary sample vector u: which dimensions pick the technique, the
//! raster position, the lights, and each bounce on either subpath; and read access to one
//! candidate's samples in the SoA candidate buffer.

use glam::Vec2;

use crate::layout::soa_index;

/// Dimension of u that picks the technique.
pub const DIM_TECHNIQUE: u32 = 0;
/// Dimensions (2) of the raster position.
pub const DIM_RASTER: u32 = 1;
/// Dimension picking the light of a light subpath.
pub const DIM_LIGHT_PICK: u32 = 3;
/// Dimensions (2) of the point on it.
pub const DIM_LIGHT_POINT: u32 = 4;
/// Dimensions (2) of the direction leaving it.
pub const DIM_LIGHT_DIRECTION: u32 = 6;
/// Dimension picking the light resampled for s = 1.
pub const DIM_CONNECT_PICK: u32 = 8;
/// Dimensions (2) of the point on it.
pub const DIM_CONNECT_POINT: u32 = 9;
/// First dimension of the per-bounce samples.
pub const DIM_BOUNCES: u32 = 11;

/// Number of primary sample dimensions for paths of up to `max_depth` bounces: the fixed
/// ones plus two per bounce on each subpath.
#[inline]
pub fn sample_dimensions(max_depth: u32) -> u32 {
    DIM_BOUNCES + 4 * max_depth
}

/// Whether a path of `depth` bounces reads any of dimensions `first .. first + count`: the
/// fixed dimensions, and two per bounce on each subpath up to `depth` (a camera subpath of t ≤
/// depth + 2 vertices samples at most depth bounces, a light subpath of s ≤ depth + 1 fewer).
/// Small steps keep a chain's depth and a large step draws every dimension afresh, so mutating
/// the dimensions that a candidate's depth never reads changes nothing the chain can see; the
/// `mutate` pass skips them.
#[inline]
pub fn dimensions_used(first: u32, count: u32, depth: u32, max_depth: u32) -> bool {
    let end = first + count;
    let camera_end = DIM_BOUNCES + 2 * depth;
    let light_start = DIM_BOUNCES + 2 * max_depth;
    first < camera_end || (end > light_start && first < light_start + 2 * depth)
}

/// First of the two dimensions of bounce `i` (0-based) on the camera (side 0) or light
/// (side 1) subpath.
#[inline]
pub fn bounce_dimension(side: u32, bounce: u32, max_depth: u32) -> u32 {
    DIM_BOUNCES + side * 2 * max_depth + 2 * bounce
}

/// The technique for u[0] at depth k: `s = min(⌊u·(k+2)⌋, k+1)` light vertices, t = k + 2 − s.
#[inline]
pub fn technique(u0: f32, depth: u32) -> (u32, u32) {
    let n = depth + 2;
    let s = ((u0 * n as f32) as u32).min(n - 1);
    (s, n - s)
}

/// Read access to one candidate's primary samples in the SoA candidate buffer.
#[derive(Clone, Copy)]
pub struct Samples {
    /// Index k of the candidate in the buffer.
    pub candidate: u32,
    /// Candidates in the buffer (the SoA stride).
    pub count: u32,
}

impl Samples {
    /// u[dim].
    #[inline]
    pub fn get(&self, u: &[f32], dim: u32) -> f32 {
        u[soa_index(self.candidate, dim, self.count)]
    }

    /// (u[dim], u[dim + 1]).
    #[inline]
    pub fn get2(&self, u: &[f32], dim: u32) -> Vec2 {
        Vec2::new(self.get(u, dim), self.get(u, dim + 1))
    }
}
