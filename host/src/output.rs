//! Writing images: a linear float OpenEXR and a tone-mapped sRGB PNG beside it. The PNG is the
//! linear image scaled by an exposure (`--exposure EV`, or automatic: [`auto_exposure`]),
//! through a filmic curve ([`filmic`]) that rolls highlights off instead of clipping them, and
//! the sRGB transfer; the EXR stays linear radiance. Each file is
//! written to a temporary name in the same directory and renamed into place, so an interrupted
//! render never leaves a broken image; [`check_writable`] refuses an unwritable path before
//! any rendering starts. The same image is the same file, byte for byte ([`EXR_ENCODING`]).

use std::path::{Path, PathBuf};

/// How smlt's EXR files (images and `--shard` parts) are laid out: the exr crate's default
/// (RLE in 64 × 64 tiles), with the tiles in increasing order. The default's unspecified order
/// writes them as its threads finish, so a render repeated with the same seed and budget gave
/// the same pixels in files that differed.
pub const EXR_ENCODING: exr::prelude::Encoding = exr::prelude::Encoding {
    line_order: exr::prelude::LineOrder::Increasing,
    ..exr::prelude::Encoding::FAST_LOSSLESS
};

/// Why an image could not be written (or read back).
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The output path is not an `.exr` file name.
    #[error("output {0} must end in .exr (a PNG is written beside it)")]
    NotExr(String),
    /// The output cannot be created.
    #[error("cannot write {path}: {reason}")]
    Write {
        #[allow(missing_docs)] // named for what it is
        path: String,
        /// The underlying error's message.
        reason: String,
    },
    /// An EXR cannot be read ([`read_exr`]).
    #[error("cannot read {path}: {reason}")]
    Read {
        #[allow(missing_docs)] // named for what it is
        path: String,
        /// The underlying error's message.
        reason: String,
    },
}

fn temporary(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.tmp", std::process::id()))
}

fn write_error(path: &Path, e: impl std::fmt::Display) -> OutputError {
    OutputError::Write { path: path.display().to_string(), reason: e.to_string() }
}

/// The PNG written beside `exr`.
pub fn png_path(exr: &Path) -> PathBuf {
    exr.with_extension("png")
}

/// Checks that `exr` (and the PNG beside it) can be created, by creating and removing a
/// temporary file next to each.
pub fn check_writable(exr: &Path) -> Result<(), OutputError> {
    if exr.extension().and_then(|e| e.to_str()).map(|e| e.eq_ignore_ascii_case("exr")) != Some(true) {
        return Err(OutputError::NotExr(exr.display().to_string()));
    }
    for path in [exr.to_path_buf(), png_path(exr)] {
        if path.is_dir() {
            return Err(write_error(&path, "is a directory"));
        }
        let tmp = temporary(&path);
        std::fs::File::create(&tmp).map_err(|e| write_error(&path, e))?;
        let _ = std::fs::remove_file(&tmp);
    }
    Ok(())
}

/// How bright the PNG is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Exposure {
    /// [`auto_exposure`] of the image.
    Auto,
    /// A fixed exposure in stops: the image is scaled by 2^EV.
    Ev(f32),
}

/// The percentile of the image's luminance that [`auto_exposure`] places at [`AUTO_KEY`].
pub const AUTO_PERCENTILE: f64 = 0.95;
/// The linear value, before the filmic curve, that the [`AUTO_PERCENTILE`] luminance gets.
pub const AUTO_KEY: f32 = 0.8;

/// The automatic exposure in stops: the 95th percentile of the pixels' luminance is scaled to
/// 0.8 before the filmic curve, so that the brightest 5 % (a light seen directly, a caustic)
/// roll off into the shoulder without setting the exposure of everything else. A black image
/// gets 0.
pub fn auto_exposure(rgb: &[f32]) -> f32 {
    let mut lum: Vec<f32> = rgb
        .as_chunks::<3>()
        .0
        .iter()
        .map(|p| shared::color::luminance(glam::Vec3::from_array(*p)))
        .filter(|l| l.is_finite())
        .collect();
    if lum.is_empty() {
        return 0.0;
    }
    let k = ((lum.len() - 1) as f64 * AUTO_PERCENTILE).round() as usize;
    let (_, key, _) = lum.select_nth_unstable_by(k, f32::total_cmp);
    let mut key = *key;
    if !(key > 0.0) {
        key = lum.iter().copied().fold(0.0, f32::max);
    }
    if key > 0.0 {
        (AUTO_KEY / key).log2()
    } else {
        0.0
    }
}

