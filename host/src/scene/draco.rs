//! `KHR_draco_mesh_compression`: mesh primitives whose attributes and indices are one Draco
//! stream (Blender's glTF exporter with "Compression" on, `gltf-transform draco`, and many
//! files on the web). Each such primitive's stream is decoded (the `draco-core` crate, a
//! decoder that follows Google's C++ Draco bit for bit) and its accessors are pointed at views
//! of a new buffer holding the decoded values, in each accessor's own component type: the rest
//! of the loader reads them as any accessor, and a fallback the file may hold is not read.
//!
//! The extension's rules (the spec's "Conformance") are checked first, and a primitive that
//! breaks one, or whose stream does not decode, is refused by its glTF path: the extension's
//! `attributes` name attributes of the primitive, each a Draco attribute of as many
//! components as its accessor; each accessor's `count` is the decoded points (the indices':
//! three a decoded face); an accessor read by two primitives decodes the same from both.
//! Attributes the extension does not name are read from their own views, as the spec says.

use std::collections::HashMap;

use draco_core::{DecoderBuffer, FaceIndex, Mesh, MeshDecoder, PointAttribute};
use gltf::json::accessor::{ComponentType, GenericComponentType};
use gltf::json::validation::Checked;
use gltf::json::Value;

/// The extension's name.
pub const EXTENSION: &str = "KHR_draco_mesh_compression";

/// A primitive's extension object, read.
#[derive(Debug, PartialEq)]
struct Compressed {
    /// The view of the Draco stream.
    view: usize,
    /// Each compressed attribute's semantic and its Draco attribute's unique id.
    attributes: Vec<(String, u32)>,
}

impl Compressed {
    /// Reads extension object `e` (the errors name what is wrong, relative to it).
    fn read(e: &Value) -> Result<Self, String> {
        let view = match e.get("bufferView") {
            Some(v) => v.as_u64().ok_or(format!("bufferView: {v} is no unsigned integer"))? as usize,
            None => return Err("bufferView: missing".into()),
        };
        let map = e.get("attributes").and_then(Value::as_object).ok_or("attributes: missing or no object")?;
        let mut attributes = Vec::new();
        for (name, id) in map {
            let id = id.as_u64().and_then(|i| u32::try_from(i).ok());
            attributes.push((name.clone(), id.ok_or(format!("attributes.{name}: no Draco attribute id"))?));
        }
        Ok(Compressed { view, attributes })
    }
}

/// The extension object of a primitive, if it has one.
fn extension(primitive: &gltf::json::mesh::Primitive) -> Option<&Value> {
    primitive.extensions.as_ref().and_then(|e| e.others.get(EXTENSION))
}

/// The buffers the Draco streams of `root`'s primitives lie in (a view the extension names that
/// does not exist is left to [`decompress`] to refuse).
pub fn stream_buffers(root: &gltf::json::Root) -> Vec<usize> {
    let views = root.meshes.iter().flat_map(|m| &m.primitives).filter_map(extension);
    views
        .filter_map(|e| e.get("bufferView").and_then(Value::as_u64))
        .filter_map(|v| root.buffer_views.get(v as usize))
        .map(|view| view.buffer.value())
        .collect()
}

/// Decodes the Draco stream of every primitive of `root` that has one and points the accessors
/// it fills at a new buffer appended to `buffers` (see the module doc). The error names the
/// primitive's glTF path; a stream in one of the `placeholders` (buffers whose data the file
/// does not hold) is refused as such.
pub fn decompress(
    root: &mut gltf::json::Root,
    buffers: &mut Vec<gltf::buffer::Data>,
    placeholders: &[usize],
) -> Result<(), String> {
    // Each accessor filled, with the buffer it was filled from.
    let mut filled: HashMap<usize, usize> = HashMap::new();
    for m in 0..root.meshes.len() {
        for p in 0..root.meshes[m].primitives.len() {
            let primitive = &root.meshes[m].primitives[p];
            let Some(e) = extension(primitive) else { continue };
            let primitive_at = format!("meshes[{m}].primitives[{p}]");
            let at = format!("{primitive_at}.extensions.{EXTENSION}");
            let c = Compressed::read(e).map_err(|what| format!("{at}.{what}"))?;
            let stream =
                stream(root, buffers, placeholders, c.view).map_err(|what| format!("{at}.{what}"))?;
            let mesh = decode(stream).map_err(|what| format!("{at}: {what}"))?;
            let accessors = accessor_values(root, primitive, &c, &mesh)
                .map_err(|what| format!("{primitive_at}.{what}"))?;
            for (k, bytes) in accessors {
                match filled.get(&k) {
                    Some(&earlier) if buffers[earlier].0 != bytes => {
                        return Err(format!(
                            "{at}: accessors[{k}] is read by another compressed primitive, whose data \
                             decodes to other values"
                        ))
                    }
                    Some(_) => {}
                    None => {
                        filled.insert(k, point_at(root, buffers, k, bytes));
                    }
                }
            }
        }
    }
    Ok(())
}

