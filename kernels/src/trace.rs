//! The `trace` pass: one invocation per candidate chooses the MMLT technique and traces the
//! camera and light subpaths into the vertex buffer (`shared::mmlt::trace_candidate`). The
//! path estimator (`shared::pssmlt`) has nothing to trace here.

use shared::mmlt::{trace_candidate, PathInfo, PathVertex, Samples};
use shared::params::{RenderParams, ESTIMATOR_PATH};
use shared::ray_caster::RayCaster;

stage! {
    /// What `trace` binds.
    pub struct TraceIo<'a> over scene R {
        0 params: uniform RenderParams,
        /// The depth `mutate` chose for each candidate.
        1 cand_depth: read u32,
        2 cand_u: read f32,
        /// The subpaths' vertices, SoA (`k + slot·C`).
        3 vertices: write PathVertex,
        4 paths: write PathInfo,
    }
    entry "trace_cs" (threads 64) => trace;
    bound;
}

/// The kernel body for candidate `k`.
pub fn trace<R: RayCaster>(k: usize, io: TraceIo<R>) {
    let params = io.params;
    let k = k as u32;
    // The path estimator traces its whole path in `connect`.
    if k >= params.candidates || params.estimator == ESTIMATOR_PATH {
        return;
    }
    let depth = io.cand_depth[k as usize];
    let samples = Samples { candidate: k, count: params.candidates };
    io.paths[k as usize] = trace_candidate(params, io.scene, io.cand_u, samples, depth, io.vertices);
}
