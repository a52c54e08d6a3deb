//! Structural validation of a glTF document before anything reads it, the way the Khronos
//! glTF validator reads a file: every buffer view within its buffer, every accessor within its
//! buffer view (stride included), index counts a multiple of 3, camera and node values in the
//! ranges the specification gives, material factors in [0, 1], a finite emission strength.
//! The first problem is returned as one line naming the element by its glTF path
//! (`accessors[3]`, `nodes[1].rotation`). What is checked while the triangles are read (indices
//! below the vertex count, finite positions) is in the reader.

use serde_json::Value;

/// Checks `root` (the document's JSON) against `buffers` (the bytes each buffer holds).
pub fn validate(root: &Value, buffers: &[usize]) -> Result<(), String> {
    let list = |key: &str| root.get(key).and_then(Value::as_array).map(Vec::as_slice).unwrap_or(&[]);
    let buffer_lengths: Vec<u64> = list("buffers")
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let declared = uint(b, "byteLength", &format!("buffers[{i}]"))?.unwrap_or(0);
            let held = buffers.get(i).copied().unwrap_or(0) as u64;
            if declared > held {
                return Err(format!(
                    "buffers[{i}]: byteLength is {declared} but the buffer holds {held} bytes"
                ));
            }
            Ok(declared)
        })
        .collect::<Result<_, _>>()?;
    let mut views = Vec::new();
    for (i, v) in list("bufferViews").iter().enumerate() {
        let at = format!("bufferViews[{i}]");
        let buffer = uint(v, "buffer", &at)?.ok_or(format!("{at}: no buffer"))?;
        let length =
            *buffer_lengths.get(buffer as usize).ok_or(format!("{at}: buffer {buffer} does not exist"))?;
        let offset = uint(v, "byteOffset", &at)?.unwrap_or(0);
        let size = uint(v, "byteLength", &at)?.ok_or(format!("{at}: no byteLength"))?;
        if offset.saturating_add(size) > length {
            return Err(format!(
                "{at}: byteOffset {offset} + byteLength {size} runs past the end of buffers[{buffer}] ({length} bytes)"
            ));
        }
        let stride = uint(v, "byteStride", &at)?;
        if let Some(s) = stride {
            if !(4..=252).contains(&s) || s % 4 != 0 {
                return Err(format!("{at}: byteStride {s} is not a multiple of 4 in 4..=252"));
            }
        }
        views.push((size, stride));
    }
    let accessors = list("accessors");
    let mut counts = Vec::new();
    for (i, a) in accessors.iter().enumerate() {
        let at = format!("accessors[{i}]");
        let count = uint(a, "count", &at)?.ok_or(format!("{at}: no count"))?;
        if count == 0 {
            return Err(format!("{at}: count is 0"));
        }
        let component = match uint(a, "componentType", &at)? {
            Some(5120 | 5121) => 1,
            Some(5122 | 5123) => 2,
            Some(5125 | 5126) => 4,
            other => return Err(format!("{at}: componentType {other:?} is not a glTF component type")),
        };
        let components = match a.get("type").and_then(Value::as_str) {
            Some("SCALAR") => 1,
            Some("VEC2") => 2,
            Some("VEC3") => 3,
            Some("VEC4") | Some("MAT2") => 4,
            Some("MAT3") => 9,
            Some("MAT4") => 16,
            other => return Err(format!("{at}: type {other:?} is not a glTF accessor type")),
        };
        let element = component * components;
        if let Some(view) = uint(a, "bufferView", &at)? {
            let (size, stride) =
                *views.get(view as usize).ok_or(format!("{at}: bufferView {view} does not exist"))?;
            let offset = uint(a, "byteOffset", &at)?.unwrap_or(0);
            if offset % component != 0 {
                return Err(format!(
                    "{at}: byteOffset {offset} is not a multiple of its component size {component}"
                ));
            }
            let stride = stride.unwrap_or(element);
            let end = (offset as u128) + (stride as u128) * (count as u128 - 1) + element as u128;
            if end > size as u128 {
                return Err(format!(
                    "{at}: {count} elements of {element} bytes (stride {stride}) from byteOffset {offset} run past \
                     the end of bufferViews[{view}] ({size} bytes)"
                ));
            }
        }
        if let Some(sparse) = a.get("sparse") {
            check_sparse(sparse, count, component * components, &views, &format!("{at}.sparse"))?;
        }
        let normalized = a.get("normalized").and_then(Value::as_bool).unwrap_or(false);
        counts.push((
            count,
            component,
            components,
            a.get("componentType").and_then(Value::as_u64),
            normalized,
        ));
    }
    // KHR_mesh_quantization's integer attributes, where the file declares it: required, as the
    // extension says it must be (the validator's NON_REQUIRED_EXTENSION).
    let declares = |key: &str| list(key).iter().any(|e| e.as_str() == Some(MESH_QUANTIZATION));
    let quantized = declares("extensionsUsed");
    if quantized && !declares("extensionsRequired") {
        return Err(format!(
            "extensionsRequired: {MESH_QUANTIZATION} is used but not required (the extension cannot be optional)"
        ));
    }
    for (m, mesh) in list("meshes").iter().enumerate() {
        let primitives = mesh.get("primitives").and_then(Value::as_array).map(Vec::as_slice).unwrap_or(&[]);
        for (p, prim) in primitives.iter().enumerate() {
            let at = format!("meshes[{m}].primitives[{p}]");
            match uint(prim, "mode", &at)?.unwrap_or(4) {
                0..=3 => continue, // points and lines: the reader skips them
                4..=6 => {}        // triangles, strips, fans
                mode => return Err(format!("{at}.mode: {mode} is not a glTF primitive mode")),
            }
            if prim.get("attributes").and_then(|a| a.get("POSITION")).is_none() {
                continue; // nothing to draw: the reader skips it, as the spec says
            }
            // The attributes the reader reads, of the types the spec allows them: read as another
            // type, their values would be misread, not refused.
            let attributes = prim.get("attributes").and_then(Value::as_object).into_iter().flatten();
            for (name, accessor) in attributes {
                let Some(types) = AttributeTypes::of(name) else { continue };
                let Some(&(_, _, components, kind, normalized)) =
                    accessor.as_u64().and_then(|k| counts.get(k as usize))
                else {
                    return Err(format!("{at}: {name} accessor {accessor} does not exist"));
                };
                if !types.allows(components, kind, normalized, quantized) {
                    return Err(format!("{at}: {name} must be {}", types.describe(quantized)));
                }
            }
            // An index (or vertex) count that is no multiple of 3 leaves an incomplete triangle,
            // which the reader drops with a warning (the validator's warning
            // MESH_PRIMITIVE_INCOMPATIBLE_MODE).
            if let Some(k) = uint(prim, "indices", &at)? {
                let &(_, _, components, kind, _) =
                    counts.get(k as usize).ok_or(format!("{at}.indices: accessors[{k}] does not exist"))?;
                if components != 1 || !matches!(kind, Some(5121 | 5123 | 5125)) {
                    return Err(format!("{at}.indices: accessors[{k}] must be unsigned integer scalars"));
                }
            }
        }
    }
    for (n, node) in list("nodes").iter().enumerate() {
        let at = format!("nodes[{n}]");
        for (key, len) in [("translation", 3), ("rotation", 4), ("scale", 3), ("matrix", 16)] {
            if let Some(v) = node.get(key) {
                let values = numbers(v, len).ok_or(format!("{at}.{key}: not {len} finite numbers"))?;
                if key == "rotation" {
                    let norm = values.iter().map(|x| x * x).sum::<f64>().sqrt();
                    if (norm - 1.0).abs() > 1e-3 {
                        return Err(format!(
                            "{at}.rotation: the quaternion has length {}, not 1",
                            norm as f32
                        ));
                    }
                }
            }
        }
    }
    // A skin's inverse bind matrices, one for each joint (glTF 2.0, "Skins"): fewer would leave
    // a joint without one, another type would be misread.
    for (k, skin) in list("skins").iter().enumerate() {
        let at = format!("skins[{k}]");
        let joints = skin.get("joints").and_then(Value::as_array).map_or(0, Vec::len);
        if joints == 0 {
            return Err(format!("{at}.joints: a skin has at least one joint"));
        }
        if let Some(a) = uint(skin, "inverseBindMatrices", &at)? {
            let at = format!("{at}.inverseBindMatrices");
            let &(count, _, components, kind, _) =
                counts.get(a as usize).ok_or(format!("{at}: accessors[{a}] does not exist"))?;
            if components != 16 || kind != Some(FLOAT) {
                return Err(format!("{at}: accessors[{a}] must be MAT4 floats"));
            }
            if count < joints as u64 {
                return Err(format!("{at}: accessors[{a}] holds {count} matrices for {joints} joints"));
            }
        }
    }
    for (c, camera) in list("cameras").iter().enumerate() {
        if let Some(p) = camera.get("perspective") {
            let at = format!("cameras[{c}].perspective");
            let yfov = number(p, "yfov", &at)?.ok_or(format!("{at}: no yfov"))?;
            if !(yfov > 0.0 && yfov.is_finite()) {
                return Err(format!("{at}.yfov: {} rad is not a positive angle", yfov as f32));
            }
            if let Some(aspect) = number(p, "aspectRatio", &at)? {
                if !(aspect > 0.0) {
                    return Err(format!("{at}.aspectRatio: {} is not positive", aspect as f32));
                }
            }
            if let Some(znear) = number(p, "znear", &at)? {
                if !(znear > 0.0) {
                    return Err(format!("{at}.znear: {} is not positive", znear as f32));
                }
            }
        }
        if let Some(o) = camera.get("orthographic") {
            // Not rendered, but read: a broken one names the file broken.
            let at = format!("cameras[{c}].orthographic");
            let get = |key: &str| number(o, key, &at)?.ok_or(format!("{at}: no {key}"));
            let (xmag, ymag, zfar, znear) = (get("xmag")?, get("ymag")?, get("zfar")?, get("znear")?);
            if xmag == 0.0 || ymag == 0.0 {
                return Err(format!("{at}: xmag {xmag} and ymag {ymag}: neither may be zero"));
            }
            if !(znear >= 0.0 && zfar > znear) {
                return Err(format!("{at}: znear {znear} and zfar {zfar}: the spec asks 0 ≤ znear < zfar"));
            }
        }
    }
    for (m, material) in list("materials").iter().enumerate() {
        let at = format!("materials[{m}]");
        let base = material.get("pbrMetallicRoughness").and_then(|p| p.get("baseColorFactor"));
        for (key, v, len) in [
            ("pbrMetallicRoughness.baseColorFactor", base, 4),
            ("emissiveFactor", material.get("emissiveFactor"), 3),
        ] {
            if let Some(v) = v {
                let values = numbers(v, len).ok_or(format!("{at}.{key}: not {len} finite numbers"))?;
                if let Some(x) = values.iter().find(|x| !(0.0..=1.0).contains(*x)) {
                    return Err(format!(
                        "{at}.{key}: {} is outside [0, 1] (glTF bounds it; an albedo above 1 makes energy)",
                        *x as f32
                    ));
                }
            }
        }
        if let Some(c) = material.get("extensions").and_then(|e| e.get("KHR_materials_clearcoat")) {
            let at = format!("{at}.extensions.KHR_materials_clearcoat");
            for key in ["clearcoatFactor", "clearcoatRoughnessFactor"] {
                if let Some(x) = number(c, key, &at)? {
                    if !(0.0..=1.0).contains(&x) {
                        return Err(format!("{at}.{key}: {} is outside [0, 1]", x as f32));
                    }
                }
            }
            let keys = ["clearcoatTexture", "clearcoatRoughnessTexture", "clearcoatNormalTexture"];
            texture_infos(c, &keys, &at, list("textures").len())?;
        }
        if let Some(s) = material.get("extensions").and_then(|e| e.get(super::read::SHEEN)) {
            let at = format!("{at}.extensions.{}", super::read::SHEEN);
            if let Some(v) = s.get("sheenColorFactor") {
                let values = numbers(v, 3).ok_or(format!("{at}.sheenColorFactor: not 3 finite numbers"))?;
                if let Some(x) = values.iter().find(|x| !(0.0..=1.0).contains(*x)) {
                    return Err(format!("{at}.sheenColorFactor: {} is outside [0, 1]", *x as f32));
                }
            }
            if let Some(x) = number(s, "sheenRoughnessFactor", &at)? {
                if !(0.0..=1.0).contains(&x) {
                    return Err(format!("{at}.sheenRoughnessFactor: {} is outside [0, 1]", x as f32));
                }
            }
            texture_infos(s, &["sheenColorTexture", "sheenRoughnessTexture"], &at, list("textures").len())?;
        }
        if let Some(s) = material.get("extensions").and_then(|e| e.get("KHR_materials_emissive_strength")) {
            let at = format!("{at}.extensions.KHR_materials_emissive_strength");
            let strength = number(s, "emissiveStrength", &at)?.unwrap_or(1.0);
            if !(strength >= 0.0) {
                return Err(format!("{at}.emissiveStrength: {} is not a finite number ≥ 0", strength as f32));
            }
        }
    }
    Ok(())
}

