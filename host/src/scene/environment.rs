//! The environment light a render is given (`--environment`): a latitude-longitude image in
//! OpenEXR (`.exr`, its first RGB(A) layer) or Radiance HDR (`.hdr`) of linear radiance, or a
//! constant colour (`0.5,0.6,0.8`, or one grey value), scaled by a strength and turned about
//! +Y. The image's orientation is Mitsuba 3's `envmap`'s (`shared::environment`).

use std::path::Path;

use shared::environment::EnvironmentMap;

use super::SceneError;

/// Rows of a constant environment (one texel wide): its sampling follows sin θ row by row.
const CONSTANT_ROWS: u32 = 64;

/// What a render was asked to light its scene with.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentSpec {
    /// A file path, or a constant colour.
    pub source: String,
    /// The factor every texel is scaled by.
    pub strength: f32,
    /// The rotation about +Y in degrees.
    pub rotation_degrees: f32,
}

impl EnvironmentSpec {
    /// Reads the image (or parses the colour) and builds the light, or says in one line why
    /// not: a missing or unreadable file, another format, a texel that is not a finite
    /// non-negative number.
    pub fn read(&self) -> Result<EnvironmentMap, SceneError> {
        let fail = |what: String| SceneError::Environment { given: self.source.clone(), what };
        if !(self.strength.is_finite() && self.strength >= 0.0) {
            return Err(fail(format!("strength {}: must be a finite number ≥ 0", self.strength)));
        }
        if !self.rotation_degrees.is_finite() {
            return Err(fail(format!(
                "rotation {}: must be a finite number of degrees",
                self.rotation_degrees
            )));
        }
        let (width, height, mut texels) = match constant(&self.source) {
            Some(colour) => (1, CONSTANT_ROWS, vec![colour?; CONSTANT_ROWS as usize]),
            None => read_image(Path::new(&self.source))?,
        };
        if let Some((k, t)) =
            texels.iter().enumerate().find(|(_, t)| !t.iter().all(|c| c.is_finite() && *c >= 0.0))
        {
            let (x, y) = (k as u32 % width, k as u32 / width);
            return Err(fail(format!("texel ({x}, {y}) is {t:?}: radiance must be finite and ≥ 0")));
        }
        for t in &mut texels {
            for c in t.iter_mut() {
                *c *= self.strength;
            }
        }
        Ok(EnvironmentMap::new(width, height, &texels, self.rotation_degrees.to_radians()))
    }

    /// What the render summary and a part's identity say of it.
    pub fn describe(&self) -> String {
        format!("{} × {} rotated {}°", self.source, self.strength, self.rotation_degrees)
    }
}

/// The colour of a constant environment's source (`r,g,b` or one grey value), None when the
/// source is not one (a file path), or an error when it is but a value is out of range.
fn constant(source: &str) -> Option<Result<[f32; 3], SceneError>> {
    let values: Vec<f32> =
        source.split(',').map(|v| v.trim().parse::<f32>()).collect::<Result<_, _>>().ok()?;
    let rgb = match values[..] {
        [g] => [g; 3],
        [r, g, b] => [r, g, b],
        _ => {
            return Some(Err(SceneError::Environment {
                given: source.into(),
                what: "a constant colour is one value or three (r,g,b)".into(),
            }))
        }
    };
    if !rgb.iter().all(|c| c.is_finite() && *c >= 0.0) {
        return Some(Err(SceneError::Environment {
            given: source.into(),
            what: "a constant colour's values must be finite and ≥ 0".into(),
        }));
    }
    Some(Ok(rgb))
}

