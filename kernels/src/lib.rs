#![cfg_attr(target_arch = "spirv", no_std)]
use spirv_std::spirv;
use spirv_std::glam::UVec3;

#[spirv(compute(threads(64)))]
pub fn probe_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] out: &mut [u32],
) {
    let i = id.x as usize;
    if i < out.len() {
        out[i] = i as u32 * 3;
    }
}
