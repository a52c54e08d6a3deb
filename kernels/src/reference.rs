//! The `reference` pass: one invocation per pixel adds `params.samples` path-traced samples
//! (`shared::path_tracer`, round `params.round`) to its own pixel of an f32 image, which the
//! host drains into f64 after every pass.

use shared::bsdf::Material;
use shared::cwbvh::{WideBvh, WideNode};
use shared::light::LightEntry;
use shared::path_tracer::{pixel_round, ReferenceParams};
use shared::ray_caster::RayCaster;
use shared::scene::Scene;
use shared::triangle::Triangle;
use spirv_std::glam::UVec3;
use spirv_std::spirv;

/// The kernel body for pixel `i`.
pub fn reference<R: RayCaster>(i: usize, params: &ReferenceParams, scene: Scene<R>, image: &mut [f32]) {
    if i as u32 >= params.width * params.height {
        return;
    }
    let sum = pixel_round(params, scene, i as u32);
    image[i * 3] += sum.x;
    image[i * 3 + 1] += sum.y;
    image[i * 3 + 2] += sum.z;
}

/// Entry point: one invocation per pixel.
#[spirv(compute(threads(64), entry_point_name = "reference_cs"))]
pub fn reference_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] params: &[ReferenceParams],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] nodes: &[WideNode],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] triangles: &[Triangle],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 3)] materials: &[Material],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 4)] lights: &[LightEntry],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 5)] image: &mut [f32],
) {
    let scene = Scene { caster: WideBvh { nodes, triangles }, triangles, materials, lights };
    reference(id.x as usize, &params[0], scene, image);
}
