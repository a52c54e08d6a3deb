//! glTF's textures read into the one texel store the kernels sample (`shared::texture`): each
//! image decoded once to RGBA8 (PNG and JPEG, the two the spec defines, and WebP,
//! `EXT_texture_webp`'s, through the `image` crate; KTX2 with Basis Universal data,
//! `KHR_texture_basisu`'s, through [`super::ktx2`]), each texture (an image with a sampler) once
//! however many materials use it. Only the textures a material reads are loaded. A texture with
//! one of the two extensions reads the extension's image, not its `source` (the spec's fallback
//! for clients without the extension).
//!
//! What is read of a sampler: its wrap modes, and its magnification filter (NEAREST, or
//! bilinear for LINEAR and by default); its minification filter is not (no mip-maps: a path
//! tracer's pixel samples filter a minified texture, see `shared::texture`). An image in
//! another encoding (another extension's source) is not read: the texture is left out with a
//! warning naming it, and its factor is used. An image that claims one of the four encodings
//! and does not decode is refused by name.

use std::collections::HashMap;
use std::path::Path;

use base64::Engine;
use shared::texture::{
    texture_transform, Texture, TextureRef, IDENTITY, WRAP_CLAMP, WRAP_MIRROR, WRAP_REPEAT,
};

use super::SceneError;

/// The extension whose texture source is a WebP image.
pub const WEBP: &str = "EXT_texture_webp";

/// The extensions that give a texture an image in place of its `source`, the first present read.
const SOURCE_EXTENSIONS: [&str; 2] = [super::ktx2::EXTENSION, WEBP];

/// The textures and texels read so far.
#[derive(Default)]
pub struct TextureStore {
    /// In the order first used (`TextureRef::texture` indexes them).
    pub textures: Vec<Texture>,
    /// Every image's texels, RGBA8 packed red-first.
    pub texels: Vec<u32>,
    /// glTF texture index → its entry (None: not readable, warned).
    loaded: HashMap<usize, Option<u32>>,
    /// glTF image index → (offset, width, height) in `texels`.
    images: HashMap<usize, (u32, u32, u32)>,
}

/// `KHR_texture_transform`'s fields (the spec's defaults where absent).
#[derive(serde::Deserialize)]
#[serde(rename_all = "camelCase")]
struct Transform {
    #[serde(default)]
    offset: [f32; 2],
    #[serde(default)]
    rotation: f32,
    #[serde(default = "unit_scale")]
    scale: [f32; 2],
    #[serde(default)]
    tex_coord: Option<u32>,
}

fn unit_scale() -> [f32; 2] {
    [1.0, 1.0]
}

/// A textureInfo's `KHR_texture_transform` read from its JSON (`slot` its glTF path).
fn json_transform(
    value: Option<&serde_json::Value>,
    slot: &str,
    source: &Source,
) -> Result<Option<Transform>, SceneError> {
    value
        .map(|v| {
            serde_json::from_value::<Transform>(v.clone()).map_err(|e| SceneError::Malformed {
                path: source.name.into(),
                what: format!("{slot}.extensions.KHR_texture_transform: {e}"),
            })
        })
        .transpose()
}

/// What a texture is read from.
pub struct Source<'a> {
    #[allow(missing_docs)] // the document
    pub doc: &'a gltf::Document,
    /// Every buffer's bytes.
    pub buffers: &'a [gltf::buffer::Data],
    /// Buffers whose data is not in the file.
    pub placeholders: &'a [usize],
    /// The folder external images lie in (None: a document held in memory).
    pub base: Option<&'a Path>,
    /// The scene's name for messages.
    pub name: &'a str,
}

impl TextureStore {
    /// The reference of a material's texture slot `slot` (its glTF path, for messages), or
    /// [`TextureRef::NONE`] where the image cannot be read (warned).
    pub fn reference(
        &mut self,
        source: &Source,
        info: &gltf::texture::Info,
        slot: &str,
        warnings: &mut Vec<String>,
    ) -> Result<TextureRef, SceneError> {
        let transform = info.texture_transform().map(|t| Transform {
            offset: t.offset(),
            rotation: t.rotation(),
            scale: t.scale(),
            tex_coord: t.tex_coord(),
        });
        self.reference_parts(source, info.texture().index(), info.tex_coord(), transform, slot, warnings)
    }

