//! Colour: the luminance that turns an rgb contribution into the chains' scalar target, the
//! light CDF's power, the pixel importance and the PNG's exposure.

use glam::Vec3;

/// Luminance (Rec. 709) of a linear RGB value.
#[inline]
pub fn luminance(rgb: Vec3) -> f32 {
    0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    /// Rec. 709's weights: white is 1, and green weighs most.
    #[test]
    fn rec709_weights() {
        assert!((luminance(Vec3::ONE) - 1.0).abs() < 1e-6);
        assert_eq!(luminance(Vec3::new(0.0, 1.0, 0.0)), 0.7152);
        assert_eq!(luminance(Vec3::new(1.0, 0.0, 0.0)), 0.2126);
    }
}
