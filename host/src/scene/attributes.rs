//! Vertex attributes as floats, whichever component type the file stores them in: floats, or
//! the integers `KHR_mesh_quantization` allows (which the optimisers gltfpack and glTF-Transform
//! write), normalised or not. The spec's conversions (glTF 2.0, "Animations", and the
//! extension's text): a normalised integer c of type T is `max(c / MAX(T), −1)`, an integer
//! that is not normalised is its value, c; the scale and offset that undo the quantisation are
//! the node's transform, which the reader applies to every mesh. Which type each attribute may
//! have is `validate`'s to check before anything reads it.

use gltf::accessor::{DataType, Item, Iter};

/// The float of a normalised signed byte: c / 127, at least −1.
#[inline]
pub fn from_normalized_i8(c: i8) -> f32 {
    (c as f32 / 127.0).max(-1.0)
}

/// The float of a normalised unsigned byte: c / 255.
#[inline]
pub fn from_normalized_u8(c: u8) -> f32 {
    c as f32 / 255.0
}

/// The float of a normalised signed short: c / 32767, at least −1.
#[inline]
pub fn from_normalized_i16(c: i16) -> f32 {
    (c as f32 / 32767.0).max(-1.0)
}

/// The float of a normalised unsigned short: c / 65535.
#[inline]
pub fn from_normalized_u16(c: u16) -> f32 {
    c as f32 / 65535.0
}

