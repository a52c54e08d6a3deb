//! Float helpers that the device can call without a panic path.

/// `x` limited to [`lo`, `hi`] (`lo` ≤ `hi`); NaN gives `lo`. `f32::clamp` asserts `lo ≤ hi`:
/// a panic path, which makes rust-gpu inline every function that calls it, `inline(never)` or
/// not, and so grows the kernels' module.
#[allow(clippy::manual_clamp)]
#[inline]
pub fn clamp(x: f32, lo: f32, hi: f32) -> f32 {
    x.max(lo).min(hi)
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    #[test]
    fn clamp_limits_and_takes_nan_to_the_low_end() {
        assert_eq!((clamp(-1.0, 0.0, 1.0), clamp(0.25, 0.0, 1.0), clamp(3.0, 0.0, 1.0)), (0.0, 0.25, 1.0));
        assert_eq!(clamp(f32::NAN, 0.1, 0.9), 0.1);
    }
}