/// A filmic tone curve (Narkowicz's 2015 fit of the ACES reference rendering transform): about
/// linear in the shadows and mid-tones, a soft shoulder towards 1 for highlights.
pub fn filmic(x: f32) -> f32 {
    let x = x.max(0.0);
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// The PNG's 8-bit sRGB codes of a linear rgb image at `ev` stops through [`filmic`].
pub fn tone_map(rgb: &[f32], ev: f32) -> Vec<u8> {
    let scale = ev.exp2();
    rgb.iter().map(|v| srgb8(filmic(if v.is_finite() { v * scale } else { 0.0 }))).collect()
}

impl Exposure {
    /// The exposure in stops for `rgb`.
    pub fn stops(&self, rgb: &[f32]) -> f32 {
        match self {
            Exposure::Auto => auto_exposure(rgb),
            Exposure::Ev(ev) => *ev,
        }
    }
}

/// sRGB transfer of a linear value clamped to [0, 1], as an 8-bit code.
pub fn srgb8(linear: f32) -> u8 {
    let x = if linear.is_finite() { linear.clamp(0.0, 1.0) } else { 0.0 };
    let s = if x <= 0.003_130_8 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0 + 0.5) as u8
}

/// Writes the linear rgb image as float EXR at `exr` and a tone-mapped sRGB PNG beside it at
/// the automatic exposure; returns the exposure used, in stops.
pub fn write_images(exr: &Path, width: u32, height: u32, rgb: &[f32]) -> Result<f32, OutputError> {
    write_images_exposed(exr, width, height, rgb, Exposure::Auto)
}

/// [`write_images`] with the PNG at `exposure`; returns the exposure used, in stops.
pub fn write_images_exposed(
    exr: &Path,
    width: u32,
    height: u32,
    rgb: &[f32],
    exposure: Exposure,
) -> Result<f32, OutputError> {
    let tmp = temporary(exr);
    let w = width as usize;
    {
        use exr::prelude::*;
        let channels = SpecificChannels::rgb(|Vec2(x, y)| {
            let i = (x + y * w) * 3;
            (rgb[i], rgb[i + 1], rgb[i + 2])
        });
        let layer = Layer::new((w, height as usize), LayerAttributes::default(), EXR_ENCODING, channels);
        Image::from_layer(layer).write().to_file(&tmp).map_err(|e| write_error(exr, e))?;
    }
    std::fs::rename(&tmp, exr).map_err(|e| write_error(exr, e))?;
    let png = png_path(exr);
    let tmp = temporary(&png);
    let ev = exposure.stops(rgb);
    let img = image::RgbImage::from_raw(width, height, tone_map(rgb, ev))
        .expect("rgb buffer of width × height × 3");
    img.save_with_format(&tmp, image::ImageFormat::Png).map_err(|e| write_error(&png, e))?;
    std::fs::rename(&tmp, &png).map_err(|e| write_error(&png, e))?;
    Ok(ev)
}

/// Reads an rgb float EXR (first layer) as (width, height, rgb).
pub fn read_exr(path: &Path) -> Result<(u32, u32, Vec<f32>), OutputError> {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _| (resolution.width(), vec![0.0f32; resolution.width() * resolution.height() * 3]),
        |(w, px), position, (r, g, b, _a): (f32, f32, f32, f32)| {
            let i = (position.x() + position.y() * *w) * 3;
            px[i] = r;
            px[i + 1] = g;
            px[i + 2] = b;
        },
    )
    .map_err(|e| OutputError::Read { path: path.display().to_string(), reason: e.to_string() })?;
    let size = image.layer_data.size;
    Ok((size.width() as u32, size.height() as u32, image.layer_data.channel_data.pixels.1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filmic_is_monotone_from_black_to_white() {
        assert_eq!(filmic(0.0), 0.0);
        assert_eq!(filmic(-1.0), 0.0);
        assert_eq!(filmic(1e9), 1.0);
        let mut last = 0.0;
        for i in 1..1000 {
            let y = filmic(i as f32 * 0.01);
            assert!(y >= last, "{i}");
            last = y;
        }
        // highlights roll off instead of clipping: 2 and 4 still differ
        assert!(filmic(2.0) < 0.95 && filmic(4.0) > filmic(2.0) + 0.05);
    }

    /// The automatic exposure puts the 95th percentile at the key, whatever the image's scale,
    /// and ignores a few very bright pixels.
    #[test]
    fn auto_exposure_follows_the_image_not_its_brightest_pixels() {
        let mut rgb: Vec<f32> = (0..1000).flat_map(|i| [i as f32 / 1000.0; 3]).collect();
        for v in rgb.iter_mut().take(30) {
            *v = 1e4; // a light seen directly
        }
        let ev = auto_exposure(&rgb);
        let dim: Vec<f32> = rgb.iter().map(|v| v / 64.0).collect();
        assert!((auto_exposure(&dim) - (ev + 6.0)).abs() < 1e-4, "64× darker: 6 stops more");
        assert!(ev > -1.0 && ev < 1.0, "{ev}");
        assert_eq!(auto_exposure(&[0.0; 30]), 0.0);
        assert_eq!(auto_exposure(&[]), 0.0);
    }
}