/// The bytes of view `v`, which holds a Draco stream.
fn stream<'b>(
    root: &gltf::json::Root,
    buffers: &'b [gltf::buffer::Data],
    placeholders: &[usize],
    v: usize,
) -> Result<&'b [u8], String> {
    let view = root.buffer_views.get(v).ok_or(format!("bufferView: {v} does not exist"))?;
    let b = view.buffer.value();
    if placeholders.contains(&b) {
        return Err(format!(
            "bufferView: {v} lies in buffers[{b}], whose data is not in the file (no uri, no BIN chunk)"
        ));
    }
    let (offset, length) = (view.byte_offset.map_or(0, |o| o.0 as usize), view.byte_length.0 as usize);
    buffers
        .get(b)
        .and_then(|data| data.0.get(offset..offset.checked_add(length)?))
        .ok_or(format!("bufferView: {v} (byteOffset {offset}, byteLength {length}) runs past buffers[{b}]"))
}

/// The Draco mesh of `stream`.
fn decode(stream: &[u8]) -> Result<Mesh, String> {
    let mut mesh = Mesh::new();
    MeshDecoder::new()
        .decode(&mut DecoderBuffer::new(stream), &mut mesh)
        .map_err(|e| format!("its Draco data does not decode ({e})"))?;
    Ok(mesh)
}

/// The bytes of each accessor the compressed primitive fills: its attributes the extension
/// names, and its indices (the errors name what is wrong, relative to the primitive).
fn accessor_values(
    root: &gltf::json::Root,
    primitive: &gltf::json::mesh::Primitive,
    c: &Compressed,
    mesh: &Mesh,
) -> Result<Vec<(usize, Vec<u8>)>, String> {
    let mut out = Vec::new();
    let points = mesh.num_points();
    for (name, id) in &c.attributes {
        let here = format!("extensions.{EXTENSION}.attributes.{name}");
        let semantic = primitive.attributes.iter().find(|(s, _)| s.to_string() == *name);
        let Some((_, k)) = semantic else {
            return Err(format!("{here}: the primitive has no such attribute"));
        };
        let k = k.value();
        let accessor = root.accessors.get(k).ok_or(format!("{here}: accessors[{k}] does not exist"))?;
        let attribute = (0..mesh.num_attributes())
            .map(|i| mesh.attribute(i))
            .find(|a| a.unique_id() == *id)
            .ok_or(format!("{here}: the Draco data has no attribute {id}"))?;
        let (Checked::Valid(ty), Checked::Valid(GenericComponentType(component))) =
            (accessor.type_, accessor.component_type)
        else {
            return Err(format!("{here}: accessors[{k}] has no valid type"));
        };
        let components = ty.multiplicity();
        if attribute.num_components() as usize != components {
            return Err(format!(
                "{here}: Draco attribute {id} has {} components, accessors[{k}] {components}",
                attribute.num_components()
            ));
        }
        if accessor.count.0 as usize != points {
            return Err(format!(
                "{here}: accessors[{k}].count {}, but the Draco data decodes {points} points",
                accessor.count.0
            ));
        }
        let bytes = attribute_bytes(attribute, points, components, component)
            .map_err(|what| format!("{here}: accessors[{k}]: {what}"))?;
        out.push((k, bytes));
    }
    let indices: Vec<u32> =
        (0..mesh.num_faces()).flat_map(|f| mesh.face(FaceIndex(f as u32))).map(|p| p.0).collect();
    let Some(k) = primitive.indices.map(|i| i.value()) else {
        // Without indices the points are the triangles' corners in order.
        if indices.iter().enumerate().any(|(i, &p)| p as usize != i) || indices.len() != points {
            return Err("indices: none, but the Draco faces are not the points in order".into());
        }
        return Ok(out);
    };
    let accessor = root.accessors.get(k).ok_or(format!("indices: accessors[{k}] does not exist"))?;
    let Checked::Valid(GenericComponentType(component)) = accessor.component_type else {
        return Err(format!("indices: accessors[{k}] has no valid component type"));
    };
    if accessor.count.0 as usize != indices.len() {
        return Err(format!(
            "indices: accessors[{k}].count {}, but the Draco data decodes {} faces ({} indices)",
            accessor.count.0,
            mesh.num_faces(),
            indices.len()
        ));
    }
    let bytes =
        index_bytes(&indices, component).map_err(|what| format!("indices: accessors[{k}]: {what}"))?;
    out.push((k, bytes));
    Ok(out)
}

