//! From a file's bytes to a glTF document and its buffers, as the glTF 2.0 spec reads them.
//!
//! The gltf crate's types and validation are stricter than the spec in a few places, and the
//! Khronos validator's own assets (`tests/khronos/`) hold valid files that it refuses. So the
//! JSON is first made what the crate can hold, with nothing the spec means changed:
//! - numbers written as floats with an integral value (`0.0` for an index) become integers;
//! - a scene without `nodes` gets an empty list;
//! - `animations` are dropped: smlt renders one instant and reads none of them (said once, as
//!   a warning, where a file has any);
//! - an accessor no mesh primitive reads becomes a stub, as nothing reads it.
//!
//! Then the crate's validation runs, less what the spec allows: an accessor without a
//! `bufferView` (its values are zeros, or its sparse values), a texture whose image comes from an
//! extension or the application, and a primitive without positions (skipped). Images are not
//! decoded here (`super::textures` reads those the materials use). Buffers are read from the
//! file's own folder or `data:` URIs; a buffer whose data is not in the file (no URI in a `.gltf`,
//! no `BIN` chunk in a `.glb`) or that no mesh reads (whatever its source) reads as zeros, and is
//! refused by name if a mesh uses it ([`Parsed::placeholders`]). An unsupported required
//! extension is refused as such, by name. Last, compressed views (`super::meshopt`) and
//! compressed primitives (`super::draco`) are decoded into buffers of their own.

use std::path::Path;

use serde_json::Value;

use super::SceneError;

/// A parsed document, its buffers, and what was set aside on the way.
pub struct Parsed {
    #[allow(missing_docs)] // the document
    pub doc: gltf::Document,
    /// Every buffer's bytes, in document order.
    pub buffers: Vec<gltf::buffer::Data>,
    /// Buffers whose data the file does not hold (read as zeros).
    pub placeholders: Vec<usize>,
    /// What was read leniently or set aside, for the loader's warnings.
    pub warnings: Vec<String>,
}

/// Parses `bytes` (a `.gltf` or a `.glb`) named `name`, whose external buffers lie relative to
/// `base` (None: a document held in memory, which may use `data:` URIs only).
pub fn parse(bytes: &[u8], name: &str, base: Option<&Path>) -> Result<Parsed, SceneError> {
    let load = |reason: String| SceneError::Load { path: name.into(), reason };
    let (json, blob) =
        if bytes.starts_with(b"glTF") { split_glb(bytes).map_err(load)? } else { (bytes.to_vec(), None) };
    let mut value: Value =
        serde_json::from_slice(&json).map_err(|e| load(format!("invalid glTF JSON: {e}")))?;
    let mut warnings = Vec::new();
    normalise(&mut value, &mut warnings);
    light_types(&mut value).map_err(|what| SceneError::Unsupported { path: name.into(), what })?;
    let root: gltf::json::Root =
        serde_json::from_value(value).map_err(|e| load(format!("invalid glTF: {e}")))?;
    validate(&root).map_err(|what| match what.strip_prefix("extensionsRequired") {
        Some(_) => {
            SceneError::Unsupported { path: name.into(), what: format!("a required extension: {what}") }
        }
        None => load(format!("invalid glTF: {what}")),
    })?;
    let views = used_views(&root);
    let mut used: Vec<usize> =
        views.iter().filter_map(|&v| root.buffer_views.get(v)).map(super::meshopt::source_buffer).collect();
    used.extend(super::draco::stream_buffers(&root));
    let doc = gltf::Document::from_json_without_validation(root);
    let (mut buffers, placeholders) = read_buffers(&doc, base, blob, &used, name)?;
    // Compressed views and primitives decoded into buffers of their own, which the rest reads
    // as any view.
    let mut root = doc.into_json();
    let malformed = |what| SceneError::Malformed { path: name.into(), what };
    super::meshopt::decompress(&mut root, &mut buffers, &placeholders, &views).map_err(malformed)?;
    super::draco::decompress(&mut root, &mut buffers, &placeholders).map_err(malformed)?;
    let doc = gltf::Document::from_json_without_validation(root);
    Ok(Parsed { doc, buffers, placeholders, warnings })
}