/// The texture references `keys` of an extension's object `ext` (at `at`): each an index below
/// `textures` and an unsigned texCoord (the core's references the gltf crate checks; an
/// extension's it does not).
fn texture_infos(ext: &Value, keys: &[&str], at: &str, textures: usize) -> Result<(), String> {
    for key in keys {
        if let Some(info) = ext.get(key) {
            let at = format!("{at}.{key}");
            let index = uint(info, "index", &at)?.ok_or(format!("{at}: no index"))?;
            if index >= textures as u64 {
                return Err(format!("{at}.index: {index} names no texture"));
            }
            uint(info, "texCoord", &at)?;
        }
    }
    Ok(())
}

/// The extension that gives vertex attributes integer types.
pub const MESH_QUANTIZATION: &str = "KHR_mesh_quantization";

const BYTE: u64 = 5120;
const UNSIGNED_BYTE: u64 = 5121;
const SHORT: u64 = 5122;
const UNSIGNED_SHORT: u64 = 5123;
const FLOAT: u64 = 5126;
/// `KHR_mesh_quantization`'s integer types of normals and tangents.
const SIGNED_NORMALISED_TYPES: &[(u64, bool)] = &[(BYTE, true), (SHORT, true)];

/// The types a vertex attribute that the reader reads may have (glTF 2.0's "Meshes", and
/// `KHR_mesh_quantization`'s table): its component counts (one, but `COLOR_0`'s RGB or RGBA),
/// whether floats are allowed (all but `JOINTS_n`), and the integer component types (with whether
/// they are normalised) of the core spec and of the extension.
struct AttributeTypes {
    components: &'static [u64],
    floats: bool,
    core: &'static [(u64, bool)],
    quantized: &'static [(u64, bool)],
}

