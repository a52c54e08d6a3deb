//! Vertex colours (glTF 2.0, "Meshes": `COLOR_0`, a linear RGB or RGBA a vertex, which multiplies
//! the base colour). Blender's exporter writes a mesh's colour attribute as `COLOR_0` where its
//! material reads it (a Color Attribute node into the Principled BSDF's Base Color), and leaves
//! the material's `baseColorFactor` white: read without them, such a mesh rendered white.
//!
//! A primitive with `COLOR_0` draws its material as a copy whose textures entry says so
//! (`MaterialTextures::vertex_colors`, one copy a material: [`ColouredMaterials`]); its triangles
//! carry the colours at their corners (`shared::surface::TriangleColors`), which
//! `shared::surface` interpolates and multiplies into the base colour. `COLOR_0`'s alpha is not
//! applied: it matters only to a material's cut-out (`alphaMode` MASK or BLEND), where a warning
//! says so. A colour that is not finite or lies outside [0, 1] is refused by path.

use std::collections::HashMap;

use shared::surface::MaterialTextures;

use super::attributes;
use super::{SceneError, TriangleSoup};

/// The copies of the materials that primitives with vertex colours draw.
pub struct ColouredMaterials {
    /// Every material's textures entry as the loader built it, whether or not the material
    /// keeps one (indexed as `TriangleSoup::materials`).
    textures: Vec<MaterialTextures>,
    /// Material → its copy with vertex colours.
    copies: HashMap<u32, u32>,
}

impl ColouredMaterials {
    /// Copies of the materials whose textures entries are `textures` (one a material, as built).
    pub fn new(textures: Vec<MaterialTextures>) -> Self {
        Self { textures, copies: HashMap::new() }
    }

    /// The textures entry material `material` was built with (its alpha mode among them).
    pub fn textures_of(&self, material: u32) -> &MaterialTextures {
        &self.textures[material as usize]
    }

    /// The material a primitive with vertex colours draws `material` with: a copy of it (made
    /// once, appended to `soup`) whose textures entry sets `vertex_colors`.
    pub fn of(&mut self, material: u32, soup: &mut TriangleSoup) -> u32 {
        *self.copies.entry(material).or_insert_with(|| {
            let mut copy = soup.materials[material as usize];
            copy.textures = soup.material_textures.len() as u32;
            soup.material_textures
                .push(MaterialTextures { vertex_colors: 1, ..self.textures[material as usize] });
            soup.materials.push(copy);
            soup.materials.len() as u32 - 1
        })
    }
}

/// A primitive's `COLOR_0`.
pub struct VertexColors {
    /// Linear RGB, one a vertex.
    pub rgb: Vec<[f32; 3]>,
    /// Whether any vertex's alpha lies below 1.
    pub translucent: bool,
}

/// `prim`'s `COLOR_0` for its `vertices`; None where it has none. Refused by path (`at`): an
/// accessor that cannot be read or holds fewer values than the vertices, a colour that is not finite or lies outside
/// [0, 1] (by more than 10⁻³, a float file's rounding; within it, clamped).
pub fn read<'a, 's, F>(
    get: F,
    prim: &gltf::Primitive<'a>,
    vertices: usize,
    (at, name): (&str, &str),
) -> Result<Option<VertexColors>, SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let Some(accessor) = prim.get(&gltf::Semantic::Colors(0)) else {
        return Ok(None);
    };
    let malformed = |what: String| SceneError::Malformed { path: name.into(), what: format!("{at}: {what}") };
    let rgba: Vec<[f32; 4]> = match accessor.dimensions() {
        gltf::accessor::Dimensions::Vec4 => attributes::read::<_, 4>(&accessor, get),
        _ => attributes::read::<_, 3>(&accessor, get)
            .map(|v| v.iter().map(|c| [c[0], c[1], c[2], 1.0]).collect()),
    }
    .or_else(|| accessor.view().is_none().then(|| vec![[0.0, 0.0, 0.0, 0.0]; accessor.count()]))
    .ok_or_else(|| malformed("its COLOR_0 accessor cannot be read".into()))?;
    if rgba.len() < vertices {
        return Err(malformed(format!("COLOR_0 has {} values for {vertices} vertices", rgba.len())));
    }
    if let Some(i) = rgba.iter().position(|c| !c.iter().all(|x| (-1e-3..=1.0 + 1e-3).contains(x))) {
        return Err(malformed(format!("COLOR_0 {i}: {:?} lies outside [0, 1]", rgba[i])));
    }
    Ok(Some(VertexColors {
        rgb: rgba.iter().map(|c| [c[0], c[1], c[2]].map(|x| x.clamp(0.0, 1.0))).collect(),
        translucent: rgba.iter().any(|c| c[3] < 1.0),
    }))
}
