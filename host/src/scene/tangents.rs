//! The vertex tangents of a normal-mapped primitive (`shared::normal_map`): its `TANGENT`
//! where it has one, else MikkTSpace's over its positions, normals and the normal texture's
//! coordinates, as the spec asks ("When tangents are not specified, client implementations
//! SHOULD calculate tangents using default MikkTSpace algorithms with the specified vertex
//! positions, normals, and texture coordinates associated with the normal texture"). Both in
//! the mesh's own space, each triangle's three corners, then to world space.

use bevy_mikktspace::{generate_tangents, Geometry, TangentSpace};
use glam::{Mat4, Vec2, Vec3, Vec4};
use shared::texture::TextureRef;

use super::SceneError;

/// A primitive's triangles with what MikkTSpace reads of each corner, and the tangents it
/// writes back.
struct Mesh<'a> {
    positions: &'a [Vec3],
    normals: &'a [Vec3],
    coordinates: &'a [Vec2],
    triangles: &'a [[u32; 3]],
    tangents: Vec<[Vec4; 3]>,
}

impl Mesh<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.triangles[face][vert] as usize
    }
}

impl Geometry for Mesh<'_> {
    fn num_faces(&self) -> usize {
        self.triangles.len()
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions.get(self.vertex(face, vert)).copied().unwrap_or_default().to_array()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals.get(self.vertex(face, vert)).copied().unwrap_or_default().to_array()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.coordinates.get(self.vertex(face, vert)).copied().unwrap_or_default().to_array()
    }
    fn set_tangent(&mut self, tangent_space: Option<TangentSpace>, face: usize, vert: usize) {
        // MikkTSpace's sign says whether (tangent, bitangent along +v, normal) is right-handed;
        // glTF's bitangent points up the image, along −v, so its w is the opposite (three.js
        // negates it for glTF likewise). A corner MikkTSpace gives nothing keeps zero: the
        // triangle's own frame.
        self.tangents[face][vert] = match tangent_space {
            Some(t) => {
                let [x, y, z, w] = t.tangent_encoded();
                Vec4::new(x, y, z, -w)
            }
            None => Vec4::ZERO,
        };
    }
}

/// What a primitive's tangents are made from, in the mesh's space: its vertices' positions and
/// normals (as read), its texture coordinate sets and its triangles (indices into them).
pub struct MeshData<'a> {
    #[allow(missing_docs)]
    pub positions: &'a [[f32; 3]],
    #[allow(missing_docs)]
    pub normals: &'a [Vec3],
    /// TEXCOORD_0 and TEXCOORD_1 (empty where the material reads no set).
    pub sets: &'a [Vec<[f32; 2]>; 2],
    #[allow(missing_docs)]
    pub triangles: &'a [[u32; 3]],
}

/// The vertex tangents of a primitive whose material has the normal texture `r` (or, for an
/// anisotropic material without one, `TextureRef::NONE`: `TEXCOORD_0` as it is), at each
/// triangle's corners in the mesh's space: its `TANGENT` where it has one, else MikkTSpace's
/// over its positions, normals and `r`'s coordinates.
/// (`at`, `name`: the primitive's glTF path and the file's, for errors; a primitive whose
/// triangles MikkTSpace does not take keeps each triangle's own frame, said in `warnings`.)
pub fn corner_tangents<'a, 's, F>(
    get: F,
    prim: &gltf::Primitive<'a>,
    r: TextureRef,
    mesh: &MeshData,
    (at, name): (&str, &str),
    warnings: &mut Vec<String>,
) -> Result<Vec<[Vec4; 3]>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    if let Some(file) = read_tangents(get, prim, at, mesh.positions.len(), name)? {
        let corner = |i: u32| file.get(i as usize).copied().unwrap_or_default();
        return Ok(mesh.triangles.iter().map(|t| t.map(corner)).collect());
    }
    let positions: Vec<Vec3> = mesh.positions.iter().map(|p| Vec3::from_array(*p)).collect();
    let fan = largest_fan(&positions, mesh.triangles);
    if fan > MAX_FAN {
        warnings.push(format!(
            "{at}: {fan} triangle corners share one position, more than MikkTSpace is given ({MAX_FAN}): its tangent frame is each triangle's own"
        ));
        return Ok(vec![[Vec4::ZERO; 3]; mesh.triangles.len()]);
    }
    let normals: Vec<Vec3> = mesh.normals.iter().map(|n| n.normalize()).collect();
    let coordinates = normal_texture_coordinates(r, mesh.sets);
    Ok(mikktspace(&positions, &normals, &coordinates, mesh.triangles))
}

