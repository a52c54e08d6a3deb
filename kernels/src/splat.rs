//! The `splat` pass: one invocation per splat record adds its rgb to an image, through a
//! [`SplatSink`]. On the device the sink is the f32 image stored as bits, added to with a
//! compare-and-swap loop (portable: core Vulkan 32-bit integer atomics, no float-atomic feature
//! needed), which the host drains into an f64 image periodically so long renders lose no
//! precision; on the host the same body adds to the f64 image directly.

use shared::layout::unpack_contribution;
use shared::params::RenderParams;
use spirv_std::glam::Vec4;

/// Number of splat records of a dispatch: one per distinct state of every chain.
pub fn splat_records(params: &RenderParams) -> u32 {
    params.chains * params.states_per_chain()
}

/// Where splats go: an rgb image, three values per pixel.
pub trait SplatSink {
    /// Adds `value` to element `index` (pixel · 3 + channel).
    fn add(&mut self, index: usize, value: f32);
}

/// The device's image: f32 values stored as bits, added to atomically.
impl SplatSink for [u32] {
    fn add(&mut self, index: usize, value: f32) {
        atomic_add_f32(self, index, value);
    }
}

/// The host's image: f64 sums (the CPU backend and the difftests).
#[cfg(not(target_arch = "spirv"))]
impl SplatSink for [f64] {
    fn add(&mut self, index: usize, value: f32) {
        self[index] += value as f64;
    }
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

stage! {
    /// What `splat` binds.
    pub struct SplatIo<'a> over image I {
        0 params: uniform RenderParams,
        1 splats: read Vec4,
        /// The image the records add to.
        2 image: sink I,
    }
    entry "splat_cs" (threads 64) => splat;
    bound;
}

/// The kernel body for record `i`: records without a pixel (`NO_PIXEL`) add nothing.
pub fn splat<S: SplatSink + ?Sized>(i: usize, io: SplatIo<S>) {
    let SplatIo { params, splats, image } = io;
    if i as u32 >= splat_records(params) {
        return;
    }
    let (rgb, pixel) = unpack_contribution(splats[i]);
    if pixel >= params.width * params.height {
        return;
    }
    let base = pixel as usize * 3;
    image.add(base, rgb.x);
    image.add(base + 1, rgb.y);
    image.add(base + 2, rgb.z);
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;
    use shared::layout::pack_contribution;
    use spirv_std::glam::Vec3;

    /// 10^8 splats of 0.1..0.4 into 2 pixels through the kernel body's f32 image, drained into
    /// f64 the way the renderer does (here every 2^16 splats per pixel), agree with an f64
    /// accumulation of the same splats to 1e-6. One f32 accumulator for the whole run stalls once
    /// its spacing exceeds twice the splat (past 2^23 · 0.8) and ends far off.
    #[test]
    fn f32_image_with_drains_matches_f64_over_1e8_splats() {
        let params =
            RenderParams { width: 2, height: 1, chains: 1 << 20, tree_depth: 1, ..Default::default() };
        let pixels = 2usize;
        let total = 100_000_000u64;
        let per_drain = (1u64 << 16) * pixels as u64;
        let mut image = vec![0u32; pixels * 3];
        let mut undrained = vec![0.0f32; pixels];
        let mut drained = vec![0.0f64; pixels];
        let mut exact = vec![0.0f64; pixels];
        let mut state = 0x9e37_79b9u32;
        let mut record = [Vec4::ZERO; 1];
        for i in 0..total {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            let pixel = (state % pixels as u32) as usize;
            let value = 0.1 + 0.3 * ((state >> 8) as f32 / (1u32 << 24) as f32);
            record[0] = pack_contribution(Vec3::new(value, 0.0, 0.0), 1.0, pixel as u32);
            splat(0, SplatIo { params: &params, splats: &record, image: &mut image[..] });
            exact[pixel] += value as f64;
            undrained[pixel] += value;
            if (i + 1) % per_drain == 0 || i + 1 == total {
                for p in 0..pixels {
                    drained[p] += f32::from_bits(image[p * 3]) as f64;
                    image[p * 3] = 0;
                }
            }
        }
        for p in 0..pixels {
            let rel = (drained[p] - exact[p]).abs() / exact[p];
            assert!(rel < 1e-6, "pixel {p}: drained f32 off by {rel:e}");
            let rel_undrained = (undrained[p] as f64 - exact[p]).abs() / exact[p];
            assert!(rel_undrained > 0.1, "pixel {p}: a single f32 sum is off by only {rel_undrained:e}");
        }
    }
}
