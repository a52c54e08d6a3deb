//! Writing images: a linear float OpenEXR and a tone-mapped sRGB PNG beside it. Each file is
//! written to a temporary name in the same directory and renamed into place, so an interrupted
//! render never leaves a broken image; [`check_writable`] refuses an unwritable path before
//! any rendering starts.

use std::path::{Path, PathBuf};

/// Why an image could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The output path is not an `.exr` file name.
    #[error("output {0} must end in .exr (a PNG is written beside it)")]
    NotExr(String),
    /// The output cannot be created.
    #[error("cannot write {path}: {reason}")]
    Write {
        /// The path.
        path: String,
        /// Why.
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

/// sRGB transfer of a linear value clamped to [0, 1], as an 8-bit code.
pub fn srgb8(linear: f32) -> u8 {
    let x = if linear.is_finite() { linear.clamp(0.0, 1.0) } else { 0.0 };
    let s = if x <= 0.003_130_8 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0 + 0.5) as u8
}

/// Writes the linear rgb image as float EXR at `exr` and a clamped sRGB PNG beside it.
pub fn write_images(exr: &Path, width: u32, height: u32, rgb: &[f32]) -> Result<(), OutputError> {
    let tmp = temporary(exr);
    let w = width as usize;
    exr::prelude::write_rgb_file(&tmp, w, height as usize, |x, y| {
        let i = (x + y * w) * 3;
        (rgb[i], rgb[i + 1], rgb[i + 2])
    })
    .map_err(|e| write_error(exr, e))?;
    std::fs::rename(&tmp, exr).map_err(|e| write_error(exr, e))?;
    let png = png_path(exr);
    let tmp = temporary(&png);
    let bytes: Vec<u8> = rgb.iter().map(|v| srgb8(*v)).collect();
    let img = image::RgbImage::from_raw(width, height, bytes).expect("rgb buffer of width × height × 3");
    img.save_with_format(&tmp, image::ImageFormat::Png).map_err(|e| write_error(&png, e))?;
    std::fs::rename(&tmp, &png).map_err(|e| write_error(&png, e))?;
    Ok(())
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
    .map_err(|e| write_error(path, e))?;
    let size = image.layer_data.size;
    Ok((size.width() as u32, size.height() as u32, image.layer_data.channel_data.pixels.1))
}