/// The most triangle corners that MikkTSpace is given at one position. Its grouping of the
/// triangles around a vertex recurses once a triangle and its welding compares the corners at
/// one position pairwise (the reference implementation's, which `bevy_mikktspace` keeps): a fan
/// of tens of thousands of triangles, or a mesh whose positions are all one (a POSITION
/// accessor without data reads as zeros), would exhaust the stack or the time. A real mesh's
/// vertex joins a few dozen triangles.
pub const MAX_FAN: usize = 4096;

/// The most corners of `triangles` (indices into `positions`) at one position.
fn largest_fan(positions: &[Vec3], triangles: &[[u32; 3]]) -> usize {
    let mut at = std::collections::HashMap::new();
    let mut largest = 0;
    for &i in triangles.as_flattened() {
        let p = positions.get(i as usize).copied().unwrap_or_default();
        let count = at.entry(p.to_array().map(f32::to_bits)).or_insert(0usize);
        *count += 1;
        largest = largest.max(*count);
    }
    largest
}

/// A primitive's `TANGENT` in the mesh's space, one a vertex, or None where it has none. A
/// tangent that is not finite is refused; a zero one gives no direction (a triangle whose three
/// are zero keeps its own frame).
fn read_tangents<'a, 's, F>(
    get: F,
    prim: &gltf::Primitive<'a>,
    at: &str,
    vertices: usize,
    name: &str,
) -> Result<Option<Vec<Vec4>>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let Some(accessor) = prim.get(&gltf::Semantic::Tangents) else {
        return Ok(None);
    };
    let malformed = |what: String| SceneError::Malformed { path: name.into(), what: format!("{at}: {what}") };
    let tangents: Vec<[f32; 4]> = match super::attributes::read(&accessor, get) {
        Some(t) => t,
        // No view and no sparse values: zeros, which give no frame.
        None if accessor.view().is_none() => vec![[0.0; 4]; accessor.count()],
        None => return Err(malformed("its TANGENT accessor cannot be read".into())),
    };
    if tangents.len() < vertices {
        return Err(malformed(format!("TANGENT has {} values for {vertices} vertices", tangents.len())));
    }
    let mut out = Vec::with_capacity(tangents.len());
    for (i, t) in tangents.iter().enumerate() {
        let t = Vec4::from_array(*t);
        if !t.is_finite() {
            return Err(malformed(format!("TANGENT {i} is not finite: {t}")));
        }
        out.push(t);
    }
    Ok(Some(out))
}

/// MikkTSpace's tangents of `triangles` (indices into the vertex attributes; an index beyond
/// them reads zeros) at each triangle's corners: xyz unit, w the glTF bitangent's sign, so that
/// the bitangent `w · (n × t)` points up the texture's image (towards decreasing v).
pub fn mikktspace(
    positions: &[Vec3],
    normals: &[Vec3],
    coordinates: &[Vec2],
    triangles: &[[u32; 3]],
) -> Vec<[Vec4; 3]> {
    let mut mesh =
        Mesh { positions, normals, coordinates, triangles, tangents: vec![[Vec4::ZERO; 3]; triangles.len()] };
    // The crate's error has no variants yet (it is non-exhaustive): were it to fail, every
    // triangle would keep its own frame.
    match generate_tangents(&mut mesh) {
        Ok(()) => mesh.tangents,
        Err(_) => vec![[Vec4::ZERO; 3]; triangles.len()],
    }
}

/// The coordinates a normal texture `r` reads at each vertex: its set of `sets` (TEXCOORD_0
/// and TEXCOORD_1), through its `KHR_texture_transform`, as the device looks it up.
pub fn normal_texture_coordinates(r: TextureRef, sets: &[Vec<[f32; 2]>; 2]) -> Vec<Vec2> {
    let set = &sets[(r.tex_coord == 1) as usize];
    set.iter().map(|&uv| r.coordinates(Vec2::from_array(uv), Vec2::from_array(uv))).collect()
}

