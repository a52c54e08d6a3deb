//! `EXT_meshopt_compression`: buffer views whose bytes are meshoptimizer's codecs' (which
//! gltfpack `-c` and `gltf-transform optimize`, by default, write). Each compressed view the
//! meshes read is decoded with the reference decoder (meshoptimizer's C++, through the `meshopt`
//! crate) into a buffer of its own, and the view is pointed at it: the rest of the loader reads
//! it as any other view, and the fallback buffer (often a placeholder with no data) is not read.
//!
//! The extension's rules are checked first, and a view that breaks one, or whose data does not
//! decode, is refused by its glTF path: `byteLength` = `byteStride` × `count`; ATTRIBUTES with a
//! stride that is a multiple of 4 up to 256; TRIANGLES (a count that is a multiple of 3) and
//! INDICES with a stride of 2 or 4 and no filter; the OCTAHEDRAL filter with a stride of 4 or 8,
//! QUATERNION with 8, EXPONENTIAL with a multiple of 4.

use gltf::json::Value;

/// The extension's name.
pub const EXTENSION: &str = "EXT_meshopt_compression";

/// A view's compressed data, as its extension object describes it.
#[derive(Debug, PartialEq)]
struct Compressed {
    buffer: usize,
    offset: usize,
    length: usize,
    stride: usize,
    count: usize,
    mode: Mode,
    filter: Filter,
}

/// The codec of a compressed view (the extension's `mode`).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    Attributes,
    Triangles,
    Indices,
}

/// What is done to decoded attributes (the extension's `filter`).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Filter {
    None,
    Octahedral,
    Quaternion,
    Exponential,
}

/// The extension object of `view`, if it has one.
fn extension(view: &gltf::json::buffer::View) -> Option<&Value> {
    view.extensions.as_ref().and_then(|e| e.others.get(EXTENSION))
}

/// The buffer `view`'s bytes are read from: the extension's where it is compressed.
pub fn source_buffer(view: &gltf::json::buffer::View) -> usize {
    extension(view)
        .and_then(|e| e.get("buffer"))
        .and_then(Value::as_u64)
        .map_or(view.buffer.value(), |b| b as usize)
}

impl Compressed {
    /// Reads and checks the extension object `e` of a view of `view_length` bytes and
    /// `view_stride` (the errors name what is wrong, relative to the extension).
    fn read(e: &Value, view_length: usize, view_stride: Option<usize>) -> Result<Self, String> {
        let uint = |key: &str, default: Option<usize>| match e.get(key) {
            Some(v) => v.as_u64().map(|v| v as usize).ok_or(format!("{key}: {v} is no unsigned integer")),
            None => default.ok_or(format!("{key}: missing")),
        };
        let text = |key: &str, default: Option<&'static str>| match e.get(key) {
            Some(Value::String(s)) => Ok(s.clone()),
            Some(v) => Err(format!("{key}: {v} is no string")),
            None => default.map(String::from).ok_or(format!("{key}: missing")),
        };
        let mode = match text("mode", None)?.as_str() {
            "ATTRIBUTES" => Mode::Attributes,
            "TRIANGLES" => Mode::Triangles,
            "INDICES" => Mode::Indices,
            other => return Err(format!("mode: '{other}' is not ATTRIBUTES, TRIANGLES or INDICES")),
        };
        let filter = match text("filter", Some("NONE"))?.as_str() {
            "NONE" => Filter::None,
            "OCTAHEDRAL" => Filter::Octahedral,
            "QUATERNION" => Filter::Quaternion,
            "EXPONENTIAL" => Filter::Exponential,
            other => {
                return Err(format!("filter: '{other}' is not NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL"))
            }
        };
        let c = Compressed {
            buffer: uint("buffer", None)?,
            offset: uint("byteOffset", Some(0))?,
            length: uint("byteLength", None)?,
            stride: uint("byteStride", None)?,
            count: uint("count", None)?,
            mode,
            filter,
        };
        let s = c.stride;
        if view_stride.is_some_and(|v| v != s) {
            return Err(format!("byteStride: {s}, but the bufferView's is {}", view_stride.unwrap_or(0)));
        }
        if c.count.checked_mul(s) != Some(view_length) {
            return Err(format!(
                "count {} × byteStride {s} is not the bufferView's byteLength {view_length}",
                c.count
            ));
        }
        let stride_ok = match (mode, filter) {
            (Mode::Attributes, Filter::None) => s.is_multiple_of(4) && (4..=256).contains(&s),
            (Mode::Attributes, Filter::Octahedral) => s == 4 || s == 8,
            (Mode::Attributes, Filter::Quaternion) => s == 8,
            (Mode::Attributes, Filter::Exponential) => s.is_multiple_of(4) && (4..=256).contains(&s),
            (Mode::Triangles | Mode::Indices, Filter::None) => s == 2 || s == 4,
            (Mode::Triangles | Mode::Indices, _) => return Err("filter: only ATTRIBUTES are filtered".into()),
        };
        if !stride_ok {
            return Err(format!(
                "byteStride {s} is not one that mode {mode:?} with filter {filter:?} allows"
            ));
        }
        if mode == Mode::Triangles && !c.count.is_multiple_of(3) {
            return Err(format!("count {} of TRIANGLES is no multiple of 3", c.count));
        }
        Ok(c)
    }

    /// The view's bytes, decoded from `data` (the compressed bytes).
    fn decode(&self, data: &[u8]) -> Result<Vec<u8>, String> {
        let mut out = vec![0u8; self.count * self.stride];
        if self.count == 0 {
            return Ok(out);
        }
        let (dst, (n, size)) = (out.as_mut_ptr().cast(), (self.count, self.stride));
        // SAFETY: `out` holds n × size bytes, which each decoder writes at most; `data` is a
        // slice the decoders read within its length (they are safe for untrusted input).
        let status = unsafe {
            match self.mode {
                Mode::Attributes => {
                    meshopt::ffi::meshopt_decodeVertexBuffer(dst, n, size, data.as_ptr(), data.len())
                }
                Mode::Triangles => {
                    meshopt::ffi::meshopt_decodeIndexBuffer(dst, n, size, data.as_ptr(), data.len())
                }
                Mode::Indices => {
                    meshopt::ffi::meshopt_decodeIndexSequence(dst, n, size, data.as_ptr(), data.len())
                }
            }
        };
        if status != 0 {
            return Err(format!("its {:?} data does not decode (meshoptimizer's error {status})", self.mode));
        }
        // SAFETY: the filters rewrite n elements of `size` bytes in place, the strides they take
        // checked in `read`.
        unsafe {
            match self.filter {
                Filter::None => {}
                Filter::Octahedral => meshopt::ffi::meshopt_decodeFilterOct(dst, n, size),
                Filter::Quaternion => meshopt::ffi::meshopt_decodeFilterQuat(dst, n, size),
                Filter::Exponential => meshopt::ffi::meshopt_decodeFilterExp(dst, n, size),
            }
        }
        Ok(out)
    }
}