    /// [`TextureStore::reference`] of a material's `normalTexture` (whose info the gltf crate
    /// reads without `KHR_texture_transform`: the extension is read here), and its scale.
    pub fn normal_reference(
        &mut self,
        source: &Source,
        normal: &gltf::material::NormalTexture,
        slot: &str,
        warnings: &mut Vec<String>,
    ) -> Result<(TextureRef, f32), SceneError> {
        let transform = json_transform(normal.extension_value("KHR_texture_transform"), slot, source)?;
        let r = self.reference_parts(
            source,
            normal.texture().index(),
            normal.tex_coord(),
            transform,
            slot,
            warnings,
        )?;
        let scale = normal.scale();
        if !scale.is_finite() {
            return Err(SceneError::Malformed {
                path: source.name.into(),
                what: format!("{slot}.scale: {scale} is not finite"),
            });
        }
        Ok((r, scale))
    }

    /// [`TextureStore::reference`] of a textureInfo that the gltf crate does not read (an
    /// extension's, as JSON: `index`, `texCoord` and its `KHR_texture_transform`), refused in
    /// one line where it names no texture.
    pub fn json_reference(
        &mut self,
        source: &Source,
        info: &serde_json::Value,
        slot: &str,
        warnings: &mut Vec<String>,
    ) -> Result<TextureRef, SceneError> {
        let malformed = |what: String| SceneError::Malformed { path: source.name.into(), what };
        let index = info.get("index").and_then(serde_json::Value::as_u64);
        let index = index.ok_or_else(|| malformed(format!("{slot}: no texture index")))?;
        if index >= source.doc.as_json().textures.len() as u64 {
            return Err(malformed(format!("{slot}.index: {index} names no texture")));
        }
        let tex_coord = match info.get("texCoord") {
            None => 0,
            Some(v) => {
                v.as_u64().ok_or_else(|| malformed(format!("{slot}.texCoord: {v} is not an index")))?
            }
        };
        let transform = json_transform(
            info.get("extensions").and_then(|e| e.get("KHR_texture_transform")),
            slot,
            source,
        )?;
        let tex_coord = u32::try_from(tex_coord).unwrap_or(u32::MAX);
        self.reference_parts(source, index as usize, tex_coord, transform, slot, warnings)
    }

    /// The reference to glTF texture `texture` through `TEXCOORD_<tex_coord>` and `transform`
    /// (`KHR_texture_transform`, whose texCoord overrides `tex_coord`).
    fn reference_parts(
        &mut self,
        source: &Source,
        texture: usize,
        tex_coord: u32,
        transform: Option<Transform>,
        slot: &str,
        warnings: &mut Vec<String>,
    ) -> Result<TextureRef, SceneError> {
        let tex_coord = transform.as_ref().and_then(|t| t.tex_coord).unwrap_or(tex_coord);
        if tex_coord > 1 {
            return Err(SceneError::Unsupported {
                path: source.name.into(),
                what: format!("{slot}: texCoord {tex_coord} (smlt reads TEXCOORD_0 and TEXCOORD_1)"),
            });
        }
        let transform = match transform {
            Some(t) => {
                let m = texture_transform(t.offset, t.rotation, t.scale);
                if !m.iter().all(|x| x.is_finite()) {
                    return Err(SceneError::Malformed {
                        path: source.name.into(),
                        what: format!("{slot}.extensions.KHR_texture_transform: not finite"),
                    });
                }
                m
            }
            None => IDENTITY,
        };
        let Some(index) = self.load(source, texture, slot, warnings)? else {
            return Ok(TextureRef::NONE);
        };
        Ok(TextureRef { texture: index, tex_coord, transform })
    }