/// A decoded attribute's values as `component` numbers, tightly packed: floats as Draco gives
/// them (dequantised, normals from their octahedral coordinates), integers as its integers,
/// which must fit the type.
fn attribute_bytes(
    attribute: &PointAttribute,
    points: usize,
    components: usize,
    component: ComponentType,
) -> Result<Vec<u8>, String> {
    let values = attribute.read_f32s(points, components);
    if component == ComponentType::F32 {
        return Ok(values.iter().flat_map(|v| v.to_le_bytes()).collect());
    }
    let (low, high) = match component {
        ComponentType::I8 => (i8::MIN as f32, i8::MAX as f32),
        ComponentType::U8 => (0.0, u8::MAX as f32),
        ComponentType::I16 => (i16::MIN as f32, i16::MAX as f32),
        ComponentType::U16 => (0.0, u16::MAX as f32),
        other => return Err(format!("component type {other:?} is not one an attribute is read in")),
    };
    let mut bytes = Vec::with_capacity(values.len() * component.size());
    for &v in &values {
        if !(v.fract() == 0.0 && (low..=high).contains(&v)) {
            return Err(format!("the decoded value {v} is no {component:?}"));
        }
        match component {
            ComponentType::I8 => bytes.push(v as i8 as u8),
            ComponentType::U8 => bytes.push(v as u8),
            ComponentType::I16 => bytes.extend((v as i16).to_le_bytes()),
            _ => bytes.extend((v as u16).to_le_bytes()),
        }
    }
    Ok(bytes)
}

/// `indices` as `component` numbers, tightly packed.
fn index_bytes(indices: &[u32], component: ComponentType) -> Result<Vec<u8>, String> {
    let largest = indices.iter().copied().max().unwrap_or(0);
    let fits = match component {
        ComponentType::U8 => largest <= u8::MAX as u32,
        ComponentType::U16 => largest <= u16::MAX as u32,
        ComponentType::U32 => true,
        other => return Err(format!("component type {other:?} is not one indices are")),
    };
    if !fits {
        return Err(format!("the decoded index {largest} does not fit its {component:?}"));
    }
    Ok(match component {
        ComponentType::U8 => indices.iter().map(|&i| i as u8).collect(),
        ComponentType::U16 => indices.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect(),
        _ => indices.iter().flat_map(|&i| i.to_le_bytes()).collect(),
    })
}

