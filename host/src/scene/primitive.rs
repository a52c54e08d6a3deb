//! One mesh primitive: read once in its mesh's space (morph targets applied, every index checked,
//! its normals, texture coordinates, vertex colours and vertex tangents beside it,
//! its material the copy that reads the colours where it has them), then placed in the
//! world as often as its node draws it — by one matrix (the node's, or each instance's of
//! `instancing`) or by one matrix a vertex (a skin's, `skin`) — each time its triangles added to
//! the soup.

use glam::{Mat3, Mat4, Vec3, Vec4};
use gltf::mesh::Mode;
use shared::cutout::ALPHA_OPAQUE;
use shared::normal_map::TriangleTangents;
use shared::normals::TriangleNormals;
use shared::surface::{TriangleColors, TriangleTexcoords};
use shared::texture::TextureRef;

use super::attributes;
use super::colors::{self, ColouredMaterials};
use super::morph;
use super::read::MAX_COORDINATE;
use super::tangents;
use super::{SceneError, TriangleSoup};

/// A primitive's triangles in its mesh's space.
pub struct MeshPrimitive {
    /// The primitive's glTF path, `meshes[m].primitives[p]`.
    pub at: String,
    /// Vertex positions, morph targets applied.
    pub positions: Vec<Vec3>,
    /// Triangles, indices into `positions` (each below their count).
    pub triangles: Vec<[u32; 3]>,
    /// Material (`TriangleSoup::materials` index).
    pub material: u32,
    /// Vertex normals (None: the mesh is flat), morph targets applied.
    pub normals: Option<Vec<Vec3>>,
    /// Texture coordinate sets (None: the material reads no texture).
    pub texcoords: Option<[Vec<[f32; 2]>; 2]>,
    /// The vertex tangents of a normal texture or an anisotropic material at each triangle's
    /// corners (None: neither).
    pub tangents: Option<Vec<[Vec4; 3]>>,
    /// Vertex colours, linear RGB (`COLOR_0`; None: it has none).
    pub colors: Option<Vec<[f32; 3]>>,
}

/// Where a primitive's vertices go in the world: by one matrix, every vertex (a node's world
/// matrix, times an instance's), or by one a vertex (a skin's blends); with each matrix the inverse
/// transpose its normals take and its determinant (negative where it mirrors).
pub struct Placement {
    matrices: Vec<Mat4>,
    normals: Vec<Mat3>,
    determinants: Vec<f32>,
}

impl Placement {
    /// Every vertex by `matrix`.
    pub fn rigid(matrix: Mat4) -> Self {
        Self::of(vec![matrix])
    }

    /// Vertex i by `matrices[i]`.
    pub fn per_vertex(matrices: Vec<Mat4>) -> Self {
        Self::of(matrices)
    }

    fn of(matrices: Vec<Mat4>) -> Self {
        let normals = matrices.iter().map(|m| Mat3::from_mat4(*m).inverse().transpose()).collect();
        let determinants = matrices.iter().map(Mat4::determinant).collect();
        Self { matrices, normals, determinants }
    }

    /// The index of vertex `i`'s matrix.
    fn of_vertex(&self, i: u32) -> usize {
        if self.matrices.len() == 1 {
            0
        } else {
            i as usize
        }
    }
}

