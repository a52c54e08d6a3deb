//! The `connect` pass: one invocation per candidate connects the end points of its subpaths
//! with one shadow ray, weighs the path with the balance heuristic, and stores the packed
//! contribution (F divided by its pixel's importance in rgb, the pixel index as the bits of w;
//! the paper's §5.3). For the path estimator it traces the candidate's whole path instead
//! (`shared::pssmlt::path_candidate`), divided the same way, and stores as the candidate's depth
//! how many vertices' uniforms the path read (what `mutate` perturbs of the state it moves to).

use shared::layout::pack_over_importance;
use shared::mmlt::{connect_candidate, PathInfo, PathVertex, Samples};
use shared::params::{RenderParams, ESTIMATOR_PATH};
use shared::pssmlt::path_candidate;
use shared::ray_caster::RayCaster;
use spirv_std::glam::Vec4;

stage! {
    /// What `connect` binds.
    pub struct ConnectIo<'a> over scene R {
        0 params: uniform RenderParams,
        1 cand_u: read f32,
        /// The subpaths' vertices `trace` left.
        2 vertices: read PathVertex,
        3 paths: read PathInfo,
        /// Ĩ per pixel, which each contribution is divided by.
        4 importance: read f32,
        /// The packed contributions, one a candidate.
        5 contributions: write Vec4,
        /// The path estimator's vertices read, one a candidate.
        6 cand_depth: write u32,
    }
    entry "connect_cs" (threads 64) => connect;
    bound;
}

/// The kernel body for candidate `k`.
pub fn connect<R: RayCaster>(k: usize, io: ConnectIo<R>) {
    let params = io.params;
    let k = k as u32;
    if k >= params.candidates {
        return;
    }
    let samples = Samples { candidate: k, count: params.candidates };
    if params.estimator == ESTIMATOR_PATH {
        let (contribution, vertices) = path_candidate(params, io.scene, io.cand_u, samples, io.importance);
        io.contributions[k as usize] = contribution;
        io.cand_depth[k as usize] = vertices;
        return;
    }
    let connection =
        connect_candidate(params, io.scene, io.cand_u, samples, &io.paths[k as usize], io.vertices);
    io.contributions[k as usize] =
        pack_over_importance(connection.contribution, connection.pixel, io.importance);
}
