//! Primary-sample-space MLT over the path tracer (Kelemen et al. 2002, as LuxCore's Metropolis
//! sampler over its path tracer): a chain's state is the primary sample vector u of one
//! path-traced sample — the raster position and six uniforms per vertex — and its
//! contribution is that sample's whole estimate ([`crate::path_tracer::trace_path`]: emission
//! found by BSDF sampling and a light sample at every vertex, weighed by the power heuristic),
//! at the pixel its raster position lands on. Every depth and both of its techniques count in
//! each sample, and a path plays the path tracer's Russian roulette with its own uniform.
//!
//! **Pixel importance.** The contribution is F(u)/Ĩ_j, with Ĩ_j > 0 a fixed estimate of pixel
//! j's luminance made before the chains start (`importance` buffer, one value a pixel), so the
//! target is c(u) = luminance(F(u))/Ĩ_j and b = E[c] over uniform u
//! (`crate::params::state_depths` is 1). A luminance target spends the chains' steps in
//! proportion to each pixel's brightness, so dark pixels get few and a relative error is worst
//! there; with Ĩ ≈ I every pixel gets about the same share (as a path tracer's samples) while,
//! inside a pixel, the chains still follow the light. Any positive Ĩ gives the same image: the
//! host multiplies pixel j's sums by Ĩ_j when it drains them.
//!
//! The chains, trees, reject chains, acceptance and splats are the paper's, and so are the
//! mutations but for two things: the raster position's own largest small step
//! (`crate::mutation::MutationParams::image_s2`) and, in the naive and reject chains' small
//! steps, fresh uniforms for the groups of dimensions the state's path never read
//! (`RenderParams::refreshes_group`; a chain's depth counts the vertices its path read, which
//! `connect` records). Of the stages only `trace` and `connect` differ (the whole path is traced
//! in `connect`, which has the scene, the candidate samples and the contribution buffer; `trace`
//! has nothing to do).

use glam::{Vec2, Vec4};

use crate::layout::pack_over_importance;
use crate::mmlt::Samples;
use crate::params::RenderParams;
use crate::path_tracer::{trace_path, PathSamples, PathSettings};
use crate::ray_caster::RayCaster;
use crate::scene::Scene;

/// The path tracer's settings of a chains' dispatch: the path estimator traces the path
/// tracer's paths.
impl From<&RenderParams> for PathSettings {
    #[inline]
    fn from(p: &RenderParams) -> Self {
        Self { camera: p.camera, max_depth: p.max_depth, light_count: p.light_count, epsilon: p.epsilon }
    }
}

/// The dimensions (2) of the raster position, as fractions of the image's width and height.
pub const PATH_DIM_RASTER: u32 = 0;

/// Dimensions of a vertex's uniforms: the light pick, the light point (2), the BSDF direction
/// (2) and the Russian roulette.
pub const PATH_VERTEX_DIMENSIONS: u32 = 6;

/// First of the [`PATH_VERTEX_DIMENSIONS`] dimensions of vertex `v` ≥ 1.
#[inline]
pub fn path_vertex_dimension(v: u32) -> u32 {
    2 + PATH_VERTEX_DIMENSIONS * (v - 1)
}

/// Dimensions of u for paths of up to `max_depth` bounces: the raster position and six for
/// each of vertices 1..=max_depth (the vertex after the last bounce only finds emission).
#[inline]
pub fn path_dimensions(max_depth: u32) -> u32 {
    path_vertex_dimension(max_depth + 1)
}

/// A candidate's primary samples as the path tracer's uniforms.
#[derive(Clone, Copy)]
pub struct ChainSamples<'a> {
    u: &'a [f32],
    samples: Samples,
}

impl PathSamples for ChainSamples<'_> {
    #[inline]
    fn raster(&self) -> Vec2 {
        self.samples.get2(self.u, PATH_DIM_RASTER)
    }

    #[inline]
    fn vertex(&self, v: u32) -> [f32; 6] {
        let first = path_vertex_dimension(v);
        let at = |i: u32| self.samples.get(self.u, first + i);
        [at(0), at(1), at(2), at(3), at(4), at(5)]
    }
}

/// Whether a path that read the uniforms of its first `vertices` vertices
/// ([`crate::path_tracer::PathEstimate::vertices`]) read any of dimensions `4·group ..
/// 4·group + 4`.
#[inline]
pub fn path_group_read(group: u32, vertices: u32) -> bool {
    4 * group < path_vertex_dimension(vertices + 1)
}

/// The path estimator's packed contribution of candidate `samples` — F/Ĩ_j in rgb, the pixel j
/// as the bits of w, with `importance` holding Ĩ per pixel — and how many vertices' uniforms
/// its path read.
#[inline]
pub fn path_candidate<R: RayCaster>(
    params: &RenderParams,
    scene: Scene<R>,
    u: &[f32],
    samples: Samples,
    importance: &[f32],
) -> (Vec4, u32) {
    let chain = ChainSamples { u, samples };
    let raster = chain.raster();
    let cam = params.camera;
    let (x, y) = (raster.x * cam.width, raster.y * cam.height);
    let settings = PathSettings::from(params);
    let path = trace_path(&settings, scene, (x, y), &chain);
    let pixel = cam.pixel(x, y);
    (pack_over_importance(path.radiance, pixel, importance), path.vertices)
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    /// The layout covers every uniform a path of max_depth bounces reads, once.
    #[test]
    fn every_vertex_has_its_own_six_dimensions() {
        assert_eq!(path_dimensions(0), 2);
        assert_eq!(path_dimensions(10), 62);
        for v in 1..=10 {
            assert_eq!(path_vertex_dimension(v + 1) - path_vertex_dimension(v), 6);
            assert!(path_vertex_dimension(v) + 6 <= path_dimensions(10));
        }
        assert_eq!(path_vertex_dimension(1), 2);
    }

    /// A path that read v vertices read dimensions 0 .. 2 + 6v: the groups of four that touch
    /// them, a group straddling the boundary included.
    #[test]
    fn groups_read_are_those_below_the_last_vertex_read() {
        let groups_read = |v: u32| (0..16).filter(|&g| path_group_read(g, v)).count();
        assert_eq!(groups_read(0), 1); // the raster position: dims 0, 1
        assert_eq!(groups_read(1), 2); // dims 0..8
        assert_eq!(groups_read(2), 4); // dims 0..14: group 3 (12..16) straddles
        assert_eq!(groups_read(3), 5); // dims 0..20
        assert_eq!(groups_read(10), 16); // dims 0..62: every group
        assert!(!path_group_read(4, 2) && path_group_read(3, 2));
    }
}
