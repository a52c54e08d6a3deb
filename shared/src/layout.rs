//! How chain state and results sit in device buffers.
//!
//! - **SoA (the paper's §5.1):** variable i of chain p is stored at `p + i·N` (N chains), so the
//!   threads of a warp, which handle neighbouring chains, read neighbouring words.
//! - **Packed contribution (the paper's §5.3):** a candidate's result is one `float4`: the rgb
//!   contribution times its weight in xyz, and the pixel index stored as the *bits* of w
//!   (`__int_as_float`), so one 16-byte access carries both. A candidate that lands on no
//!   pixel stores [`NO_PIXEL`]. The bits are the index with bit 30 flipped
//!   ([`PIXEL_BITS_FLIP`]), so that w is never a subnormal float.

use glam::{Vec3, Vec4};

/// Pixel index of a contribution that lands on no pixel.
pub const NO_PIXEL: u32 = u32::MAX;

/// What the pixel index is XORed with as the bits of a packed contribution's w: a pixel index
/// below 2^30 (an image is at most 16384² = 2^28 pixels) and [`NO_PIXEL`] become the bits of
/// normal floats, where an index below 2^23 is, as it is, the bits of a subnormal. The compiler
/// computes a contribution's rgb in 4-wide vector instructions that carry w along, and an x86
/// CPU takes a microcode assist of about a hundred cycles on each such instruction that meets a
/// subnormal: the plain bits cost the CPU backend's Metropolis methods 4–19 % of their speed
/// (`results/cpu-path/pixel_bits/`). A GPU is indifferent.
pub const PIXEL_BITS_FLIP: u32 = 1 << 30;

/// Position of variable `variable` of chain `chain` among `chains` chains: `p + i·N`.
#[inline]
pub fn soa_index(chain: u32, variable: u32, chains: u32) -> usize {
    chain as usize + variable as usize * chains as usize
}

/// Variables `4·group .. 4·group + 4` of `unit` among `units` (SoA, [`soa_index`]) as one
/// vector, lane i variable 4·group + i; lanes at or beyond `variables` read 0. Each lane is
/// its own load at a constant lane, so a device keeps the four in registers.
#[inline]
pub fn load_group(buffer: &[f32], unit: u32, group: u32, units: u32, variables: u32) -> Vec4 {
    let first = 4 * group;
    let mut v = Vec4::ZERO;
    if first < variables {
        v.x = buffer[soa_index(unit, first, units)];
    }
    if first + 1 < variables {
        v.y = buffer[soa_index(unit, first + 1, units)];
    }
    if first + 2 < variables {
        v.z = buffer[soa_index(unit, first + 2, units)];
    }
    if first + 3 < variables {
        v.w = buffer[soa_index(unit, first + 3, units)];
    }
    v
}

/// Stores `value` as variables `4·group .. 4·group + 4` of `unit` (the inverse of
/// [`load_group`]); lanes at or beyond `variables` are not stored.
#[inline]
pub fn store_group(buffer: &mut [f32], unit: u32, group: u32, units: u32, variables: u32, value: Vec4) {
    let first = 4 * group;
    if first < variables {
        buffer[soa_index(unit, first, units)] = value.x;
    }
    if first + 1 < variables {
        buffer[soa_index(unit, first + 1, units)] = value.y;
    }
    if first + 2 < variables {
        buffer[soa_index(unit, first + 2, units)] = value.z;
    }
    if first + 3 < variables {
        buffer[soa_index(unit, first + 3, units)] = value.w;
    }
}

/// Packs `rgb · weight` and the pixel index (as the bits of the fourth float, flipped by
/// [`PIXEL_BITS_FLIP`]) into one Vec4.
#[inline]
pub fn pack_contribution(rgb: Vec3, weight: f32, pixel: u32) -> Vec4 {
    (rgb * weight).extend(f32::from_bits(pixel ^ PIXEL_BITS_FLIP))
}

/// Packs `rgb` divided by the pixel importance Ĩ of `pixel` (`importance`, one value a pixel)
/// and the pixel's bits: the chains' target is then luminance(rgb)/Ĩ, every pixel getting
/// about the same share of their steps, and the host multiplies the pixel's drained sums by Ĩ
/// (any positive Ĩ gives the same image). Ones leave `rgb` bit for bit; a pixel outside
/// `importance` keeps it too (none is made; the guard keeps a kernel in bounds).
#[inline]
pub fn pack_over_importance(rgb: Vec3, pixel: u32, importance: &[f32]) -> Vec4 {
    let weight = if (pixel as usize) < importance.len() { 1.0 / importance[pixel as usize] } else { 1.0 };
    pack_contribution(rgb, weight, pixel)
}

/// The inverse of [`pack_contribution`]: (rgb · weight, pixel index).
#[inline]
pub fn unpack_contribution(packed: Vec4) -> (Vec3, u32) {
    (packed.truncate(), packed.w.to_bits() ^ PIXEL_BITS_FLIP)
}