/// A tangent of the mesh's space (xyz, w) in world space under the node's matrix `world`: xyz
/// transforms as a direction on the surface (by the matrix itself, not its inverse transpose)
/// and is normalised; w flips where the matrix mirrors, since the bitangent `w · (n × t)` is
/// built from the transformed normal and tangent. Zero stays zero.
pub fn to_world(world: Mat4, tangent: Vec4) -> Vec4 {
    let linear = glam::Mat3::from_mat4(world);
    let t = (linear * tangent.truncate()).normalize_or_zero();
    if t == Vec3::ZERO {
        return Vec4::ZERO;
    }
    let w = if tangent.w < 0.0 { -1.0 } else { 1.0 };
    t.extend(if linear.determinant() < 0.0 { -w } else { w })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat square z = 0, (0, 0)–(1, 1), mapped u = x and v = 1 − y (the image's up is +y),
    /// or mirrored (u = 1 − x), with +z normals.
    fn square(mirrored: bool) -> Vec<[Vec4; 3]> {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let coordinates: Vec<Vec2> =
            positions.iter().map(|p| Vec2::new(if mirrored { 1.0 - p.x } else { p.x }, 1.0 - p.y)).collect();
        mikktspace(&positions, &[Vec3::Z; 4], &coordinates, &[[0, 1, 2], [0, 2, 3]])
    }

    /// On a flat, evenly mapped surface MikkTSpace's frame is the triangle's own: the tangent
    /// along +u (dp/du) and the bitangent `w · (n × t)` up the image, along −dp/dv.
    #[test]
    fn mikktspace_on_a_flat_square_is_the_mapping_frame() {
        for (mirrored, tangent) in [(false, Vec3::X), (true, -Vec3::X)] {
            for corner in square(mirrored).iter().flatten() {
                assert!((corner.truncate() - tangent).length() < 1e-6, "{mirrored}: {corner}");
                let bitangent = Vec3::Z.cross(corner.truncate()) * corner.w;
                // v = 1 − y, so up the image (−dp/dv) is +y, mirrored or not.
                assert!((bitangent - Vec3::Y).length() < 1e-6, "{mirrored}: {bitangent}");
            }
        }
    }

    /// A tangent follows the node's matrix as a direction; a mirroring matrix flips w, so that
    /// the bitangent built from the transformed normal still points where the mapped one does.
    #[test]
    fn tangents_follow_the_node_and_flip_their_sign_in_a_mirror() {
        let t = Vec4::new(1.0, 0.0, 0.0, 1.0);
        let turned = to_world(
            Mat4::from_rotation_z(std::f32::consts::FRAC_PI_2) * Mat4::from_scale(Vec3::splat(3.0)),
            t,
        );
        assert!((turned - Vec4::new(0.0, 1.0, 0.0, 1.0)).length() < 1e-6, "{turned}");
        let mirror = Mat4::from_scale(Vec3::new(1.0, 1.0, -1.0));
        assert_eq!(to_world(mirror, t), Vec4::new(1.0, 0.0, 0.0, -1.0));
        // The spec's bitangent in the mirrored world: n' = (0, 0, −1), w' = −1, so
        // w' (n' × t') = +y, the mirror image of the mesh's bitangent +y.
        let n = Vec3::NEG_Z;
        assert_eq!(n.cross(Vec3::X) * -1.0, Vec3::Y);
        assert_eq!(to_world(mirror, Vec4::ZERO), Vec4::ZERO);
    }

    /// Corners are counted by position, whichever vertex they index.
    #[test]
    fn the_largest_fan_counts_the_corners_at_one_position() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ZERO];
        assert_eq!(largest_fan(&positions, &[[0, 1, 2], [3, 2, 1], [0, 1, 2]]), 3);
        assert_eq!(largest_fan(&positions, &[]), 0);
    }

    /// The normal texture's coordinates are its own set through its transform.
    #[test]
    fn a_normal_texture_reads_its_own_set_through_its_transform() {
        let sets = [vec![[0.5, 0.25]], vec![[0.1, 0.2]]];
        let r = TextureRef {
            texture: 0,
            tex_coord: 1,
            transform: shared::texture::texture_transform([0.5, 0.0], 0.0, [2.0, 2.0]),
        };
        assert_eq!(normal_texture_coordinates(r, &sets), vec![Vec2::new(0.7, 0.4)]);
    }
}