/// Points accessor `k` at a view of a new buffer of `bytes` (its values tightly packed); the
/// buffer's index.
fn point_at(
    root: &mut gltf::json::Root,
    buffers: &mut Vec<gltf::buffer::Data>,
    k: usize,
    bytes: Vec<u8>,
) -> usize {
    let length = bytes.len();
    let buffer = super::parse::append_buffer(root, buffers, bytes);
    let view = root.buffer_views.len();
    root.buffer_views.push(gltf::json::buffer::View {
        buffer: gltf::json::Index::new(buffer as u32),
        byte_length: length.into(),
        byte_offset: None,
        byte_stride: None,
        name: None,
        target: None,
        extensions: None,
        extras: Default::default(),
    });
    let accessor = &mut root.accessors[k];
    accessor.buffer_view = Some(gltf::json::Index::new(view as u32));
    accessor.byte_offset = None;
    accessor.sparse = None;
    buffer
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn the_extension_object_is_read_and_checked() {
        let e = json!({"bufferView": 3, "attributes": {"POSITION": 0, "TEXCOORD_0": 2}});
        assert_eq!(
            Compressed::read(&e),
            Ok(Compressed { view: 3, attributes: vec![("POSITION".into(), 0), ("TEXCOORD_0".into(), 2)] })
        );
        for (bad, expected) in [
            (json!({"attributes": {}}), "bufferView: missing"),
            (json!({"bufferView": -1, "attributes": {}}), "bufferView: -1 is no unsigned integer"),
            (json!({"bufferView": 0}), "attributes: missing or no object"),
            (
                json!({"bufferView": 0, "attributes": {"NORMAL": "1"}}),
                "attributes.NORMAL: no Draco attribute id",
            ),
        ] {
            assert_eq!(Compressed::read(&bad), Err(expected.to_string()));
        }
    }

    #[test]
    fn indices_are_written_in_their_accessor_s_type() {
        assert_eq!(index_bytes(&[0, 2, 255], ComponentType::U8), Ok(vec![0, 2, 255]));
        assert_eq!(index_bytes(&[1, 258], ComponentType::U16), Ok(vec![1, 0, 2, 1]));
        assert_eq!(index_bytes(&[70000], ComponentType::U32), Ok(70000u32.to_le_bytes().to_vec()));
        assert_eq!(
            index_bytes(&[256], ComponentType::U8),
            Err("the decoded index 256 does not fit its U8".into())
        );
        assert!(index_bytes(&[0], ComponentType::F32).is_err());
    }

    #[test]
    fn without_indices_the_faces_must_be_the_points_in_order() {
        let root: gltf::json::Root = serde_json::from_value(json!({
            "asset": {"version": "2.0"},
            "accessors": [{"componentType": 5126, "count": 4, "type": "SCALAR"}],
            "meshes": [{"primitives": [{"attributes": {"_HEIGHT": 0}}]}]
        }))
        .unwrap();
        let c = Compressed { view: 0, attributes: vec![("_HEIGHT".into(), 0)] };
        let mut mesh = Mesh::new();
        mesh.add_attribute(attribute(draco_core::DataType::Float32, &[0.0, 1.0, 2.0, 3.0]));
        mesh.set_num_points(4);
        // Two triangles sharing an edge: their corners are not the points in order.
        mesh.add_face([0, 1, 2].map(draco_core::PointIndex));
        mesh.add_face([0, 2, 3].map(draco_core::PointIndex));
        let primitive = &root.meshes[0].primitives[0];
        assert_eq!(
            accessor_values(&root, primitive, &c, &mesh),
            Err("indices: none, but the Draco faces are not the points in order".into())
        );
    }

    /// A one-component attribute of `values` stored as Draco's `data_type`.
    fn attribute(data_type: draco_core::DataType, values: &[f32]) -> PointAttribute {
        let mut a = PointAttribute::new();
        a.init(draco_core::GeometryAttributeType::Generic, 1, data_type, false, values.len());
        let bytes: Vec<u8> = match data_type {
            draco_core::DataType::Float32 => values.iter().flat_map(|v| v.to_le_bytes()).collect(),
            _ => values.iter().flat_map(|&v| (v as i16).to_le_bytes()).collect(),
        };
        a.buffer_mut().write(0, &bytes);
        a
    }

    #[test]
    fn attributes_are_written_in_their_accessor_s_type() {
        let floats = attribute(draco_core::DataType::Float32, &[0.25, -1.5]);
        let expected: Vec<u8> = [0.25f32, -1.5].iter().flat_map(|v| v.to_le_bytes()).collect();
        assert_eq!(attribute_bytes(&floats, 2, 1, ComponentType::F32), Ok(expected));
        let shorts = attribute(draco_core::DataType::Int16, &[-32768.0, 300.0]);
        assert_eq!(attribute_bytes(&shorts, 2, 1, ComponentType::I16), Ok(vec![0, 0x80, 44, 1]));
        assert_eq!(
            attribute_bytes(&shorts, 2, 1, ComponentType::U8),
            Err("the decoded value -32768 is no U8".into())
        );
        assert_eq!(
            attribute_bytes(&floats, 2, 1, ComponentType::I8),
            Err("the decoded value 0.25 is no I8".into())
        );
        assert!(attribute_bytes(&floats, 2, 1, ComponentType::U32).is_err());
    }
}