impl AttributeTypes {
    /// The types of attribute `name`, or None for one the reader does not read.
    fn of(name: &str) -> Option<Self> {
        const ANY_NORMALISATION: &[(u64, bool)] = &[
            (BYTE, false),
            (BYTE, true),
            (UNSIGNED_BYTE, false),
            (UNSIGNED_BYTE, true),
            (SHORT, false),
            (SHORT, true),
            (UNSIGNED_SHORT, false),
            (UNSIGNED_SHORT, true),
        ];
        const UNSIGNED_NORMALISED: &[(u64, bool)] = &[(UNSIGNED_BYTE, true), (UNSIGNED_SHORT, true)];
        let set = |prefix: &str| name.strip_prefix(prefix).is_some_and(|n| n.parse::<u32>().is_ok());
        let floats =
            |components, quantized| AttributeTypes { components, floats: true, core: &[], quantized };
        Some(match name {
            "POSITION" => floats(&[3], ANY_NORMALISATION),
            "NORMAL" => floats(&[3], SIGNED_NORMALISED_TYPES),
            "TANGENT" => floats(&[4], SIGNED_NORMALISED_TYPES),
            "TEXCOORD_0" | "TEXCOORD_1" => AttributeTypes {
                components: &[2],
                floats: true,
                core: UNSIGNED_NORMALISED,
                quantized: ANY_NORMALISATION,
            },
            // Joint indices are integers in every file; weights are floats or normalised.
            "COLOR_0" => AttributeTypes {
                components: &[3, 4],
                floats: true,
                core: UNSIGNED_NORMALISED,
                quantized: UNSIGNED_NORMALISED,
            },
            _ if set("JOINTS_") => AttributeTypes {
                components: &[4],
                floats: false,
                core: &[(UNSIGNED_BYTE, false), (UNSIGNED_SHORT, false)],
                quantized: &[],
            },
            _ if set("WEIGHTS_") => AttributeTypes {
                components: &[4],
                floats: true,
                core: UNSIGNED_NORMALISED,
                quantized: UNSIGNED_NORMALISED,
            },
            _ => return None,
        })
    }

