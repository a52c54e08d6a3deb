//! `KHR_texture_basisu`'s images: KTX2 files holding Basis Universal data (ETC1S with BasisLZ,
//! or UASTC, raw or Zstandard-supercompressed), transcoded to RGBA8 by the `basisu` crate (a
//! port of Binomial's reference transcoder; `scripts/peers/check_ktx2.py` compares it with
//! Binomial's own, three.js's build of it).
//!
//! The base level is read: smlt keeps no mip-maps (see `shared::texture`). The container rules
//! the extension sets that change what the texels mean are checked, each refused in one line:
//! a 2D image (no depth, array layers or cube faces), `KTXorientation` `rd` or absent (rows top
//! first, as glTF's uv reads them), `KTXswizzle` `rgba` or absent, ETC1S or UASTC (LDR) data.
//! An image larger than the `image` crate lets a PNG be (512 MiB of RGBA8), or a Zstandard
//! level whose inflated size is not its blocks', is refused before it is transcoded; the caller
//! runs [`decode`] guarded (`super::read::guarded`), so that a panic in the young transcoder is
//! a refusal in one line too. The DFD's transfer function is not read: as for a PNG, the
//! material slot that samples a texture says whether its values are sRGB-encoded (the spec asks
//! the two to agree).

/// The extension whose texture source is a KTX2 image.
pub const EXTENSION: &str = "KHR_texture_basisu";

/// The twelve bytes every KTX2 file begins with.
const IDENTIFIER: &[u8; 12] = b"\xabKTX 20\xbb\r\n\x1a\n";

/// A transcoded image: rows top first, RGBA8 red first.
#[derive(Debug)]
pub struct Image {
    /// In texels.
    pub width: u32,
    /// In texels.
    pub height: u32,
    /// 4 · width · height bytes.
    pub rgba: Vec<u8>,
}

/// Why a KTX2 image was not read.
#[derive(Debug, PartialEq)]
pub enum Ktx2Error {
    /// Its bytes are not a KTX2 file that decodes.
    Malformed(String),
    /// A valid file of a kind glTF's textures do not hold (an array, a cube map, a video, a
    /// non-Basis format, another orientation or swizzle).
    Unsupported(String),
}

/// Whether `bytes` begin as a KTX2 file.
pub fn is_ktx2(bytes: &[u8]) -> bool {
    bytes.starts_with(IDENTIFIER)
}

/// The little-endian u32 at `at`, if the file holds it.
fn word(bytes: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?))
}

/// The header fields that say what kind of image the file holds.
#[derive(Debug, PartialEq)]
struct Header {
    vk_format: u32,
    depth: u32,
    layers: u32,
    faces: u32,
    supercompression: u32,
    /// The key/value data's byte range.
    kvd: (usize, usize),
}

impl Header {
    fn read(bytes: &[u8]) -> Result<Header, Ktx2Error> {
        let field = |i: usize| word(bytes, 12 + 4 * i);
        let truncated = || Ktx2Error::Malformed("its KTX2 header is cut short".into());
        let kvd_offset = word(bytes, 56).ok_or_else(truncated)? as usize;
        let kvd_length = word(bytes, 60).ok_or_else(truncated)? as usize;
        Ok(Header {
            vk_format: field(0).ok_or_else(truncated)?,
            depth: field(4).ok_or_else(truncated)?,
            layers: field(5).ok_or_else(truncated)?,
            faces: field(6).ok_or_else(truncated)?,
            supercompression: field(8).ok_or_else(truncated)?,
            kvd: (kvd_offset, kvd_offset.saturating_add(kvd_length)),
        })
    }
}

