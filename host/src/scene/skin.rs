//! Skins (glTF 2.0, "Skins"): a skinned mesh drawn in the pose its joints' nodes hold, as a
//! viewer draws it without animation. Vertex v goes to `Σ_k w_k · J[j_k]` times its position,
//! where its `JOINTS_n` name joints j_k of the node's skin, its `WEIGHTS_n` give their weights
//! w_k, and joint j's matrix `J[j]` is the joint node's world matrix times the skin's inverse bind
//! matrix j (the identity where the skin has none). The skinned node's own transform is not
//! applied, as the spec says; morph targets are, before the skin.
//!
//! Blender's exporter writes armatures so: the joints hold the rest pose (its default), or the
//! pose of the current frame (`export_rest_position_armature` off). Reading the mesh at its node
//! instead drew it in its bind pose, wherever the node was.
//!
//! Weights are divided by their sum, as Blender's armature modifier does (the spec asks for sums
//! of 1; a quantised file's are 1 to a rounding). Refused by path: a joint outside the rendered
//! scene, inverse bind matrices that cannot be read or are not finite, a primitive without joints
//! and weights, a weight that is negative or not finite, a weighted joint index beyond the
//! skin's joints, a vertex without weight.

use glam::Mat4;

use super::attributes;
use super::SceneError;

/// The matrix of each of `skin`'s joints: the joint node's world matrix (`worlds`, indexed by
/// node; None for a node outside the rendered scene) times its inverse bind matrix.
pub fn joint_matrices<'a, 's, F>(
    skin: &gltf::Skin<'a>,
    worlds: &[Option<Mat4>],
    get: F,
    name: &str,
) -> Result<Vec<Mat4>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let at = format!("skins[{}]", skin.index());
    let malformed = |what: String| SceneError::Malformed { path: name.into(), what: format!("{at}{what}") };
    let joints: Vec<gltf::Node> = skin.joints().collect();
    let inverse_binds: Vec<Mat4> = match skin.inverse_bind_matrices() {
        None => vec![Mat4::IDENTITY; joints.len()],
        Some(a) => gltf::accessor::Iter::<[[f32; 4]; 4]>::new(a, get)
            .map(|m| m.map(|m| Mat4::from_cols_array_2d(&m)).collect())
            .ok_or_else(|| malformed(".inverseBindMatrices: cannot be read".into()))?,
    };
    if let Some(k) = inverse_binds.iter().position(|m| !m.is_finite()) {
        return Err(malformed(format!(".inverseBindMatrices: matrix {k} is not finite")));
    }
    joints
        .iter()
        .enumerate()
        .map(|(k, joint)| {
            let world = worlds.get(joint.index()).copied().flatten().ok_or_else(|| {
                malformed(format!(".joints[{k}]: nodes[{}] is not in the scene rendered", joint.index()))
            })?;
            let inverse_bind = inverse_binds
                .get(k)
                .ok_or_else(|| malformed(format!(".inverseBindMatrices: no matrix for joint {k}")))?;
            Ok(world * *inverse_bind)
        })
        .collect()
}

/// The matrix of each of `prim`'s `vertices`: the joint matrices `joints` its `JOINTS_n` name,
/// blended by its `WEIGHTS_n` divided by their sum (`skinning_matrix`).
pub fn vertex_matrices<'a, 's, F>(
    get: F,
    prim: &gltf::Primitive<'a>,
    joints: &[Mat4],
    vertices: usize,
    (at, name): (&str, &str),
) -> Result<Vec<Mat4>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let malformed = |what: String| SceneError::Malformed { path: name.into(), what: format!("{at}: {what}") };
    // Each set's (joint indices, weights), one of each a vertex.
    let mut sets = Vec::new();
    for set in 0.. {
        let (Some(j), Some(w)) =
            (prim.get(&gltf::Semantic::Joints(set)), prim.get(&gltf::Semantic::Weights(set)))
        else {
            if prim.get(&gltf::Semantic::Joints(set)).is_some()
                || prim.get(&gltf::Semantic::Weights(set)).is_some()
            {
                return Err(malformed(format!("JOINTS_{set} and WEIGHTS_{set} come in pairs; it has one")));
            }
            break;
        };
        let read = |a: gltf::Accessor<'a>, what: &str| -> Result<Vec<[f32; 4]>, SceneError> {
            let values = match attributes::read(&a, get.clone()) {
                Some(v) => v,
                // No view and no sparse values: zeros, as the spec says.
                None if a.view().is_none() => vec![[0.0; 4]; a.count()],
                None => return Err(malformed(format!("its {what}_{set} accessor cannot be read"))),
            };
            if values.len() < vertices {
                return Err(malformed(format!(
                    "{what}_{set} has {} values for {vertices} vertices",
                    values.len()
                )));
            }
            Ok(values)
        };
        sets.push((read(j, "JOINTS")?, read(w, "WEIGHTS")?));
    }
    if sets.is_empty() {
        return Err(malformed("its node has a skin, but it has no JOINTS_0 and WEIGHTS_0".into()));
    }
    (0..vertices)
        .map(|v| {
            let influences = sets.iter().flat_map(|(j, w)| j[v].into_iter().zip(w[v]));
            skinning_matrix(influences, joints).map_err(|why| malformed(format!("vertex {v}: {why}")))
        })
        .collect()
}