    /// Whether `components` of `kind` (`normalized` or not) are one of the types, the
    /// extension's counted where the file uses it (`quantized`).
    fn allows(&self, components: u64, kind: Option<u64>, normalized: bool, quantized: bool) -> bool {
        let Some(kind) = kind else { return false };
        self.components.contains(&components)
            && (kind == FLOAT && self.floats
                || self.core.contains(&(kind, normalized))
                || quantized && self.quantized.contains(&(kind, normalized)))
    }

    /// The types, in words, for the error that refuses another.
    fn describe(&self, quantized: bool) -> String {
        let vecs: Vec<String> = self.components.iter().map(|c| format!("VEC{c}")).collect();
        let vecs = vecs.join(" or ");
        if !self.floats {
            return format!("a {vecs} of unsigned bytes or shorts");
        }
        let vec = format!("a {vecs} of floats");
        match (self.core.is_empty(), quantized) {
            (true, false) => format!("{vec} (integers need {MESH_QUANTIZATION}, used and required)"),
            (false, false) => format!(
                "{vec}, or of normalised unsigned bytes or shorts (other integers need {MESH_QUANTIZATION}, used and required)"
            ),
            (_, true) if self.quantized == SIGNED_NORMALISED_TYPES => {
                format!("{vec}, or of normalised signed bytes or shorts ({MESH_QUANTIZATION})")
            }
            (_, true) => format!("{vec}, or of bytes or shorts ({MESH_QUANTIZATION})"),
        }
    }
}