/// Extensions that smlt reads itself, which the gltf crate does not know: the clear coat from
/// the document's JSON, quantised attributes through `super::attributes`, WebP images in
/// `super::textures`, compressed views in `super::meshopt`, compressed primitives in
/// `super::draco`, KTX2 images in `super::ktx2`, a node's instances in `super::instancing`,
/// anisotropic roughness and the sheen in `super::read`.
pub const READ_BY_SMLT: [&str; 9] = [
    "KHR_materials_clearcoat",
    super::read::ANISOTROPY,
    super::read::SHEEN,
    super::validate::MESH_QUANTIZATION,
    super::textures::WEBP,
    super::meshopt::EXTENSION,
    super::draco::EXTENSION,
    super::ktx2::EXTENSION,
    super::instancing::EXTENSION,
];

/// Appends `bytes` to the document as a buffer of its own (decoded data: no URI), in `root` and
/// in `buffers`; its index.
pub fn append_buffer(
    root: &mut gltf::json::Root,
    buffers: &mut Vec<gltf::buffer::Data>,
    bytes: Vec<u8>,
) -> usize {
    root.buffers.push(gltf::json::Buffer {
        byte_length: bytes.len().into(),
        name: None,
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    buffers.push(gltf::buffer::Data(bytes));
    buffers.len() - 1
}

/// What the gltf crate's types cannot hold but the spec allows, made what they can (see the
/// module doc).
fn normalise(value: &mut Value, warnings: &mut Vec<String>) {
    integers(value);
    // An accessor no mesh primitive reads is never read: a stub keeps the indices of the others
    // and leaves nothing in it to trip over (an unknown type, say).
    let used = used_accessor_indices(value);
    if let Some(accessors) = value.get_mut("accessors").and_then(Value::as_array_mut) {
        for (i, a) in accessors.iter_mut().enumerate() {
            if !used.contains(&i) {
                *a = serde_json::json!({"componentType": 5126, "count": 1, "type": "SCALAR"});
            }
        }
    }
    if let Some(scenes) = value.get_mut("scenes").and_then(Value::as_array_mut) {
        for scene in scenes.iter_mut().filter_map(Value::as_object_mut) {
            scene.entry("nodes").or_insert_with(|| Value::Array(Vec::new()));
        }
    }
    if let Some(object) = value.as_object_mut() {
        if let Some(animations) = object.remove("animations") {
            let n = animations.as_array().map_or(0, Vec::len);
            warnings.push(format!("{n} animation(s) ignored: smlt renders the scene as it stands"));
        }
    }
}

/// The light types `KHR_lights_punctual` defines.
const LIGHT_TYPES: [&str; 3] = ["directional", "point", "spot"];

/// A punctual light of a type the extension does not define (a later extension's, say) is
/// refused by name where a node uses it, and made an unlit point light where none does (the
/// spec lets an unused object be anything the reader can ignore).
fn light_types(value: &mut Value) -> Result<(), String> {
    let used: Vec<u64> = value
        .get("nodes")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(|n| n.pointer("/extensions/KHR_lights_punctual/light").and_then(Value::as_u64))
        .collect();
    let Some(lights) =
        value.pointer_mut("/extensions/KHR_lights_punctual/lights").and_then(Value::as_array_mut)
    else {
        return Ok(());
    };
    for (i, light) in lights.iter_mut().enumerate() {
        let ty = light.get("type").and_then(Value::as_str).unwrap_or_default().to_string();
        if LIGHT_TYPES.contains(&ty.as_str()) {
            continue;
        }
        if used.contains(&(i as u64)) {
            return Err(format!(
                "extensions.KHR_lights_punctual.lights[{i}].type: '{ty}' (smlt reads {})",
                LIGHT_TYPES.join(", ")
            ));
        }
        *light = serde_json::json!({"type": "point", "intensity": 0.0});
    }
    Ok(())
}

/// The accessors a mesh primitive reads, from the JSON (attributes, morph targets, indices), and
/// those of a node's instances (`super::instancing`) and of a skin's inverse bind matrices
/// (`super::skin`).
fn used_accessor_indices(value: &Value) -> Vec<usize> {
    let mut used = Vec::new();
    let index = |v: &Value| v.as_u64().map(|i| i as usize);
    for node in value.get("nodes").and_then(Value::as_array).into_iter().flatten() {
        let instancing = node.get("extensions").and_then(|e| e.get(super::instancing::EXTENSION));
        if let Some(map) = instancing.and_then(|i| i.get("attributes")).and_then(Value::as_object) {
            used.extend(map.values().filter_map(index));
        }
    }
    for skin in value.get("skins").and_then(Value::as_array).into_iter().flatten() {
        used.extend(skin.get("inverseBindMatrices").and_then(index));
    }
    for mesh in value.get("meshes").and_then(Value::as_array).into_iter().flatten() {
        for prim in mesh.get("primitives").and_then(Value::as_array).into_iter().flatten() {
            let maps = prim
                .get("attributes")
                .into_iter()
                .chain(prim.get("targets").and_then(Value::as_array).into_iter().flatten());
            for map in maps.filter_map(Value::as_object) {
                used.extend(map.values().filter_map(index));
            }
            used.extend(prim.get("indices").and_then(index));
        }
    }
    used
}

/// Every float with an integral value in `v` as an integer (JSON does not tell them apart; the
/// gltf crate's index and count fields want integers).
fn integers(v: &mut Value) {
    match v {
        Value::Number(n) if !n.is_i64() && !n.is_u64() => {
            if let Some(f) = n.as_f64() {
                if f.fract() == 0.0 && f.abs() < 9.0e15 {
                    *v = if f < 0.0 { Value::from(f as i64) } else { Value::from(f as u64) };
                }
            }
        }
        Value::Array(items) => items.iter_mut().for_each(integers),
        Value::Object(fields) => fields.values_mut().for_each(integers),
        _ => {}
    }
}

/// The gltf crate's validation of `root`, less what the spec allows (see the module doc); the
/// first finding as "path: error".
fn validate(root: &gltf::json::Root) -> Result<(), String> {
    use gltf::json::validation::{Error, Validate};
    let mut findings = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| findings.push((path().to_string(), error)));
    let allowed = |path: &str, error: &Error| {
        let index = |prefix: &str| {
            path.strip_prefix(prefix)
                .and_then(|rest| rest.split(']').next())
                .and_then(|i| i.parse::<usize>().ok())
        };
        if path.starts_with("extensionsRequired[") && matches!(error, Error::Unsupported) {
            // Those smlt reads itself, which the gltf crate does not know.
            return READ_BY_SMLT.iter().any(|e| path.ends_with(&format!("= \"{e}\"")));
        }
        if index("accessors[").is_some() {
            // Zeros (or sparse values) without a view (and so every stub `normalise` left).
            return path.ends_with("].bufferView") && matches!(error, Error::Missing);
        }
        if index("textures[").is_some() {
            // Optional in glTF 2.0: an extension or the application supplies the image.
            return path.ends_with("].source") && matches!(error, Error::Missing);
        }
        // A primitive without positions is skipped (the spec: clients skip it).
        path.starts_with("meshes[")
            && path.ends_with(r#".attributes["POSITION"]"#)
            && matches!(error, Error::Missing)
    };
    match findings.iter().find(|(path, error)| !allowed(path, error)) {
        Some((path, error)) => Err(format!("{path}: {error}")),
        None => Ok(()),
    }
}

/// The buffer views the accessors lie in (their views and sparse views), each once: after
/// `normalise` every accessor left with a view is one a mesh primitive reads.
fn used_views(root: &gltf::json::Root) -> Vec<usize> {
    let views = |a: &gltf::json::Accessor| {
        let sparse =
            a.sparse.iter().flat_map(|s| [s.indices.buffer_view.value(), s.values.buffer_view.value()]);
        a.buffer_view.map(|v| v.value()).into_iter().chain(sparse).collect::<Vec<_>>()
    };
    let mut used: Vec<usize> = root.accessors.iter().flat_map(views).collect();
    used.sort_unstable();
    used.dedup();
    used
}

/// Every buffer's bytes: from the `.glb`'s `BIN` chunk, a `data:` URI or a file beside the
/// document; zeros where the file holds no data (their indices returned too).
fn read_buffers(
    doc: &gltf::Document,
    base: Option<&Path>,
    mut blob: Option<Vec<u8>>,
    used: &[usize],
    name: &str,
) -> Result<(Vec<gltf::buffer::Data>, Vec<usize>), SceneError> {
    let mut buffers = Vec::new();
    let mut placeholders = Vec::new();
    for buffer in doc.buffers() {
        let unsupported = |what: String| SceneError::Unsupported { path: name.into(), what };
        let data = match gltf::buffer::Data::from_source_and_blob(buffer.source(), base, &mut blob) {
            Ok(data) => data,
            // A buffer no mesh reads is never read: whatever is wrong with its source.
            Err(_) if !used.contains(&buffer.index()) => {
                placeholders.push(buffer.index());
                gltf::buffer::Data(vec![0; buffer.length()])
            }
            Err(gltf::Error::MissingBlob) => {
                placeholders.push(buffer.index());
                gltf::buffer::Data(vec![0; buffer.length()])
            }
            Err(gltf::Error::UnsupportedScheme) => {
                return Err(unsupported(format!(
                    "buffers[{}].uri: only files beside the document and data: URIs are read",
                    buffer.index()
                )))
            }
            Err(gltf::Error::ExternalReferenceInSliceImport) => {
                return Err(SceneError::Load {
                    path: name.into(),
                    reason: format!(
                        "buffers[{}] refers to a file, but the document was given without a folder",
                        buffer.index()
                    ),
                })
            }
            Err(e) => return Err(SceneError::Load { path: name.into(), reason: e.to_string() }),
        };
        if data.len() < buffer.length() {
            return Err(SceneError::Malformed {
                path: name.into(),
                what: format!(
                    "buffers[{}]: byteLength {} but its data holds {} bytes",
                    buffer.index(),
                    buffer.length(),
                    data.len()
                ),
            });
        }
        buffers.push(data);
    }
    Ok((buffers, placeholders))
}

/// The JSON and the `BIN` chunk of a `.glb` (the spec's layout: a 12-byte header, a JSON chunk,
/// then chunks of which the first `BIN` one is the buffer); bytes after the header's length and
/// chunks of other types are ignored, as the spec asks of readers.
fn split_glb(bytes: &[u8]) -> Result<(Vec<u8>, Option<Vec<u8>>), String> {
    let word =
        |at: usize| bytes.get(at..at + 4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]) as usize);
    let version = word(4).ok_or("the .glb header is cut short")?;
    if version != 2 {
        return Err(format!("binary glTF version {version} (this reads version 2)"));
    }
    let total = word(8).ok_or("the .glb header is cut short")?.min(bytes.len());
    let (mut at, mut json, mut bin) = (12usize, None, None);
    while at + 8 <= total {
        let (length, kind) = (word(at).unwrap_or(0), word(at + 4).unwrap_or(0));
        let data =
            bytes.get(at + 8..(at + 8).saturating_add(length)).ok_or("a .glb chunk runs past the file")?;
        match kind {
            0x4E4F534A if json.is_none() => json = Some(data.to_vec()),
            0x004E4942 if json.is_some() && bin.is_none() => bin = Some(data.to_vec()),
            _ => {}
        }
        at = at + 8 + length.next_multiple_of(4);
    }
    Ok((json.ok_or("the .glb has no JSON chunk")?, bin))
}