/// The value of key `key` in the key/value data `kvd` (a NUL-terminated string value without
/// its NUL), if present.
fn metadata<'a>(kvd: &'a [u8], key: &str) -> Result<Option<&'a [u8]>, Ktx2Error> {
    let mut at = 0;
    while at < kvd.len() {
        let length = word(kvd, at)
            .map(|l| l as usize)
            .filter(|&l| at + 4 + l <= kvd.len())
            .ok_or_else(|| Ktx2Error::Malformed("its key/value data runs past its end".into()))?;
        let entry = &kvd[at + 4..at + 4 + length];
        if let Some(nul) = entry.iter().position(|&b| b == 0) {
            if &entry[..nul] == key.as_bytes() {
                let value = &entry[nul + 1..];
                return Ok(Some(value.strip_suffix(&[0]).unwrap_or(value)));
            }
        }
        // Each entry is padded to a multiple of four bytes.
        at += (4 + length).next_multiple_of(4);
    }
    Ok(None)
}

/// Decodes the KTX2 file `bytes` (which [`is_ktx2`]) to its base level's RGBA8.
pub fn decode(bytes: &[u8]) -> Result<Image, Ktx2Error> {
    use Ktx2Error::{Malformed, Unsupported};
    let header = Header::read(bytes)?;
    if header.vk_format != 0 {
        return Err(Unsupported(format!(
            "a KTX2 image of vkFormat {}, not Basis Universal data (KHR_texture_basisu's images are; \
             smlt reads no other KTX2)",
            header.vk_format
        )));
    }
    let kind = if header.faces > 1 {
        Some(format!("a cube map ({} faces)", header.faces))
    } else if header.layers > 1 {
        Some(format!("an array of {} layers", header.layers))
    } else if header.depth > 1 {
        Some(format!("a 3D image of depth {}", header.depth))
    } else {
        None
    };
    if let Some(kind) = kind {
        return Err(Unsupported(format!("a KTX2 {kind}; a material's texture is one 2D image")));
    }
    let kvd = bytes
        .get(header.kvd.0..header.kvd.1)
        .ok_or_else(|| Malformed("its key/value data lies past the file's end".into()))?;
    for (key, allowed) in [("KTXorientation", "rd"), ("KTXswizzle", "rgba")] {
        if let Some(value) = metadata(kvd, key)? {
            if value != allowed.as_bytes() {
                return Err(Unsupported(format!(
                    "its {key} is '{}'; glTF allows '{allowed}' only",
                    String::from_utf8_lossy(value)
                )));
            }
        }
    }
    let transcoder = basisu::Transcoder::new(bytes).map_err(|e| match e {
        basisu::Error::UnsupportedFeature(what) => {
            Unsupported(format!("KTX2 content smlt cannot transcode: {what}"))
        }
        e => Malformed(format!("its KTX2 data does not decode ({}): {e:?}", scheme(header.supercompression))),
    })?;
    if transcoder.is_video() {
        return Err(Unsupported("a KTX2 video; a material's texture is one 2D image".into()));
    }
    let format = transcoder.source_format();
    if !matches!(format, basisu::SourceFormat::Etc1s | basisu::SourceFormat::UastcLdr) {
        return Err(Unsupported(format!(
            "a KTX2 image of {format:?} data; KHR_texture_basisu's are ETC1S or UASTC (LDR)"
        )));
    }
    let (width, height) = transcoder.base_dimensions();
    // The `image` crate's own limit on what one PNG, JPEG or WebP may decode to.
    let limit = image::Limits::default().max_alloc.unwrap_or(u64::MAX);
    if 4 * width as u64 * height as u64 > limit {
        return Err(Unsupported(format!(
            "a {width}×{height} KTX2 image, more than the {} MiB one image may decode to",
            limit >> 20
        )));
    }
    if header.supercompression == 2 {
        // A Zstandard level inflates to its UASTC blocks, 16 bytes each; the transcoder
        // allocates what the level index claims before inflating.
        let blocks = u64::from(width.div_ceil(4)) * u64::from(height.div_ceil(4));
        let claimed = bytes.get(96..104).map(|b| u64::from_le_bytes(b.try_into().unwrap()));
        if claimed != Some(16 * blocks) {
            return Err(Malformed(format!(
                "its base level claims {} inflated bytes, not the {} of its {width}×{height} UASTC blocks",
                claimed.map_or("no".into(), |c| c.to_string()),
                16 * blocks
            )));
        }
    }
    let rgba =
        transcoder.transcode(0, basisu::TargetFormat::Rgba32, basisu::DecodeFlags::NONE).map_err(|e| {
            Malformed(format!("its KTX2 data does not decode ({}): {e:?}", scheme(header.supercompression)))
        })?;
    if rgba.len() != 4 * width as usize * height as usize {
        return Err(Malformed(format!("its {width}×{height} KTX2 image transcoded to {} bytes", rgba.len())));
    }
    Ok(Image { width, height, rgba })
}