/// The splat record of a state with contribution `v` (F, pixel bits), target `c` and
/// expected-steps weight `w`: (F/c)·w — F/c is bounded, unlike w/c, which overflows for a
/// denormal c — or an empty record ([`NO_PIXEL`]) when the state has no weight or is invalid
/// (a NaN or infinite target is never splatted).
#[inline]
pub fn splat_record(v: Vec4, c: f32, w: f32) -> Vec4 {
    use crate::acceptance::is_valid_target;
    let (rgb, pixel) = unpack_contribution(v);
    let value = (rgb / c) * w;
    let finite = is_valid_target(value.x) && is_valid_target(value.y) && is_valid_target(value.z);
    if w > 0.0 && c > 0.0 && is_valid_target(c) && finite {
        pack_contribution(value, 1.0, pixel)
    } else {
        pack_contribution(Vec3::ZERO, 0.0, NO_PIXEL)
    }
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    #[test]
    fn soa_index_is_chain_plus_variable_times_chains() {
        assert_eq!(soa_index(0, 0, 7), 0);
        assert_eq!(soa_index(3, 0, 7), 3);
        assert_eq!(soa_index(3, 2, 7), 17);
        // Neighbouring chains, same variable: neighbouring words.
        assert_eq!(soa_index(4, 5, 1000) - soa_index(3, 5, 1000), 1);
        assert_eq!(soa_index(u32::MAX, 1, u32::MAX), 2 * u32::MAX as usize);
    }

    /// A group of four variables goes in and out lane by lane; the last group of an odd
    /// count leaves the words beyond it alone and reads them as 0.
    #[test]
    fn groups_store_and_load_four_variables() {
        let (units, variables) = (3u32, 6u32);
        let mut buffer = vec![-1.0f32; (units * 8) as usize];
        store_group(&mut buffer, 2, 0, units, variables, Vec4::new(1.0, 2.0, 3.0, 4.0));
        store_group(&mut buffer, 2, 1, units, variables, Vec4::new(5.0, 6.0, 7.0, 8.0));
        for (i, v) in [1.0, 2.0, 3.0, 4.0, 5.0, 6.0].into_iter().enumerate() {
            assert_eq!(buffer[soa_index(2, i as u32, units)], v);
        }
        assert_eq!(buffer[soa_index(2, 6, units)], -1.0);
        assert_eq!(buffer[soa_index(1, 0, units)], -1.0);
        assert_eq!(load_group(&buffer, 2, 1, units, variables), Vec4::new(5.0, 6.0, 0.0, 0.0));
        assert_eq!(load_group(&buffer, 2, 0, units, variables), Vec4::new(1.0, 2.0, 3.0, 4.0));
    }

    /// A contribution is divided by the importance of its pixel, ones leave it bit for bit, and
    /// a pixel outside the buffer keeps it.
    #[test]
    fn a_contribution_is_divided_by_its_pixels_importance() {
        let rgb = Vec3::new(0.3, 1.7, 1e-3);
        assert_eq!(unpack_contribution(pack_over_importance(rgb, 2, &[1.0, 1.0, 0.25, 1.0])), (rgb * 4.0, 2));
        let (back, _) = unpack_contribution(pack_over_importance(rgb, 2, &[1.0; 4]));
        assert_eq!(back.to_array().map(f32::to_bits), rgb.to_array().map(f32::to_bits));
        assert_eq!(unpack_contribution(pack_over_importance(rgb, NO_PIXEL, &[0.25; 4])), (rgb, NO_PIXEL));
    }

    /// Every pixel index survives the trip through a float's bits, the ones whose own bits are
    /// subnormals (below 2^23) or NaN patterns included.
    #[test]
    fn packing_round_trips_every_kind_of_index() {
        for pixel in [0u32, 1, 7, (1 << 23) - 1, 1 << 23, 1920 * 1080 - 1, 0x7f80_0001, NO_PIXEL] {
            let rgb = Vec3::new(0.5, 2.0, 1e-3);
            let (back, p) = unpack_contribution(pack_contribution(rgb, 0.25, pixel));
            assert_eq!(p, pixel);
            assert_eq!(back, rgb * 0.25);
        }
    }

    /// The w of every pixel of the largest image, and of NO_PIXEL, is a normal float: no CPU
    /// instruction that carries it along meets a subnormal.
    #[test]
    fn a_packed_pixel_is_a_normal_float() {
        let largest = 16384 * 16384;
        let pixels = (0..1 << 16).chain((largest - (1 << 16))..largest).chain((0..largest).step_by(4099));
        for pixel in pixels.chain([NO_PIXEL]) {
            let w = pack_contribution(Vec3::ONE, 1.0, pixel).w;
            assert!(w.is_normal(), "pixel {pixel}: w = {w:e}");
        }
    }
}