/// A lat-long image's size and linear rgb texels, row after row from the top.
fn read_image(path: &Path) -> Result<(u32, u32, Vec<[f32; 3]>), SceneError> {
    let shown = path.display().to_string();
    let fail = |what: String| SceneError::Environment { given: shown.clone(), what };
    if !path.is_file() {
        return Err(fail(if path.exists() { "is not a file".into() } else { "no such file".into() }));
    }
    let extension = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    let (width, height, texels) = match extension.as_str() {
        "exr" => {
            use exr::prelude::*;
            let image = read_first_rgba_layer_from_file(
                path,
                |size, _| (size.width(), vec![[0.0f32; 3]; size.area()]),
                |(width, texels): &mut (usize, Vec<[f32; 3]>), at, (r, g, b, _a): (f32, f32, f32, f32)| {
                    texels[at.y() * *width + at.x()] = [r, g, b];
                },
            )
            .map_err(|e| fail(format!("cannot read it as OpenEXR: {e}")))?;
            let size = image.layer_data.size;
            (size.width(), size.height(), image.layer_data.channel_data.pixels.1)
        }
        "hdr" => {
            let image = image::ImageReader::open(path)
                .map_err(|e| fail(e.to_string()))?
                .with_guessed_format()
                .map_err(|e| fail(e.to_string()))?
                .decode()
                .map_err(|e| fail(format!("cannot read it as Radiance HDR: {e}")))?
                .into_rgb32f();
            let (w, h) = image.dimensions();
            (w as usize, h as usize, image.pixels().map(|p| p.0).collect())
        }
        _ => return Err(fail("reads .exr and .hdr images, or a constant colour such as 0.5,0.6,0.8".into())),
    };
    if width == 0 || height == 0 || width > 1 << 16 || height > 1 << 15 {
        return Err(fail(format!("its size {width} × {height} is not a lat-long map's")));
    }
    Ok((width as u32, height as u32, texels))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(source: &str) -> EnvironmentSpec {
        EnvironmentSpec { source: source.into(), strength: 2.0, rotation_degrees: 0.0 }
    }

    #[test]
    fn constant_colours_parse_and_scale() {
        let env = spec("0.5, 0.25,1").read().unwrap();
        assert_eq!((env.environment.width, env.environment.height), (1, CONSTANT_ROWS));
        assert_eq!(&env.map[..3], &[1.0, 0.5, 2.0]);
        let grey = spec("0.3").read().unwrap();
        assert_eq!(&grey.map[..3], &[0.6, 0.6, 0.6]);
    }

    #[test]
    fn bad_sources_are_refused_in_one_line() {
        let message = |s: &EnvironmentSpec| s.read().unwrap_err().to_string();
        assert!(message(&spec("1,2")).contains("one value or three"));
        assert!(message(&spec("1,-2,3")).contains("≥ 0"));
        assert!(message(&spec("/nonexistent/sky.exr")).contains("no such file"));
        let dir = std::env::temp_dir().join(format!("smlt-env-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let png = dir.join("sky.png");
        std::fs::write(&png, b"not really").unwrap();
        assert!(message(&spec(png.to_str().unwrap())).contains("reads .exr and .hdr"));
        let exr = dir.join("sky.exr");
        std::fs::write(&exr, b"not an exr").unwrap();
        assert!(message(&spec(exr.to_str().unwrap())).contains("cannot read it as OpenEXR"));
        let mut s = spec("1");
        s.strength = f32::NAN;
        assert!(message(&s).contains("strength"));
        for m in [message(&spec("1,2")), message(&spec(exr.to_str().unwrap()))] {
            assert!(!m.contains('\n'), "{m}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    /// An EXR written with the exr crate reads back texel for texel, top row first.
    #[test]
    fn exr_images_read_top_row_first() {
        let dir = std::env::temp_dir().join(format!("smlt-env-exr-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("sky.exr");
        exr::prelude::write_rgb_file(&path, 4, 2, |x, y| (x as f32, y as f32, 0.5)).unwrap();
        let env = spec(path.to_str().unwrap()).read().unwrap();
        assert_eq!((env.environment.width, env.environment.height), (4, 2));
        // Texel (3, 1) scaled by 2: its rgb at 4 floats a texel.
        assert_eq!(&env.map[4 * 7..4 * 7 + 3], &[6.0, 2.0, 1.0]);
        std::fs::remove_dir_all(&dir).ok();
    }
}
