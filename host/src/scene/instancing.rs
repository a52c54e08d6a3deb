//! `EXT_mesh_gpu_instancing`: a mesh node drawn once for each of its instances, instance k at
//! the node's world matrix times instance k's TRS (its `TRANSLATION`, `ROTATION`, `SCALE`, each
//! the identity where absent), as the extension defines them. glTF-Transform's `instance` (which
//! its `optimize` runs by default on meshes used five times or more) and gltfpack `-mi` write it,
//! glTF-Transform without marking it required: read as plain glTF, such a file draws each
//! instanced mesh once, at the node.
//!
//! The attributes' accessors must exist and hold the same count of the types the extension
//! allows (floats, a rotation also normalised integers); rotations are normalised. Anything else
//! is refused by path.

use glam::{Mat4, Quat, Vec3};

use super::attributes;
use super::SceneError;

/// The extension on a node whose mesh is instanced.
pub const EXTENSION: &str = "EXT_mesh_gpu_instancing";

/// The transforms node `node`'s mesh is drawn with, each to be applied before the node's world
/// matrix: its instances' TRS, or the identity alone for a node without the extension.
pub fn transforms<'a, 's, F>(
    node: &gltf::Node<'a>,
    doc: &'a gltf::Document,
    get: F,
    name: &str,
) -> Result<Vec<Mat4>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let Some(instancing) = node.extension_value(EXTENSION) else {
        return Ok(vec![Mat4::IDENTITY]);
    };
    let at = format!("nodes[{}].extensions.{EXTENSION}", node.index());
    let malformed = |what: String| SceneError::Malformed { path: name.into(), what: format!("{at}{what}") };
    let attributes = instancing
        .get("attributes")
        .and_then(serde_json::Value::as_object)
        .ok_or_else(|| malformed(": no attributes".into()))?;
    let accessor = |key: &str| -> Result<Option<gltf::Accessor<'a>>, SceneError> {
        let Some(index) = attributes.get(key) else { return Ok(None) };
        index
            .as_u64()
            .and_then(|i| doc.accessors().nth(i as usize))
            .map(Some)
            .ok_or_else(|| malformed(format!(".attributes.{key}: {index} names no accessor")))
    };
    let read = |key: &str| -> Result<Option<Vec<[f32; 4]>>, SceneError> {
        let Some(a) = accessor(key)? else { return Ok(None) };
        let values = match key {
            "ROTATION" => attributes::read::<_, 4>(&a, get.clone()),
            _ => attributes::read::<_, 3>(&a, get.clone())
                .map(|v| v.iter().map(|p| [p[0], p[1], p[2], 0.0]).collect()),
        };
        values
            .filter(|v| v.iter().flatten().all(|x| x.is_finite()))
            .map(Some)
            .ok_or_else(|| malformed(format!(".attributes.{key}: cannot be read as finite numbers")))
    };
    let (translation, rotation, scale) = (read("TRANSLATION")?, read("ROTATION")?, read("SCALE")?);
    let counts: Vec<usize> =
        [&translation, &rotation, &scale].iter().filter_map(|v| v.as_ref().map(Vec::len)).collect();
    let Some(&count) = counts.first() else {
        return Err(malformed(": none of TRANSLATION, ROTATION, SCALE".into()));
    };
    if counts.iter().any(|&c| c != count) {
        return Err(malformed(format!(
            ": its attributes hold {counts:?} instances; the extension wants one count"
        )));
    }
    (0..count)
        .map(|k| {
            let t = translation.as_ref().map_or(Vec3::ZERO, |v| Vec3::new(v[k][0], v[k][1], v[k][2]));
            let s = scale.as_ref().map_or(Vec3::ONE, |v| Vec3::new(v[k][0], v[k][1], v[k][2]));
            let r = match &rotation {
                None => Quat::IDENTITY,
                Some(v) => {
                    let q = Quat::from_array(v[k]);
                    if !(q.length() > 0.5) {
                        return Err(malformed(format!(
                            ".attributes.ROTATION {k}: {:?} is no rotation",
                            v[k]
                        )));
                    }
                    q.normalize()
                }
            };
            Ok(Mat4::from_scale_rotation_translation(s, r, t))
        })
        .collect()
}
