//! Error against a reference image, as the bench reports it, and the error heat maps.
//!
//! - **RMSE**: root of the mean over all pixels and channels of (x − r)², in linear radiance.
//! - **relMSE**: mean over pixels and channels of (x − r)² / (r² + 0.01) (the 0.01 keeps dark
//!   pixels from dominating, as in pbrt's and Mitsuba's tools).
//! - **PSNR**: 10 · log10(1 / MSE) on values clamped to [0, 1] (peak 1: the displayable range
//!   of the linear image), in dB, the way an 8-bit comparison would see it.

/// Errors of `image` against `reference` (both linear rgb, same size).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Errors {
    /// Root mean squared error.
    pub rmse: f64,
    /// Relative mean squared error.
    pub relmse: f64,
    /// Peak signal-to-noise ratio, dB, peak 1 on clamped values.
    pub psnr: f64,
}

/// The errors of `image` against `reference`.
pub fn errors(image: &[f32], reference: &[f32]) -> Errors {
    assert_eq!(image.len(), reference.len());
    let n = image.len().max(1) as f64;
    let (mut se, mut rel, mut clamped) = (0.0f64, 0.0f64, 0.0f64);
    for (x, r) in image.iter().zip(reference) {
        let (x, r) = (*x as f64, *r as f64);
        let d = x - r;
        se += d * d;
        rel += d * d / (r * r + 0.01);
        let dc = x.clamp(0.0, 1.0) - r.clamp(0.0, 1.0);
        clamped += dc * dc;
    }
    let mse_clamped = clamped / n;
    Errors {
        rmse: (se / n).sqrt(),
        relmse: rel / n,
        psnr: if mse_clamped > 0.0 { 10.0 * (1.0 / mse_clamped).log10() } else { f64::INFINITY },
    }
}

/// A per-pixel error heat map (the paper's Fig. 1/8 style): the RMS error of each pixel's
/// channels, normalised by `scale`, mapped low → blue, medium → green, high → red.
pub fn heat_map(image: &[f32], reference: &[f32], width: u32, height: u32, scale: f64) -> image::RgbImage {
    image::RgbImage::from_fn(width, height, |x, y| {
        let i = ((x + y * width) * 3) as usize;
        let e = (0..3).map(|c| ((image[i + c] - reference[i + c]) as f64).powi(2)).sum::<f64>() / 3.0;
        let t = (e.sqrt() / scale).clamp(0.0, 1.0);
        // Blue (0) → green (0.5) → red (1).
        let (r, g, b) =
            if t < 0.5 { (0.0, 2.0 * t, 1.0 - 2.0 * t) } else { (2.0 * t - 1.0, 2.0 - 2.0 * t, 0.0) };
        image::Rgb([(r * 255.0) as u8, (g * 255.0) as u8, (b * 255.0) as u8])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_of_known_images() {
        let r = vec![0.5f32; 12];
        assert_eq!(errors(&r, &r).rmse, 0.0);
        assert_eq!(errors(&r, &r).psnr, f64::INFINITY);
        let x = vec![0.6f32; 12];
        let e = errors(&x, &r);
        assert!((e.rmse - 0.1).abs() < 1e-6);
        assert!((e.psnr - 20.0).abs() < 1e-4, "{}", e.psnr);
        assert!((e.relmse - 0.01 / 0.26).abs() < 1e-6);
    }

    #[test]
    fn heat_map_colours() {
        let r = vec![0.0f32; 9];
        let x = vec![0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0];
        let m = heat_map(&x, &r, 3, 1, 1.0);
        assert_eq!(m.get_pixel(0, 0).0, [0, 0, 255]);
        assert_eq!(m.get_pixel(1, 0).0, [0, 255, 0]);
        assert_eq!(m.get_pixel(2, 0).0, [255, 0, 0]);
    }
}
