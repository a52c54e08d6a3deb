//! The Metropolis–Hastings acceptance probability for symmetric proposals (the paper's Eq. 1):
//! `a(y|x) = min(1, c(y) / c(x))`, where `c` is the scalar target (luminance of the path
//! contribution). Kelemen mutations are symmetric in primary sample space, so the proposal
//! densities cancel.
//!
//! The edge cases are defined, never NaN:
//! - a proposal whose target is NaN, ±Inf or negative is invalid and never accepted: `a = 0`
//!   (the caller counts it as a rejected sample and never splats it);
//! - from a current state with `c(x) = 0` (a zero start state) or a non-finite `c(x)`, any
//!   valid proposal is accepted: `a = 1`, so a chain leaves a state the target gives no mass;
//! - otherwise `min(1, c(y)/c(x))`, where an overflowing quotient is 1 and an underflowing one
//!   is 0.

/// Whether `x` is finite, from its exponent bits. (`f32::is_finite` compares with an infinite
/// literal, which naga's SPIR-V front end rejects.)
#[inline]
pub fn is_finite(x: f32) -> bool {
    x.to_bits() & 0x7f80_0000 != 0x7f80_0000
}

/// Whether a target value may be accepted and splatted: finite and not negative.
#[inline]
pub fn is_valid_target(c: f32) -> bool {
    is_finite(c) && c >= 0.0
}

/// `a(y|x) = min(1, c(y)/c(x))` with the edge cases of the module documentation.
#[inline]
pub fn acceptance(c_current: f32, c_proposed: f32) -> f32 {
    if !is_valid_target(c_proposed) {
        return 0.0;
    }
    if !(is_finite(c_current) && c_current > 0.0) {
        return 1.0;
    }
    let ratio = c_proposed / c_current;
    if ratio >= 1.0 {
        1.0
    } else {
        ratio
    }
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    #[test]
    fn is_finite_agrees_with_std() {
        for x in [
            0.0f32,
            -0.0,
            1.0,
            f32::MAX,
            f32::MIN,
            f32::MIN_POSITIVE,
            1e-45,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
        ] {
            assert_eq!(is_finite(x), x.is_finite(), "{x}");
        }
    }

    #[test]
    fn ordinary_ratio_and_clamp() {
        assert_eq!(acceptance(2.0, 1.0), 0.5);
        assert_eq!(acceptance(1.0, 2.0), 1.0);
        assert_eq!(acceptance(3.0, 3.0), 1.0);
        assert_eq!(acceptance(1.0, 0.0), 0.0);
    }

    #[test]
    fn invalid_proposals_are_never_accepted() {
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -1.0, -f32::MIN_POSITIVE] {
            for current in [0.0, 1.0, f32::NAN, f32::INFINITY, 1e-30] {
                assert_eq!(acceptance(current, bad), 0.0, "c(x) = {current}, c(y) = {bad}");
            }
        }
    }

    #[test]
    fn zero_or_broken_current_state_accepts_any_valid_proposal() {
        for current in [0.0, -0.0, f32::NAN, f32::INFINITY, -2.0] {
            assert_eq!(acceptance(current, 0.0), 1.0);
            assert_eq!(acceptance(current, 5.0), 1.0);
        }
    }

    #[test]
    fn extreme_ratios_stay_in_the_unit_interval() {
        assert_eq!(acceptance(f32::MIN_POSITIVE / 4.0, f32::MAX), 1.0, "overflow is 1");
        let tiny = acceptance(f32::MAX, f32::MIN_POSITIVE);
        assert!((0.0..1e-37).contains(&tiny), "underflow is ~0, got {tiny}");
        let a = acceptance(1.0, 1.0 - 1e-7);
        assert!(a < 1.0 && a > 0.9999998);
    }
}