    /// The store's entry of glTF texture `texture`, loading it at its first use.
    fn load(
        &mut self,
        source: &Source,
        texture: usize,
        slot: &str,
        warnings: &mut Vec<String>,
    ) -> Result<Option<u32>, SceneError> {
        if let Some(entry) = self.loaded.get(&texture) {
            return Ok(*entry);
        }
        let entry = self.read(source, texture, slot, warnings)?;
        self.loaded.insert(texture, entry);
        Ok(entry)
    }

    fn read(
        &mut self,
        source: &Source,
        texture: usize,
        slot: &str,
        warnings: &mut Vec<String>,
    ) -> Result<Option<u32>, SceneError> {
        let json = source.doc.as_json();
        let tex = &json.textures[texture];
        let extension = SOURCE_EXTENSIONS.iter().find_map(|&name| {
            let others = &tex.extensions.as_ref()?.others;
            Some((name, others.get(name)?.get("source")?))
        });
        let image = match extension {
            Some((name, index)) => match index.as_u64().filter(|&i| (i as usize) < json.images.len()) {
                Some(i) => i as usize,
                None => {
                    return Err(SceneError::Malformed {
                        path: source.name.into(),
                        what: format!("textures[{texture}].extensions.{name}.source: {index} names no image"),
                    })
                }
            },
            None => tex.source.value(),
        };
        if image >= json.images.len() {
            warnings.push(format!(
                "textures[{texture}] (used by {slot}) has no image smlt reads (its source comes from an extension): its factor is used"
            ));
            return Ok(None);
        }
        let (offset, width, height) = match self.images.get(&image) {
            Some(&found) => found,
            None => match self.decode(source, image, slot, warnings)? {
                Some(found) => {
                    self.images.insert(image, found);
                    found
                }
                None => return Ok(None),
            },
        };
        let sampler = tex.sampler.map(|s| &json.samplers[s.value()]);
        let wrap = |mode: Option<&gltf::json::validation::Checked<gltf::json::texture::WrappingMode>>| {
            use gltf::json::texture::WrappingMode::*;
            use gltf::json::validation::Checked::Valid;
            match mode {
                Some(Valid(ClampToEdge)) => WRAP_CLAMP,
                Some(Valid(MirroredRepeat)) => WRAP_MIRROR,
                _ => WRAP_REPEAT,
            }
        };
        let nearest = matches!(
            sampler.and_then(|s| s.mag_filter),
            Some(gltf::json::validation::Checked::Valid(gltf::json::texture::MagFilter::Nearest))
        );
        let sampler =
            Texture::sampler(wrap(sampler.map(|s| &s.wrap_s)), wrap(sampler.map(|s| &s.wrap_t)), nearest);
        self.textures.push(Texture { offset, width, height, sampler });
        Ok(Some(self.textures.len() as u32 - 1))
    }