/// Reads primitive `prim` of mesh `mesh` drawn with morph `weights`, or None for one the spec
/// says to skip or that draws no surface (no `POSITION`; points or lines; said in
/// `soup.warnings`). Triangle strips and fans are made triangles (`assemble`). Refused by path:
/// data outside the file (`placeholders`), attributes that cannot be read or are not finite, an
/// index beyond the vertices.
pub fn read<'a, 's, F>(
    get: F,
    (mesh, prim): (&gltf::Mesh<'a>, &gltf::Primitive<'a>),
    weights: &[f32],
    placeholders: &[usize],
    (soup, coloured): (&mut TriangleSoup, &mut ColouredMaterials),
    name: &str,
) -> Result<Option<MeshPrimitive>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let at = format!("meshes[{}].primitives[{}]", mesh.index(), prim.index());
    let mode = prim.mode();
    if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
        soup.warnings.push(format!("{at}: mode {mode:?} draws no surface: not rendered"));
        return Ok(None);
    }
    let malformed = |what: String| SceneError::Malformed { path: name.into(), what };
    for accessor in prim.attributes().map(|(_, a)| a).chain(prim.indices()) {
        let views = accessor
            .view()
            .into_iter()
            .chain(accessor.sparse().into_iter().flat_map(|s| [s.indices().view(), s.values().view()]));
        if let Some(b) = views.map(|v| v.buffer().index()).find(|b| placeholders.contains(b)) {
            return Err(SceneError::Unsupported {
                path: name.into(),
                what: format!(
                    "{at} reads buffers[{b}], whose data is not in the file (no uri, no BIN chunk)"
                ),
            });
        }
    }
    let Some(positions_accessor) = prim.get(&gltf::Semantic::Positions) else {
        soup.warnings.push(format!("{at} has no POSITION: skipped, as the spec says"));
        return Ok(None);
    };
    // Vertex attributes through `attributes`, which reads every type the spec allows them.
    let mut local: Vec<[f32; 3]> = match attributes::read(&positions_accessor, get.clone()) {
        Some(p) => p,
        // No view and no sparse values: zeros, as the spec says.
        None if positions_accessor.view().is_none() => vec![[0.0; 3]; positions_accessor.count()],
        None => return Err(malformed(format!("{at}: its POSITION accessor cannot be read"))),
    };
    morph::displace(get.clone(), prim, gltf::Semantic::Positions, weights, &mut local, (&at, name))?;
    if morph::moves_tangents(prim, weights) {
        soup.warnings.push(format!(
            "{at}: its morph targets' TANGENT displacements are not applied (POSITION and NORMAL are)"
        ));
    }
    if let Some(i) = local.iter().position(|p| !p.iter().all(|x| x.is_finite())) {
        return Err(malformed(format!("{at}: POSITION {i} is not finite: {:?}", local[i])));
    }
    let indices: Vec<u32> = match prim.indices() {
        Some(a) => match read_indices(&a, get.clone()) {
            Some(i) => i,
            // An index accessor without a view or sparse values: zeros, as the spec says.
            None if a.view().is_none() => vec![0; a.count()],
            None => return Err(malformed(format!("{at}.indices: its accessor cannot be read"))),
        },
        None => (0..local.len() as u32).collect(),
    };
    let material = prim.material().index().map(|i| i as u32 + 1).unwrap_or(0);
    let colors = colors::read(get.clone(), prim, local.len(), (&at, name))?;
    if colors.as_ref().is_some_and(|c| c.translucent)
        && coloured.textures_of(material).alpha_mode != ALPHA_OPAQUE
    {
        soup.warnings.push(format!(
            "{at}: COLOR_0's alpha is not applied to its material's cut-out (alphaMode MASK or BLEND)"
        ));
    }
    let textures = soup.materials[material as usize].textures;
    let texcoords = read_texcoords(get.clone(), prim, soup, material, &at, local.len(), name)?;
    let normals = read_normals(get.clone(), prim, weights, &at, local.len(), name)?;
    let (triangles, left_over) = assemble(mode, &indices);
    // Every corner a vertex, before anything reads the corners.
    if let Some(&i) = triangles.as_flattened().iter().find(|&&i| i as usize >= local.len()) {
        return Err(malformed(format!("{at}.indices: index {i} is not below the {} vertices", local.len())));
    }
    // The vertex tangents of a normal texture or an anisotropic material, each triangle's
    // corners in the mesh's space: its TANGENT, or MikkTSpace's in the coordinates of the
    // normal texture, else of the coat's, else TEXCOORD_0 (as `shared::surface::normals_at`
    // takes them).
    let t = soup.material_textures.get(textures as usize).copied().unwrap_or_default();
    let frame = if t.normal.is_some() {
        Some(t.normal)
    } else if t.clearcoat_normal.is_some() {
        Some(t.clearcoat_normal)
    } else {
        (t.anisotropic != 0).then_some(TextureRef::NONE)
    };
    let has_tangent = prim.get(&gltf::Semantic::Tangents).is_some();
    let tangents = match (frame, &normals, &texcoords) {
        // An anisotropic material's TEXCOORD_0 may be missing where its TANGENT is not.
        (Some(r), Some(normals), Some(sets)) if r.is_some() || has_tangent || !sets[0].is_empty() => {
            let mesh = tangents::MeshData { positions: &local, normals, sets, triangles: &triangles };
            Some(tangents::corner_tangents(get, prim, r, &mesh, (&at, name), &mut soup.warnings)?)
        }
        // A mesh without normals is flat: the spec says to ignore its TANGENT, and each
        // triangle keeps its own frame (dp/du, −dp/dv).
        _ => None,
    };
    let coordinates = texcoords.as_ref().is_some_and(|sets| !sets[0].is_empty());
    if frame == Some(TextureRef::NONE) && tangents.is_none() && !coordinates {
        soup.warnings.push(format!(
            "{at}: its material's {} has no tangent frame here (it needs TEXCOORD_0, or TANGENT and NORMAL): its direction is arbitrary",
            super::read::ANISOTROPY
        ));
    }
    if left_over > 0 {
        let why = if mode == Mode::Triangles { "are no multiple of 3" } else { "make no strip or fan" };
        soup.warnings.push(format!(
            "{at}: {} indices (or vertices) {why}: the last {left_over} form no triangle",
            indices.len()
        ));
    }
    // Vertex colours draw a copy of the material that reads them (`colors`; its textures are
    // the material's, read above).
    let material = if colors.is_some() { coloured.of(material, soup) } else { material };
    Ok(Some(MeshPrimitive {
        positions: local.iter().map(|p| Vec3::from_array(*p)).collect(),
        triangles,
        material,
        normals,
        texcoords,
        tangents,
        colors: colors.map(|c| c.rgb),
        at,
    }))
}