/// KTX2's name of a supercompression scheme, for messages.
fn scheme(supercompression: u32) -> &'static str {
    match supercompression {
        0 => "no supercompression",
        1 => "BasisLZ",
        2 => "Zstandard",
        3 => "ZLIB",
        _ => "an unknown supercompression",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The key/value data of `entries`, each padded as KTX2 pads it.
    fn kvd(entries: &[(&str, &str)]) -> Vec<u8> {
        let mut out = Vec::new();
        for (key, value) in entries {
            let entry = [key.as_bytes(), &[0], value.as_bytes(), &[0]].concat();
            out.extend((entry.len() as u32).to_le_bytes());
            out.extend(&entry);
            out.resize(out.len().next_multiple_of(4), 0);
        }
        out
    }

    #[test]
    fn metadata_finds_a_key_after_padded_entries() {
        let data = kvd(&[("KTXwriter", "toktx v4"), ("KTXorientation", "rd"), ("KTXswizzle", "rgb1")]);
        assert_eq!(metadata(&data, "KTXorientation").unwrap(), Some(&b"rd"[..]));
        assert_eq!(metadata(&data, "KTXswizzle").unwrap(), Some(&b"rgb1"[..]));
        assert_eq!(metadata(&data, "KTXanimData").unwrap(), None);
        let mut cut = data.clone();
        cut[0] = 200; // the first entry claims more bytes than there are
        assert!(matches!(metadata(&cut, "KTXswizzle"), Err(Ktx2Error::Malformed(_))));
    }

    /// A KTX2 header of the given fields (no levels, no DFD) followed by `kvd`.
    fn header(vk_format: u32, [depth, layers, faces]: [u32; 3], kvd: &[u8]) -> Vec<u8> {
        let mut out = IDENTIFIER.to_vec();
        for field in [vk_format, 1, 4, 4, depth, layers, faces, 1, 0] {
            out.extend(field.to_le_bytes());
        }
        for field in [0u32, 0, 80, kvd.len() as u32, 0, 0, 0, 0] {
            out.extend(field.to_le_bytes());
        }
        out.extend(kvd);
        out
    }

    #[test]
    fn what_a_gltf_texture_cannot_be_is_refused_before_transcoding() {
        let unsupported = |bytes: Vec<u8>, said: &str| match decode(&bytes) {
            Err(Ktx2Error::Unsupported(what)) => assert!(what.contains(said), "{what}"),
            other => panic!("{said}: {other:?}"),
        };
        assert!(is_ktx2(&header(0, [0, 0, 1], &[])));
        unsupported(header(37, [0, 0, 1], &[]), "vkFormat 37");
        unsupported(header(0, [0, 6, 1], &[]), "an array of 6 layers");
        unsupported(header(0, [0, 0, 6], &[]), "a cube map (6 faces)");
        unsupported(header(0, [4, 0, 1], &[]), "a 3D image of depth 4");
        unsupported(header(0, [0, 0, 1], &kvd(&[("KTXorientation", "ru")])), "KTXorientation is 'ru'");
        unsupported(header(0, [0, 0, 1], &kvd(&[("KTXswizzle", "rrr1")])), "KTXswizzle is 'rrr1'");
        // Allowed metadata passes to the transcoder, which finds no Basis data here.
        let bytes = header(0, [0, 0, 1], &kvd(&[("KTXorientation", "rd"), ("KTXswizzle", "rgba")]));
        assert!(matches!(decode(&bytes), Err(Ktx2Error::Malformed(_))));
        assert!(
            matches!(decode(&IDENTIFIER[..]), Err(Ktx2Error::Malformed(what)) if what.contains("cut short"))
        );
    }
}
