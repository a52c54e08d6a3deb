//! The scene as the kernels see it: a ray caster over the triangles, and the triangles, their
//! vertex normals, materials and their textures, punctual lights, environment light and light-selection CDF
//! that shading and light sampling read (slices of device buffers on the device, of host
//! buffers on the CPU backend). Every binding holds at least one element, as a device buffer
//! cannot be empty.

use crate::bsdf::Material;
use crate::environment::Environment;
use crate::light::LightEntry;
use crate::normal_map::TriangleTangents;
use crate::normals::TriangleNormals;
use crate::punctual::PunctualLight;
use crate::surface::{MaterialTextures, TriangleColors, TriangleTexcoords};
use crate::texture::Texture;
use crate::triangle::Triangle;

/// The scene, over the ray caster `R` (the one seam between the path code and ray casting).
#[derive(Clone, Copy)]
pub struct Scene<'a, R> {
    /// Answers the closest-hit and occlusion queries; its hits index `triangles`.
    pub caster: R,
    /// Triangles in the ray caster's order.
    pub triangles: &'a [Triangle],
    #[allow(missing_docs)] // indexed by Triangle::material
    pub materials: &'a [Material],
    /// Light-selection CDF over the emissive triangles and the punctual lights.
    pub lights: &'a [LightEntry],
    /// The punctual lights (`LightEntry::light` indexes them; at least one entry, zeroed when
    /// the scene has none, as a device buffer cannot be empty).
    pub punctual: &'a [PunctualLight],
    /// The environment light (`crate::environment::NONE` when the scene has none).
    pub environment: &'a Environment,
    /// Its texels and CDFs (at least one value, as a device buffer cannot be empty).
    pub environment_map: &'a [f32],
    /// Indexed by `Material::textures` (entry 0 unused: no textures).
    pub material_textures: &'a [MaterialTextures],
    /// Indexed by `TextureRef::texture` (one zeroed entry when there are none).
    pub textures: &'a [Texture],
    /// Every texture's texels (`crate::texture`; one zero when there are none).
    pub texels: &'a [u32],
    /// Per triangle in the triangles' order where any material has textures; one zeroed entry
    /// otherwise.
    pub texcoords: &'a [TriangleTexcoords],
    /// Per triangle in the triangles' order where any mesh has smooth normals; one zeroed
    /// (flat) entry otherwise.
    pub normals: &'a [TriangleNormals],
    /// Per triangle in the triangles' order where any triangle has vertex tangents (its
    /// material has a normal texture, its mesh normals: `crate::normal_map`); one zeroed entry
    /// otherwise.
    pub tangents: &'a [TriangleTangents],
    /// Per triangle in the triangles' order where any material has vertex colours
    /// (`MaterialTextures::vertex_colors`); one zeroed entry otherwise.
    pub colors: &'a [TriangleColors],
}