impl MeshPrimitive {
    /// Adds the primitive's triangles to `soup`, placed by `placement` (one matrix a vertex where
    /// it is `per_vertex`). Positions transform by the matrices, normals by their inverse
    /// transposes (a matrix without an inverse leaves the primitive flat), tangents by
    /// `tangents::to_world`; a triangle whose corners' matrices mirror (their determinants' sum
    /// is negative) is wound the other way, keeping its normal's sense. `any_textures`: every
    /// triangle keeps texture coordinates (zeros where its material reads none). Refused: a
    /// vertex placed beyond ±`MAX_COORDINATE`.
    pub fn place(
        &self,
        placement: &Placement,
        soup: &mut TriangleSoup,
        any_textures: bool,
        name: &str,
    ) -> Result<(), SceneError> {
        let at = &self.at;
        let matrix = |i: u32| placement.matrices[placement.of_vertex(i)];
        let positions: Vec<Vec3> =
            self.positions.iter().enumerate().map(|(i, p)| matrix(i as u32).transform_point3(*p)).collect();
        if let Some(i) = positions.iter().position(|p| !(p.abs().max_element() <= MAX_COORDINATE)) {
            return Err(SceneError::Malformed {
                path: name.into(),
                what: format!(
                    "{at}: POSITION {i} lies at {} after the node transforms, beyond ±{MAX_COORDINATE:e}",
                    positions[i]
                ),
            });
        }
        let normals: Option<Vec<Vec3>> =
            self.normals.as_ref().filter(|_| placement.normals.iter().all(Mat3::is_finite)).map(|local| {
                let to_world = |i: usize| placement.normals[placement.of_vertex(i as u32)];
                local.iter().enumerate().map(|(i, n)| (to_world(i) * *n).normalize_or_zero()).collect()
            });
        let determinant = |i: u32| placement.determinants[placement.of_vertex(i)];
        for (j, tri) in self.triangles.iter().enumerate() {
            let mut v = tri.map(|i| positions[i as usize]);
            let mut corners = *tri;
            let mut order = [0, 1, 2];
            // A mirroring transform flips the winding; keep the normal's sense.
            if tri.iter().map(|&i| determinant(i)).sum::<f32>() < 0.0 {
                v.swap(1, 2);
                corners.swap(1, 2);
                order.swap(1, 2);
            }
            soup.triangles.push(v);
            soup.material_of.push(self.material);
            if let Some(normals) = &normals {
                // Only a triangle whose normals bend is stored (the rest are flat).
                let ng = (v[1] - v[0]).cross(v[2] - v[0]).normalize_or_zero();
                let ns = corners.map(|i| normals[i as usize]);
                if ns.iter().any(|n| !(n.dot(ng) > 1.0 - 1e-6)) {
                    soup.normals.resize(soup.triangles.len() - 1, TriangleNormals::default());
                    let n = [ns[0].to_array(), ns[1].to_array(), ns[2].to_array()];
                    soup.normals.push(TriangleNormals { n: *n.as_flattened().as_array().expect("nine") });
                }
            }
            if let Some(tangents) = &self.tangents {
                let t = order.map(|k| tangents::to_world(matrix(tri[k]), tangents[j][k]));
                if t.iter().any(|t| *t != Vec4::ZERO) {
                    soup.tangents.resize(soup.triangles.len() - 1, TriangleTangents::default());
                    let t = [t[0].to_array(), t[1].to_array(), t[2].to_array()];
                    soup.tangents.push(TriangleTangents { t: *t.as_flattened().as_array().expect("twelve") });
                }
            }
            if let Some(colors) = &self.colors {
                // Stored up to the last coloured triangle (the rest read none).
                soup.colors.resize(soup.triangles.len() - 1, TriangleColors::default());
                let c = corners.map(|i| colors[i as usize]);
                soup.colors.push(TriangleColors { rgb: *c.as_flattened().as_array().expect("nine") });
            }
            if let Some(sets) = &self.texcoords {
                let mut uv = [0.0f32; 12];
                for (set, coords) in sets.iter().enumerate() {
                    for (k, &i) in corners.iter().enumerate() {
                        let c = coords.get(i as usize).copied().unwrap_or_default();
                        uv[6 * set + 2 * k..6 * set + 2 * k + 2].copy_from_slice(&c);
                    }
                }
                soup.texcoords.push(TriangleTexcoords { uv });
            } else if any_textures {
                soup.texcoords.push(TriangleTexcoords::default());
            }
        }
        Ok(())
    }
}