/// Decodes every compressed view of `root` among `views` (those the meshes read) into a new
/// buffer appended to `buffers`, pointing the view at it (offset 0, its stride kept). The error
/// names the view's glTF path; compressed data in one of the `placeholders` (buffers whose data
/// the file does not hold) is refused as such.
pub fn decompress(
    root: &mut gltf::json::Root,
    buffers: &mut Vec<gltf::buffer::Data>,
    placeholders: &[usize],
    views: &[usize],
) -> Result<(), String> {
    for &v in views {
        let view = &root.buffer_views[v];
        let Some(e) = extension(view) else { continue };
        let at = format!("bufferViews[{v}].extensions.{EXTENSION}");
        let c = Compressed::read(e, view.byte_length.0 as usize, view.byte_stride.map(|s| s.0))
            .map_err(|what| format!("{at}.{what}"))?;
        let source = buffers.get(c.buffer).ok_or(format!("{at}.buffer: {} does not exist", c.buffer))?;
        if placeholders.contains(&c.buffer) {
            return Err(format!(
                "{at}: buffers[{}], whose data is not in the file (no uri, no BIN chunk)",
                c.buffer
            ));
        }
        let data =
            c.offset.checked_add(c.length).and_then(|end| source.0.get(c.offset..end)).ok_or(format!(
                "{at}: byteOffset {} + byteLength {} runs past buffers[{}]",
                c.offset, c.length, c.buffer
            ))?;
        let decoded = c.decode(data).map_err(|what| format!("{at}: {what}"))?;
        let index = super::parse::append_buffer(root, buffers, decoded);
        let view = &mut root.buffer_views[v];
        view.buffer = gltf::json::Index::new(index as u32);
        view.byte_offset = None;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn the_extension_s_rules_are_checked() {
        let ok = json!({"buffer": 0, "byteLength": 10, "byteStride": 8, "count": 3, "mode": "ATTRIBUTES"});
        assert_eq!(
            Compressed::read(&ok, 24, Some(8)),
            Ok(Compressed {
                buffer: 0,
                offset: 0,
                length: 10,
                stride: 8,
                count: 3,
                mode: Mode::Attributes,
                filter: Filter::None
            })
        );
        let with = |edit: Value| {
            let mut e = ok.clone();
            for (k, v) in edit.as_object().unwrap() {
                e[k] = v.clone();
            }
            e
        };
        for (edit, length, stride, expected) in [
            (json!({}), 32, None, "count 3 × byteStride 8 is not the bufferView's byteLength 32"),
            (json!({}), 24, Some(12), "byteStride: 8, but the bufferView's is 12"),
            (json!({"byteStride": 6, "count": 4}), 24, None, "byteStride 6 is not one"),
            (json!({"mode": "TRIANGLES", "byteStride": 4, "count": 5}), 20, None, "count 5 of TRIANGLES"),
            (json!({"mode": "TRIANGLES", "filter": "OCTAHEDRAL"}), 24, None, "only ATTRIBUTES are filtered"),
            (
                json!({"filter": "QUATERNION", "byteStride": 4, "count": 6}),
                24,
                None,
                "byteStride 4 is not one",
            ),
            (json!({"mode": "POINTS"}), 24, None, "mode: 'POINTS' is not"),
            (json!({"filter": 3}), 24, None, "filter: 3 is no string"),
            (json!({"count": -1}), 24, None, "count: -1 is no unsigned integer"),
        ] {
            let e = with(edit.clone());
            let err = Compressed::read(&e, length, stride).unwrap_err();
            assert!(err.contains(expected), "{edit}: {err}");
        }
        let mut missing = ok.clone();
        missing.as_object_mut().unwrap().remove("byteLength");
        assert_eq!(Compressed::read(&missing, 24, None).unwrap_err(), "byteLength: missing");
    }

    /// The codecs round-trip through meshoptimizer's encoders: attributes with and without the
    /// octahedral filter, triangles and index sequences; a truncated stream is refused.
    #[test]
    fn decoding_inverts_meshoptimizer_s_encoders() {
        let vertices: Vec<[u16; 4]> = (0..100u16).map(|i| [i, 3 * i, 65535 - i, 7]).collect();
        let encoded = meshopt::encoding::encode_vertex_buffer(&vertices).unwrap();
        let c = Compressed {
            buffer: 0,
            offset: 0,
            length: encoded.len(),
            stride: 8,
            count: 100,
            mode: Mode::Attributes,
            filter: Filter::None,
        };
        let bytes: Vec<u8> = vertices.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
        assert_eq!(c.decode(&encoded).unwrap(), bytes);
        assert!(c.decode(&encoded[..encoded.len() / 2]).is_err());
        // Unit normals, octahedrally encoded in 8-bit components: decoded to within their
        // precision, as normalised signed bytes.
        let normals: Vec<[f32; 3]> = (0..64)
            .map(|i| {
                let (t, p) = (i as f32 * 0.37, i as f32 * 0.11);
                [t.sin() * p.cos(), t.cos() * p.cos(), p.sin()]
            })
            .collect();
        let unit: Vec<[f32; 4]> = normals.iter().map(|n| [n[0], n[1], n[2], 0.0]).collect();
        let oct: Vec<[i8; 4]> = meshopt::encoding::encode_filter_oct(&unit, 8);
        let encoded = meshopt::encoding::encode_vertex_buffer(&oct).unwrap();
        let c = Compressed { length: encoded.len(), stride: 4, count: 64, filter: Filter::Octahedral, ..c };
        let decoded = c.decode(&encoded).unwrap();
        for (n, d) in normals.iter().zip(decoded.chunks(4)) {
            let d = [d[0], d[1], d[2]].map(|b| b as i8 as f32 / 127.0);
            let error = n.iter().zip(d).map(|(a, b)| (a - b).abs()).fold(0.0, f32::max);
            assert!(error < 0.03, "{n:?} decoded as {d:?}");
        }
        // Triangles (which the encoder may rotate, keeping their winding) and a plain index
        // sequence, 16- and 32-bit.
        let rotated = |t: &[u32]| {
            let k = (0..3).min_by_key(|&k| t[k]).unwrap();
            [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
        };
        let triangles: Vec<u32> = (0..30).flat_map(|i| [i, i + 1, i + 2]).collect();
        for (stride, mode) in
            [(2, Mode::Triangles), (4, Mode::Triangles), (2, Mode::Indices), (4, Mode::Indices)]
        {
            let encoded = match mode {
                Mode::Triangles => meshopt::encoding::encode_index_buffer(&triangles, 32).unwrap(),
                _ => meshopt::encoding::encode_index_sequence(&triangles, 32).unwrap(),
            };
            let c = Compressed {
                length: encoded.len(),
                stride,
                count: triangles.len(),
                mode,
                filter: Filter::None,
                ..c
            };
            let decoded = c.decode(&encoded).unwrap();
            let indices: Vec<u32> = match stride {
                2 => decoded.chunks(2).map(|b| u16::from_le_bytes([b[0], b[1]]) as u32).collect(),
                _ => decoded.chunks(4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect(),
            };
            if mode == Mode::Triangles {
                let same = indices.chunks(3).map(rotated).eq(triangles.chunks(3).map(rotated));
                assert!(same, "{mode:?}, stride {stride}: {indices:?}");
            } else {
                assert_eq!(indices, triangles, "{mode:?}, stride {stride}");
            }
        }
    }
}