/// An optional unsigned integer member.
fn uint(v: &Value, key: &str, at: &str) -> Result<Option<u64>, String> {
    match v.get(key) {
        None => Ok(None),
        Some(x) => x.as_u64().map(Some).ok_or(format!("{at}.{key}: {x} is not an unsigned integer")),
    }
}

/// An optional finite number member.
fn number(v: &Value, key: &str, at: &str) -> Result<Option<f64>, String> {
    match v.get(key) {
        None => Ok(None),
        Some(x) => x
            .as_f64()
            .filter(|f| f.is_finite())
            .map(Some)
            .ok_or(format!("{at}.{key}: {x} is not a finite number")),
    }
}

/// `len` finite numbers, or None.
fn numbers(v: &Value, len: usize) -> Option<Vec<f64>> {
    let a = v.as_array()?;
    let values: Vec<f64> = a.iter().filter_map(Value::as_f64).filter(|x| x.is_finite()).collect();
    (a.len() == len && values.len() == len).then_some(values)
}

/// The sparse part of an accessor of `count` elements of `element` bytes: at most `count`
/// substitutions, unsigned integer indices, and both its index and value views long enough.
fn check_sparse(
    sparse: &Value,
    count: u64,
    element: u64,
    views: &[(u64, Option<u64>)],
    at: &str,
) -> Result<(), String> {
    let n = uint(sparse, "count", at)?.ok_or(format!("{at}: no count"))?;
    if n == 0 || n > count {
        return Err(format!("{at}: count {n} is not in 1..={count}"));
    }
    let part = |name: &str, size: Option<u64>| -> Result<(), String> {
        let at = format!("{at}.{name}");
        let v = sparse.get(name).ok_or(format!("{at}: missing"))?;
        let size = match size {
            Some(s) => s,
            None => match uint(v, "componentType", &at)? {
                Some(5121) => 1,
                Some(5123) => 2,
                Some(5125) => 4,
                other => return Err(format!("{at}: componentType {other:?} is no unsigned integer type")),
            },
        };
        let view = uint(v, "bufferView", &at)?.ok_or(format!("{at}: no bufferView"))?;
        let (length, _) =
            *views.get(view as usize).ok_or(format!("{at}: bufferView {view} does not exist"))?;
        let offset = uint(v, "byteOffset", &at)?.unwrap_or(0);
        if offset as u128 + n as u128 * size as u128 > length as u128 {
            return Err(format!("{at}: {n} elements of {size} bytes from byteOffset {offset} run past bufferViews[{view}] ({length} bytes)"));
        }
        Ok(())
    };
    part("indices", None)?;
    part("values", Some(element))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn doc() -> Value {
        json!({
            "buffers": [{"byteLength": 48}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 12}],
            "accessors": [
                {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                {"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"},
                {"bufferView": 1, "componentType": 5123, "count": 3, "type": "VEC2"}
            ],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
            "nodes": [{"mesh": 0, "rotation": [0, 0, 0, 1]}],
            "cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.01}}],
            "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1]}, "emissiveFactor": [1, 1, 1]}]
        })
    }

    /// `KHR_mesh_quantization`'s integer attributes pass where the file uses the extension, and
    /// only the types its table gives; without it they are refused, the extension named.
    #[test]
    fn quantised_attributes_need_the_extension_and_its_types() {
        // accessors[3]: a VEC3 of shorts; [4]: a VEC4 of bytes; [5]: a VEC2 of shorts (all in
        // view 0's 36 bytes).
        let quantised = |extension: bool| {
            let mut d = doc();
            let accessors = d["accessors"].as_array_mut().unwrap();
            accessors.push(json!({"bufferView": 0, "componentType": 5122, "count": 3, "type": "VEC3"}));
            accessors.push(json!({"bufferView": 0, "componentType": 5120, "count": 3, "type": "VEC4"}));
            accessors.push(json!({"bufferView": 0, "componentType": 5122, "count": 3, "type": "VEC2"}));
            if extension {
                d["extensionsUsed"] = json!([MESH_QUANTIZATION]);
                d["extensionsRequired"] = json!([MESH_QUANTIZATION]);
            }
            d
        };
        let set = |d: &mut Value, attribute: &str, accessor: u64, normalized: Option<bool>| {
            d["meshes"][0]["primitives"][0]["attributes"][attribute] = json!(accessor);
            if let Some(n) = normalized {
                d["accessors"][accessor as usize]["normalized"] = json!(n);
            }
        };
        // Allowed with the extension: positions of shorts, normalised or not; normals of
        // normalised shorts; tangents of normalised bytes; coordinates of shorts.
        for (attribute, accessor, normalized) in [
            ("POSITION", 3, false),
            ("POSITION", 3, true),
            ("NORMAL", 3, true),
            ("TANGENT", 4, true),
            ("TEXCOORD_0", 5, false),
            ("TEXCOORD_1", 5, true),
        ] {
            let mut d = quantised(true);
            set(&mut d, attribute, accessor, Some(normalized));
            assert_eq!(validate(&d, &[48]), Ok(()), "{attribute} normalised {normalized}");
            // Without the extension: refused, and the error says what would allow them.
            let mut d = quantised(false);
            set(&mut d, attribute, accessor, Some(normalized));
            let err = validate(&d, &[48]).unwrap_err();
            assert!(
                err.contains(&format!("{attribute} must be")) && err.contains(MESH_QUANTIZATION),
                "{err}"
            );
        }
        // Not in the extension's table: normals and tangents not normalised, and wrong widths.
        for (attribute, accessor, normalized, expected) in [
            ("NORMAL", 3, false, "NORMAL must be a VEC3 of floats, or of normalised signed bytes or shorts"),
            (
                "TANGENT",
                4,
                false,
                "TANGENT must be a VEC4 of floats, or of normalised signed bytes or shorts",
            ),
            ("POSITION", 5, true, "POSITION must be a VEC3 of floats, or of bytes or shorts"),
            ("TEXCOORD_0", 3, true, "TEXCOORD_0 must be a VEC2"),
        ] {
            let mut d = quantised(true);
            set(&mut d, attribute, accessor, Some(normalized));
            let err = validate(&d, &[48]).unwrap_err();
            assert!(err.contains(expected), "{attribute}: {err}");
        }
        // Used, it must be required.
        let mut d = quantised(true);
        d["extensionsRequired"] = json!([]);
        assert!(validate(&d, &[48]).unwrap_err().contains("is used but not required"));
        // 32-bit integers are no attribute's type, with or without the extension.
        let mut d = quantised(true);
        d["accessors"][3]["componentType"] = json!(5125);
        set(&mut d, "POSITION", 3, None);
        assert!(validate(&d, &[48]).unwrap_err().contains("POSITION must be"));
    }

    /// A well-formed document passes; each single wrong value is named by its path.
    #[test]
    fn each_problem_is_named_by_its_path() {
        assert_eq!(validate(&doc(), &[48]), Ok(()));
        let cases: [(&str, Value, &str); 20] = [
            ("/buffers/0/byteLength", json!(4800), "buffers[0]: byteLength is 4800"),
            (
                "/bufferViews/1/byteOffset",
                json!(40),
                "bufferViews[1]: byteOffset 40 + byteLength 12 runs past",
            ),
            ("/accessors/1/count", json!(4), "accessors[1]: 4 elements"),
            ("/accessors/0/byteOffset", json!(2), "accessors[0]: byteOffset 2 is not a multiple"),
            ("/accessors/0/count", json!(4_000_000_000_u64), "accessors[0]: 4000000000 elements"),
            ("/bufferViews/0/byteStride", json!(7), "bufferViews[0]: byteStride 7"),
            ("/nodes/0/rotation", json!([0, 0, 0, 2]), "nodes[0].rotation: the quaternion has length 2"),
            ("/cameras/0/perspective/yfov", json!(-1), "cameras[0].perspective.yfov: -1"),
            (
                "/cameras/0/perspective/yfov",
                json!(0),
                "cameras[0].perspective.yfov: 0 rad is not a positive angle",
            ),
            ("/cameras/0/perspective/aspectRatio", json!(0), "aspectRatio: 0 is not positive"),
            (
                "/materials/0/pbrMetallicRoughness/baseColorFactor",
                json!([2, 1, 1, 1]),
                "baseColorFactor: 2 is outside [0, 1]",
            ),
            ("/materials/0/emissiveFactor", json!([1, -1, 1]), "emissiveFactor: -1 is outside [0, 1]"),
            (
                "/meshes/0/primitives/0/attributes/NORMAL",
                json!(1),
                "primitives[0]: NORMAL must be a VEC3 of floats",
            ),
            (
                "/meshes/0/primitives/0/attributes/TANGENT",
                json!(0),
                "primitives[0]: TANGENT must be a VEC4 of floats",
            ),
            (
                "/meshes/0/primitives/0/attributes/TEXCOORD_1",
                json!(0),
                "primitives[0]: TEXCOORD_1 must be a VEC2",
            ),
            (
                "/meshes/0/primitives/0/attributes/NORMAL",
                json!(7),
                "primitives[0]: NORMAL accessor 7 does not exist",
            ),
            // Unsigned shorts as texture coordinates, not normalised: only KHR_mesh_quantization's.
            (
                "/meshes/0/primitives/0/attributes/TEXCOORD_0",
                json!(2),
                "primitives[0]: TEXCOORD_0 must be a VEC2",
            ),
            // Joint indices are integers; weights are not signed.
            (
                "/meshes/0/primitives/0/attributes/JOINTS_0",
                json!(0),
                "primitives[0]: JOINTS_0 must be a VEC4 of unsigned bytes or shorts",
            ),
            ("/meshes/0/primitives/0/attributes/WEIGHTS_1", json!(0), "WEIGHTS_1 must be a VEC4 of floats"),
            // Colours are RGB or RGBA, floats or normalised unsigned integers.
            (
                "/meshes/0/primitives/0/attributes/COLOR_0",
                json!(2),
                "primitives[0]: COLOR_0 must be a VEC3 or VEC4 of floats, or of normalised unsigned bytes or shorts",
            ),
        ];
        // Attributes of the types the spec gives them pass: normalised unsigned shorts too.
        let mut d = doc();
        d["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = json!(0);
        d["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(2);
        d["accessors"][2]["normalized"] = json!(true);
        assert_eq!(validate(&d, &[48]), Ok(()));
        for (pointer, value, expected) in cases {
            let mut d = doc();
            let (parent, key) = pointer.rsplit_once('/').unwrap();
            d.pointer_mut(parent).unwrap()[key] = value;
            let err = validate(&d, &[48]).expect_err(pointer);
            assert!(err.contains(expected), "{pointer}: {err}");
            assert!(!err.contains('\n'));
        }
        // Two indices are no whole triangle, but valid glTF: the reader drops them with a warning.
        let mut d = doc();
        d["accessors"][1]["count"] = json!(2);
        d["bufferViews"][1]["byteLength"] = json!(12);
        assert_eq!(validate(&d, &[48]), Ok(()));
        // A sparse part must lie within its views.
        let mut d = doc();
        d["accessors"][0]["sparse"] = json!({
            "count": 1,
            "indices": {"bufferView": 1, "componentType": 5125},
            "values": {"bufferView": 1, "byteOffset": 8}
        });
        assert!(validate(&d, &[48])
            .unwrap_err()
            .contains("accessors[0].sparse.values: 1 elements of 12 bytes"));
        d["accessors"][0]["sparse"]["values"]["byteOffset"] = json!(0);
        assert_eq!(validate(&d, &[48]), Ok(()));
        d["accessors"][0]["sparse"]["count"] = json!(99);
        assert!(validate(&d, &[48]).unwrap_err().contains("accessors[0].sparse: count 99"));
        assert!(validate(&doc(), &[40]).unwrap_err().contains("the buffer holds 40 bytes"));
        let mut d = doc();
        d["materials"][0]["extensions"] =
            json!({"KHR_materials_emissive_strength": {"emissiveStrength": -2}});
        assert!(validate(&d, &[48]).unwrap_err().contains("emissiveStrength: -2 is not a finite number ≥ 0"));
        // A skin's inverse bind matrices: MAT4 floats, one a joint or more.
        let mut d = doc();
        d["accessors"]
            .as_array_mut()
            .unwrap()
            .push(json!({"componentType": 5126, "count": 1, "type": "MAT4"}));
        d["skins"] = json!([{"joints": [0], "inverseBindMatrices": 3}]);
        assert_eq!(validate(&d, &[48]), Ok(()));
        d["skins"][0]["joints"] = json!([0, 0]);
        assert!(validate(&d, &[48])
            .unwrap_err()
            .contains("skins[0].inverseBindMatrices: accessors[3] holds 1 matrices for 2 joints"));
        d["skins"][0]["joints"] = json!([0]);
        d["accessors"][3]["type"] = json!("MAT3");
        assert!(validate(&d, &[48])
            .unwrap_err()
            .contains("skins[0].inverseBindMatrices: accessors[3] must be MAT4 floats"));
        d["skins"][0]["joints"] = json!([]);
        assert!(validate(&d, &[48]).unwrap_err().contains("skins[0].joints: a skin has at least one joint"));
    }
}