/// The triangles `indices` make in primitive mode `mode` (TRIANGLES, TRIANGLE_STRIP or
/// TRIANGLE_FAN), wound as glTF 2.0 ("Meshes", "Topology Types") defines them — strip triangle i
/// is {v_i, v_(i+1+i%2), v_(i+2−i%2)}, fan triangle i {v_(i+1), v_(i+2), v_0} — and how many
/// indices are left over (TRIANGLES' beyond a multiple of 3, a strip's or fan's below 3).
pub fn assemble(mode: Mode, indices: &[u32]) -> (Vec<[u32; 3]>, usize) {
    let n = indices.len();
    match mode {
        Mode::TriangleStrip | Mode::TriangleFan if n < 3 => (Vec::new(), n),
        Mode::TriangleStrip => {
            let strip = |i: usize| [indices[i], indices[i + 1 + i % 2], indices[i + 2 - i % 2]];
            ((0..n - 2).map(strip).collect(), 0)
        }
        Mode::TriangleFan => ((0..n - 2).map(|i| [indices[i + 1], indices[i + 2], indices[0]]).collect(), 0),
        _ => {
            let (triangles, rest) = indices.as_chunks::<3>();
            (triangles.to_vec(), rest.len())
        }
    }
}

/// The indices of accessor `a` (unsigned integers of any width, as `validate` checks), or None
/// where it cannot be read.
fn read_indices<'a, 's, F>(a: &gltf::Accessor<'a>, get: F) -> Option<Vec<u32>>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    use gltf::accessor::{DataType, Iter};
    match a.data_type() {
        DataType::U8 => Some(Iter::<u8>::new(a.clone(), get)?.map(u32::from).collect()),
        DataType::U16 => Some(Iter::<u16>::new(a.clone(), get)?.map(u32::from).collect()),
        DataType::U32 => Some(Iter::<u32>::new(a.clone(), get)?.collect()),
        _ => None,
    }
}

/// A primitive's vertex normals in the mesh's space (of length near 1, as read), or None where
/// it has none (the mesh is flat, as the spec says).
fn read_normals<'a, 's, F>(
    get: F,
    prim: &gltf::Primitive<'a>,
    weights: &[f32],
    at: &str,
    vertices: usize,
    name: &str,
) -> Result<Option<Vec<Vec3>>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let Some(accessor) = prim.get(&gltf::Semantic::Normals) else {
        return Ok(None);
    };
    let malformed = |what: String| SceneError::Malformed { path: name.into(), what: format!("{at}: {what}") };
    let local: Vec<[f32; 3]> = match attributes::read(&accessor, get.clone()) {
        Some(n) => n,
        // No view and no sparse values: zeros, which no normal can be.
        None if accessor.view().is_none() => vec![[0.0; 3]; accessor.count()],
        None => return Err(malformed("its NORMAL accessor cannot be read".into())),
    };
    if local.len() < vertices {
        return Err(malformed(format!("NORMAL has {} values for {vertices} vertices", local.len())));
    }
    let mut normals = Vec::with_capacity(local.len());
    for (i, n) in local.iter().enumerate() {
        let n = Vec3::from_array(*n);
        // The spec asks for unit normals; a slightly longer or shorter one is normalised.
        if !(n.is_finite() && n.length() > 0.5) {
            return Err(malformed(format!("NORMAL {i} is not a unit vector: {n}")));
        }
        normals.push(n);
    }
    if weights.iter().any(|&w| w != 0.0) {
        // Displaced by the morph targets, then normalised again (the spec's rule).
        let mut displaced: Vec<[f32; 3]> = normals.iter().map(|n| n.to_array()).collect();
        morph::displace(get, prim, gltf::Semantic::Normals, weights, &mut displaced, (at, name))?;
        for (i, (n, d)) in normals.iter_mut().zip(&displaced).enumerate() {
            *n = Vec3::from_array(*d).normalize_or_zero();
            if *n == Vec3::ZERO {
                return Err(malformed(format!("NORMAL {i}: its morph targets cancel it")));
            }
        }
    }
    Ok(Some(normals))
}