/// The `N`-component values of `accessor` (sparse values applied) as floats, or None where it
/// cannot be read: no view and no sparse values (the caller's zeros), data outside its buffer, or
/// a component type no vertex attribute has (32-bit integers).
pub fn read<'a, 's, F, const N: usize>(accessor: &gltf::Accessor<'a>, buffers: F) -> Option<Vec<[f32; N]>>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
    [f32; N]: Item,
    [i8; N]: Item,
    [u8; N]: Item,
    [i16; N]: Item,
    [u16; N]: Item,
{
    fn convert<'a, 's, F, T, const N: usize>(
        accessor: &gltf::Accessor<'a>,
        buffers: F,
        to_float: impl Fn(T) -> f32,
    ) -> Option<Vec<[f32; N]>>
    where
        F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
        [T; N]: Item,
        T: Copy,
    {
        Some(Iter::<[T; N]>::new(accessor.clone(), buffers)?.map(|v| v.map(&to_float)).collect())
    }
    let normalized = accessor.normalized();
    match accessor.data_type() {
        DataType::F32 => Some(Iter::<[f32; N]>::new(accessor.clone(), buffers)?.collect()),
        DataType::I8 if normalized => convert(accessor, buffers, from_normalized_i8),
        DataType::U8 if normalized => convert(accessor, buffers, from_normalized_u8),
        DataType::I16 if normalized => convert(accessor, buffers, from_normalized_i16),
        DataType::U16 if normalized => convert(accessor, buffers, from_normalized_u16),
        DataType::I8 => convert(accessor, buffers, |c: i8| c as f32),
        DataType::U8 => convert(accessor, buffers, |c: u8| c as f32),
        DataType::I16 => convert(accessor, buffers, |c: i16| c as f32),
        DataType::U16 => convert(accessor, buffers, |c: u16| c as f32),
        DataType::U32 => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn normalised_integers_map_onto_the_unit_range_as_the_spec_says() {
        // Both ends exact; the signed types' two lowest values are both −1.
        assert_eq!(from_normalized_i8(127), 1.0);
        assert_eq!(from_normalized_i8(-127), -1.0);
        assert_eq!(from_normalized_i8(-128), -1.0);
        assert_eq!(from_normalized_i8(0), 0.0);
        assert_eq!(from_normalized_u8(255), 1.0);
        assert_eq!(from_normalized_u8(0), 0.0);
        assert_eq!(from_normalized_i16(32767), 1.0);
        assert_eq!(from_normalized_i16(-32768), -1.0);
        assert_eq!(from_normalized_u16(65535), 1.0);
        // Between them the ratio, in f64 to one rounding.
        for c in [-100i8, -1, 1, 64, 100] {
            assert_eq!(from_normalized_i8(c), (c as f64 / 127.0) as f32);
        }
        for c in [1u16, 300, 32768, 65534] {
            assert_eq!(from_normalized_u16(c), (c as f64 / 65535.0) as f32);
        }
    }

    /// A one-buffer document with one accessor of `component_type` over `bytes`.
    fn accessor_document(
        component_type: u32,
        normalized: bool,
        kind: &str,
        count: usize,
        stride: Option<usize>,
        bytes: &[u8],
    ) -> gltf::Document {
        let mut view = json!({"buffer": 0, "byteLength": bytes.len()});
        if let Some(s) = stride {
            view["byteStride"] = json!(s);
        }
        let root = json!({
            "asset": {"version": "2.0"},
            "buffers": [{"byteLength": bytes.len()}],
            "bufferViews": [view],
            "accessors": [{"bufferView": 0, "componentType": component_type, "normalized": normalized,
                           "count": count, "type": kind}],
        });
        gltf::Document::from_json_without_validation(serde_json::from_value(root).unwrap())
    }

    #[test]
    fn every_component_type_reads_as_its_floats() {
        // Two VEC3s of signed bytes, each padded to 4 bytes (the spec's vertex alignment).
        let bytes = [127u8, 0x81, 0, 0, 5, 0xfb, 0x80, 0];
        let doc = accessor_document(5120, true, "VEC3", 2, Some(4), &bytes);
        let get = |_: gltf::Buffer| Some(&bytes[..]);
        let a = doc.accessors().next().unwrap();
        assert_eq!(read::<_, 3>(&a, get), Some(vec![[1.0, -1.0, 0.0], [5.0 / 127.0, -5.0 / 127.0, -1.0]]));
        // The same bytes, not normalised: their values.
        let doc = accessor_document(5120, false, "VEC3", 2, Some(4), &bytes);
        let a = doc.accessors().next().unwrap();
        assert_eq!(read::<_, 3>(&a, get), Some(vec![[127.0, -127.0, 0.0], [5.0, -5.0, -128.0]]));
        // Unsigned shorts as VEC2, packed, normalised and not.
        let shorts = [0xffu8, 0xff, 0, 0x80, 1, 0, 2, 0];
        let get = |_: gltf::Buffer| Some(&shorts[..]);
        let doc = accessor_document(5123, true, "VEC2", 2, None, &shorts);
        let a = doc.accessors().next().unwrap();
        assert_eq!(
            read::<_, 2>(&a, get),
            Some(vec![[1.0, 32768.0 / 65535.0], [1.0 / 65535.0, 2.0 / 65535.0]])
        );
        let doc = accessor_document(5123, false, "VEC2", 2, None, &shorts);
        let a = doc.accessors().next().unwrap();
        assert_eq!(read::<_, 2>(&a, get), Some(vec![[65535.0, 32768.0], [1.0, 2.0]]));
        // Signed shorts, and floats.
        let doc = accessor_document(5122, true, "VEC2", 2, None, &shorts);
        let a = doc.accessors().next().unwrap();
        assert_eq!(read::<_, 2>(&a, get), Some(vec![[-1.0 / 32767.0, -1.0], [1.0 / 32767.0, 2.0 / 32767.0]]));
        let floats: Vec<u8> = [1.5f32, -2.0].iter().flat_map(|f| f.to_le_bytes()).collect();
        let get = |_: gltf::Buffer| Some(&floats[..]);
        let doc = accessor_document(5126, false, "VEC2", 1, None, &floats);
        let a = doc.accessors().next().unwrap();
        assert_eq!(read::<_, 2>(&a, get), Some(vec![[1.5, -2.0]]));
        // 32-bit integers are no vertex attribute's type.
        let doc = accessor_document(5125, false, "VEC2", 1, None, &floats);
        let a = doc.accessors().next().unwrap();
        assert_eq!(read::<_, 2>(&a, get), None);
    }
}