    /// Decodes image `image` into the texels: its (offset, width, height), or None where its
    /// encoding is not read (warned).
    fn decode(
        &mut self,
        source: &Source,
        image: usize,
        slot: &str,
        warnings: &mut Vec<String>,
    ) -> Result<Option<(u32, u32, u32)>, SceneError> {
        let json = &source.doc.as_json().images[image];
        let at = format!("images[{image}]");
        let malformed = |what: String| SceneError::Malformed { path: source.name.into(), what };
        let bytes: Vec<u8> = if let Some(view) = json.buffer_view {
            let view = source
                .doc
                .views()
                .nth(view.value())
                .ok_or_else(|| malformed(format!("{at}.bufferView: {} does not exist", view.value())))?;
            let buffer = view.buffer().index();
            if source.placeholders.contains(&buffer) {
                return Err(SceneError::Unsupported {
                    path: source.name.into(),
                    what: format!("{at} lies in buffers[{buffer}], whose data could not be read"),
                });
            }
            let data = &source.buffers[buffer].0;
            data.get(view.offset()..view.offset() + view.length())
                .ok_or_else(|| malformed(format!("{at}: its bufferView runs past its buffer")))?
                .to_vec()
        } else if let Some(uri) = &json.uri {
            read_uri(uri, source.base).map_err(|reason| SceneError::Load {
                path: source.name.into(),
                reason: format!("{at} ('{}'): {reason}", short(uri)),
            })?
        } else {
            return Err(malformed(format!("{at}: neither a uri nor a bufferView")));
        };
        if super::ktx2::is_ktx2(&bytes) {
            let transcoder = format!("{at}: the KTX2 transcoder");
            let decoded = super::read::guarded(source.name, &transcoder, || super::ktx2::decode(&bytes))?;
            let decoded = decoded.map_err(|e| match e {
                super::ktx2::Ktx2Error::Malformed(what) => malformed(format!("{at}: {what}")),
                super::ktx2::Ktx2Error::Unsupported(what) => {
                    SceneError::Unsupported { path: source.name.into(), what: format!("{at}: {what}") }
                }
            })?;
            return self.push(source, &at, decoded.width, decoded.height, &decoded.rgba).map(Some);
        }
        let format = match image::guess_format(&bytes) {
            Ok(f @ (image::ImageFormat::Png | image::ImageFormat::Jpeg | image::ImageFormat::WebP)) => f,
            other => {
                let named = json
                    .mime_type
                    .as_ref()
                    .map(|m| m.0.clone())
                    .or_else(|| other.ok().map(|f| format!("{f:?}")))
                    .unwrap_or_else(|| "an encoding that is neither PNG, JPEG nor WebP".into());
                warnings.push(format!(
                    "{at} (used by {slot}) is {named}; smlt reads PNG, JPEG, WebP and KTX2 (Basis Universal): \
                     the texture is left out and its factor used"
                ));
                return Ok(None);
            }
        };
        let decoded = image::load_from_memory_with_format(&bytes, format)
            .map_err(|e| malformed(format!("{at}: its {format:?} data does not decode: {e}")))?;
        let rgba = decoded.to_rgba8();
        let (width, height) = rgba.dimensions();
        self.push(source, &at, width, height, rgba.as_raw()).map(Some)
    }

    /// Appends the `width` × `height` RGBA8 texels `rgba` (rows top first) of image `at` to the
    /// store: their (offset, width, height).
    fn push(
        &mut self,
        source: &Source,
        at: &str,
        width: u32,
        height: u32,
        rgba: &[u8],
    ) -> Result<(u32, u32, u32), SceneError> {
        let offset = self.texels.len();
        if offset + (width as usize) * (height as usize) > u32::MAX as usize {
            return Err(SceneError::Unsupported {
                path: source.name.into(),
                what: format!("{at}: the textures hold more than 2³² texels"),
            });
        }
        self.texels.extend(rgba.as_chunks::<4>().0.iter().map(|&p| u32::from_le_bytes(p)));
        Ok((offset as u32, width, height))
    }
}

/// The bytes behind an image URI: a `data:` URI's (base64) or a file's beside the document.
fn read_uri(uri: &str, base: Option<&Path>) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, data) = rest.split_once(";base64,").ok_or("a data: URI without ;base64,")?;
        return base64::engine::general_purpose::STANDARD
            .decode(data)
            .map_err(|e| format!("bad base64: {e}"));
    }
    if uri.contains("://") {
        return Err("only files beside the document and data: URIs are read".into());
    }
    let base = base.ok_or("the image is a file, but the document was given without a folder")?;
    let path = urlencoding::decode(uri).map_err(|e| e.to_string())?;
    let file = base.join(path.as_ref());
    std::fs::read(&file).map_err(|e| format!("cannot read {}: {e}", file.display()))
}

/// A URI as a message shows it (a data: URI's head only).
fn short(uri: &str) -> String {
    if uri.len() > 48 {
        format!("{}…", &uri[..uri.char_indices().nth(40).map_or(uri.len(), |(i, _)| i)])
    } else {
        uri.to_string()
    }
}