/// The texture coordinates a primitive's textured material reads (`TEXCOORD_0` and, where a
/// texture of the material uses it, `TEXCOORD_1`; a set it does not use is zeros), or None for
/// a material without textures. A set a texture uses and the primitive lacks is refused, as
/// the Khronos validator does; an anisotropic material's `TEXCOORD_0`, its tangent frame's
/// where the primitive has no `TANGENT`, is read where the primitive has it (else empty).
fn read_texcoords<'a, 's, F>(
    get: F,
    prim: &gltf::Primitive<'a>,
    soup: &TriangleSoup,
    material: u32,
    at: &str,
    vertices: usize,
    name: &str,
) -> Result<Option<[Vec<[f32; 2]>; 2]>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let textures = soup.materials[material as usize].textures;
    if textures == 0 {
        return Ok(None);
    }
    let t = &soup.material_textures[textures as usize];
    // A textures entry for a cut-out or vertex colours alone reads no coordinates.
    if !t.slots().iter().any(TextureRef::is_some) && t.anisotropic == 0 {
        return Ok(None);
    }
    let mut sets = [Vec::new(), Vec::new()];
    for (set, coords) in sets.iter_mut().enumerate() {
        let uses = t.slots().iter().any(|r| r.is_some() && r.tex_coord == set as u32);
        // An anisotropic material's tangent frame is TEXCOORD_0's where the primitive has it.
        let frames = set == 0 && t.anisotropic != 0;
        if !uses && !frames {
            continue;
        }
        let Some(accessor) = prim.get(&gltf::Semantic::TexCoords(set as u32)) else {
            if !uses {
                continue;
            }
            return Err(SceneError::Malformed {
                path: name.into(),
                what: format!(
                    "{at}: its material (materials[{}]) reads TEXCOORD_{set}, which the primitive does not have",
                    material - 1
                ),
            });
        };
        *coords = match attributes::read(&accessor, get.clone()) {
            Some(c) => c,
            // No view and no sparse values: zeros, as the spec says.
            None if accessor.view().is_none() => vec![[0.0; 2]; accessor.count()],
            None => {
                return Err(SceneError::Malformed {
                    path: name.into(),
                    what: format!("{at}: its TEXCOORD_{set} accessor cannot be read"),
                })
            }
        };
        if coords.len() < vertices {
            return Err(SceneError::Malformed {
                path: name.into(),
                what: format!("{at}: TEXCOORD_{set} has {} values for {vertices} vertices", coords.len()),
            });
        }
    }
    Ok(Some(sets))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_make_the_spec_s_triangles() {
        let v = [10, 11, 12, 13, 14];
        // A strip alternates its winding so that every triangle faces the same way.
        assert_eq!(assemble(Mode::TriangleStrip, &v), (vec![[10, 11, 12], [11, 13, 12], [12, 13, 14]], 0));
        // A fan turns about its first vertex.
        assert_eq!(assemble(Mode::TriangleFan, &v), (vec![[11, 12, 10], [12, 13, 10], [13, 14, 10]], 0));
        // Triangles in threes; the rest left over, as are a strip's or fan's two.
        assert_eq!(assemble(Mode::Triangles, &v), (vec![[10, 11, 12]], 2));
        assert_eq!(assemble(Mode::TriangleStrip, &v[..2]), (vec![], 2));
        assert_eq!(assemble(Mode::TriangleFan, &[]), (vec![], 0));
    }
}
