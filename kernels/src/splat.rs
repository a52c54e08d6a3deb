//! The `splat` pass: one invocation per splat record adds its rgb to the f32 image with a
//! compare-and-swap loop on the bits (portable: core Vulkan 32-bit integer atomics, no
//! float-atomic feature needed). The host drains this image into an f64 image periodically,
//! so long renders lose no precision. On the CPU the host adds the same records directly.

use shared::layout::unpack_contribution;
use shared::mmlt::RenderParams;
use spirv_std::glam::{UVec3, Vec4};
use spirv_std::spirv;

/// Number of splat records of a dispatch: one per distinct state of every chain.
pub fn splat_records(params: &RenderParams) -> u32 {
    params.chains * params.states_per_chain()
}

/// Adds `value` to the float stored as bits at `image[index]`.
fn atomic_add_f32(image: &mut [u32], index: usize, value: f32) {
    #[cfg(target_arch = "spirv")]
    {
        use spirv_std::arch::{atomic_compare_exchange, atomic_load};
        use spirv_std::memory::{Scope, Semantics};
        // QueueFamily scope spans every invocation of the dispatch and, unlike Device scope, needs
        // no extra capability under the Vulkan memory model.
        const DEVICE: u32 = Scope::QueueFamily as u32;
        const NONE: u32 = Semantics::NONE.bits();
        let slot = &mut image[index];
        let mut old = unsafe { atomic_load::<u32, DEVICE, NONE>(slot) };
        loop {
            let new = (f32::from_bits(old) + value).to_bits();
            let seen = unsafe { atomic_compare_exchange::<u32, DEVICE, NONE, NONE>(slot, new, old) };
            if seen == old {
                break;
            }
            old = seen;
        }
    }
    #[cfg(not(target_arch = "spirv"))]
    {
        image[index] = (f32::from_bits(image[index]) + value).to_bits();
    }
}

/// The kernel body for record `i`.
pub fn splat(i: usize, params: &RenderParams, splats: &[Vec4], image: &mut [u32]) {
    if i as u32 >= splat_records(params) {
        return;
    }
    let (rgb, pixel) = unpack_contribution(splats[i]);
    if pixel >= params.width * params.height {
        return;
    }
    let base = pixel as usize * 3;
    atomic_add_f32(image, base, rgb.x);
    atomic_add_f32(image, base + 1, rgb.y);
    atomic_add_f32(image, base + 2, rgb.z);
}

/// Entry point: one invocation per splat record.
#[spirv(compute(threads(64), entry_point_name = "splat_cs"))]
pub fn splat_cs(
    #[spirv(global_invocation_id)] id: UVec3,
    #[spirv(storage_buffer, descriptor_set = 0, binding = 0)] params: &[RenderParams],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 1)] splats: &[Vec4],
    #[spirv(storage_buffer, descriptor_set = 0, binding = 2)] image: &mut [u32],
) {
    splat(id.x as usize, &params[0], splats, image);
}
