//! Morph targets (glTF 2.0, "Morph Targets"): a primitive's vertices as a viewer draws them
//! without animation — each attribute plus its targets' displacements, each weighted by the
//! node's `weights`, else the mesh's, else 0. Blender's exporter writes a mesh's shape keys so, at
//! their current values; reading the base attributes alone drew the mesh without them.
//!
//! `POSITION` and `NORMAL` displacements are applied (a displaced normal is normalised again, as
//! the spec says); `TANGENT` displacements are not (a warning says so where a weight moves one).

use gltf::Semantic;

use super::attributes;
use super::SceneError;

/// The weights the node's mesh is drawn with: the node's, else the mesh's (empty: every weight
/// 0, the base attributes).
pub fn weights<'a>(node: &gltf::Node<'a>, mesh: &gltf::Mesh<'a>) -> &'a [f32] {
    node.weights().or_else(|| mesh.weights()).unwrap_or(&[])
}

/// Adds to `values` (the primitive's `semantic`, `POSITION` or `NORMAL`, one per vertex) the
/// displacements of the primitive's morph targets, each times its weight in `weights`; targets
/// of weight 0 are not read. Refused by path (`at`): weights that are not finite or not one a
/// target, a target accessor that cannot be read or has another count than the vertices.
pub fn displace<'a, 's, F>(
    get: F,
    prim: &gltf::Primitive<'a>,
    semantic: Semantic,
    weights: &[f32],
    values: &mut [[f32; 3]],
    (at, name): (&str, &str),
) -> Result<(), SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let malformed = |what: String| SceneError::Malformed { path: name.into(), what: format!("{at}: {what}") };
    let targets = prim.morph_targets().len();
    if weights.is_empty() {
        return Ok(());
    }
    if weights.len() != targets {
        return Err(malformed(format!("{} morph weights for its {targets} morph targets", weights.len())));
    }
    if let Some(w) = weights.iter().find(|w| !w.is_finite()) {
        return Err(malformed(format!("a morph weight of {w}")));
    }
    for (t, (target, &w)) in prim.morph_targets().zip(weights).enumerate() {
        let accessor = match semantic {
            Semantic::Positions => target.positions(),
            Semantic::Normals => target.normals(),
            _ => unreachable!("only POSITION and NORMAL are displaced"),
        };
        let (Some(accessor), true) = (accessor, w != 0.0) else { continue };
        let name = if semantic == Semantic::Positions { "POSITION" } else { "NORMAL" };
        let offsets: Vec<[f32; 3]> = match attributes::read(&accessor, get.clone()) {
            Some(d) => d,
            // No view and no sparse values: zeros, as the spec says.
            None if accessor.view().is_none() => continue,
            None => return Err(malformed(format!("targets[{t}].{name} cannot be read"))),
        };
        if offsets.len() != values.len() {
            return Err(malformed(format!(
                "targets[{t}].{name} has {} values for {} vertices",
                offsets.len(),
                values.len()
            )));
        }
        for (v, d) in values.iter_mut().zip(&offsets) {
            for k in 0..3 {
                v[k] += w * d[k];
            }
        }
    }
    Ok(())
}

/// Whether a weight other than 0 moves a `TANGENT` target of the primitive (not applied:
/// [`displace`] takes `POSITION` and `NORMAL`).
pub fn moves_tangents(prim: &gltf::Primitive, weights: &[f32]) -> bool {
    prim.morph_targets().zip(weights).any(|(t, &w)| w != 0.0 && t.tangents().is_some())
}