/// One vertex's skinning matrix: `Σ w · joints[j]` over its `influences` (joint index j as read,
/// weight w), divided by the weights' sum. Joints of weight 0 are not looked up. Err says why
/// there is none: a weight that is negative or not finite, a weighted index beyond `joints`, or
/// no weight at all.
pub fn skinning_matrix(
    influences: impl Iterator<Item = (f32, f32)>,
    joints: &[Mat4],
) -> Result<Mat4, String> {
    let (mut sum, mut total) = (Mat4::ZERO, 0.0);
    for (j, w) in influences {
        if !(w >= 0.0 && w.is_finite()) {
            return Err(format!("a joint weight of {w}"));
        }
        if w == 0.0 {
            continue;
        }
        let joint = joints
            .get(j as usize)
            .ok_or_else(|| format!("joint {j} is weighted, and its skin has {} joints", joints.len()))?;
        sum += *joint * w;
        total += w;
    }
    if total <= 0.0 {
        return Err("no joint weighs on it".into());
    }
    Ok(sum * (1.0 / total))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Quat, Vec3};

    #[test]
    fn a_vertex_moves_by_its_joints_weighted_and_normalised() {
        let joints = [
            Mat4::from_translation(Vec3::X),
            Mat4::from_rotation_z(std::f32::consts::FRAC_PI_2),
            Mat4::from_scale(Vec3::splat(2.0)),
        ];
        let p = Vec3::new(1.0, 0.0, 0.0);
        // One joint alone: its matrix.
        let one = skinning_matrix([(1.0, 1.0)].into_iter(), &joints).unwrap();
        assert!(one.transform_point3(p).abs_diff_eq(Vec3::Y, 1e-6));
        // Two halves: the mean of the two placements (linear blend skinning).
        let half = skinning_matrix([(0.0, 0.5), (1.0, 0.5)].into_iter(), &joints).unwrap();
        assert!(half.transform_point3(p).abs_diff_eq(Vec3::new(1.0, 0.5, 0.0), 1e-6));
        // Weights summing to 254/255 (normalised bytes) are divided by their sum; a zero
        // weight's joint is not looked up, even beyond the joints.
        let bytes =
            skinning_matrix([(0.0, 127.0 / 255.0), (1.0, 127.0 / 255.0), (9.0, 0.0)].into_iter(), &joints)
                .unwrap();
        assert!(bytes.abs_diff_eq(half, 1e-6));
        // The weights over sets: a third joint in the second set.
        let three = skinning_matrix([(0.0, 0.25), (1.0, 0.25), (2.0, 0.5)].into_iter(), &joints).unwrap();
        assert!(three.transform_point3(p).abs_diff_eq(Vec3::new(2.0 / 4.0 + 1.0, 0.25, 0.0), 1e-6));
        // Rigid joints at equal weight average their matrices: not a rigid motion in general
        // (the blend's known shrinking), checked here as the spec's formula.
        let r = Mat4::from_quat(Quat::from_rotation_z(std::f32::consts::PI));
        let shrunk = skinning_matrix([(0.0, 0.5), (1.0, 0.5)].into_iter(), &[Mat4::IDENTITY, r]).unwrap();
        assert!(shrunk.transform_point3(p).abs_diff_eq(Vec3::ZERO, 1e-6));
    }

    #[test]
    fn a_vertex_without_a_place_is_refused_with_why() {
        let joints = [Mat4::IDENTITY];
        let err = |i: &[(f32, f32)]| skinning_matrix(i.iter().copied(), &joints).unwrap_err();
        assert_eq!(err(&[(0.0, 0.0), (0.0, 0.0)]), "no joint weighs on it");
        assert_eq!(err(&[(0.0, -0.5), (0.0, 1.5)]), "a joint weight of -0.5");
        assert_eq!(err(&[(0.0, f32::NAN)]), "a joint weight of NaN");
        assert_eq!(err(&[(3.0, 1.0)]), "joint 3 is weighted, and its skin has 1 joints");
    }
}
