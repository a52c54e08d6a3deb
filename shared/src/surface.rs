//! The material and the normals at a surface point: a triangle's material with its textures
//! looked up at the point's texture coordinates, and its geometric and shading normals
//! ([`normals_at`]) — what every stage shades with, from a hit (trace, the path tracer), a
//! stored path vertex (connect: its position and triangle) or a point sampled on a light.
//!
//! A material without textures ([`Material::textures`] 0) is the triangle's material as it is;
//! otherwise (glTF 2.0's `pbrMetallicRoughness`, `emissiveTexture` and `normalTexture`):
//! - the base colour is `baseColorFactor` × `baseColorTexture`'s sRGB-decoded rgb × the
//!   vertices' `COLOR_0` ([`TriangleColors`], where the material's triangles have it);
//! - roughness is `roughnessFactor` × the green channel and metallic `metallicFactor` × the
//!   blue channel of `metallicRoughnessTexture` (linear), mixed with transmission as the
//!   untextured material is ([`Material::with_metallic`]);
//! - emission is `emissiveFactor` × strength × `emissiveTexture`'s sRGB-decoded rgb;
//! - the shading normal is bent by `normalTexture` (`crate::normal_map`, in [`normals_at`]);
//! - `KHR_materials_transmission`'s transmission is transmissionFactor × transmissionTexture's
//!   red channel (linear), mixed with the point's metallic as the untextured material is;
//! - `KHR_materials_specular`'s specularFactor × specularTexture's alpha (linear) and
//!   specularColorFactor × specularColorTexture's sRGB-decoded rgb;
//! - `KHR_materials_anisotropy`'s strength is anisotropyStrength × the blue channel of its
//!   anisotropyTexture (linear), whose red and green turn the lobe ([`anisotropy_direction`],
//!   in [`normals_at`]).
//!
//! Texture coordinates are interpolated over the triangle from its vertices' `TEXCOORD_0` and
//! `TEXCOORD_1` ([`TriangleTexcoords`]) at the point's barycentric coordinates, which
//! [`barycentrics`] recovers from the point itself: a path vertex stores its position, not its
//! coordinates, and recovering them gives the trace and connect stages the same material and
//! shading normal at the same vertex. The shading normal is interpolated the same way from the
//! vertices' `NORMAL` ([`TriangleNormals`]; `crate::normals` says which normal is used where).

use glam::{Vec2, Vec3, Vec4};

use crate::bsdf::Material;
use crate::element::element_or;
use crate::normal_map::{position_derivatives, TangentFrame, TriangleTangents};
use crate::normals::{shading_normal, Normals, TriangleNormals};
use crate::scene::Scene;
use crate::texture::{sample, Texture, TextureRef};
use crate::triangle::Triangle;

/// The textures of a material and the factors they multiply, and its cut-out (`crate::cutout`)
/// (uploaded as it is; entry 0 of the scene's list is never used: [`Material::textures`] 0
/// means none).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MaterialTextures {
    /// `baseColorTexture` (sRGB).
    pub base_color: TextureRef,
    /// `metallicRoughnessTexture` (linear; G roughness, B metallic).
    pub metallic_roughness: TextureRef,
    /// `emissiveTexture` (sRGB).
    pub emissive: TextureRef,
    /// `normalTexture` (linear; a tangent-space normal, `crate::normal_map`).
    pub normal: TextureRef,
    /// glTF's metallicFactor (the material's `metallic` is a share derived from it).
    pub metallic: f32,
    /// glTF's roughnessFactor (the material's `alpha` is its square).
    pub roughness: f32,
    /// `KHR_materials_transmission`'s transmissionFactor (the material's `transmission` is a
    /// share derived from it).
    pub transmission_factor: f32,
    /// glTF's `alphaMode` (`crate::cutout`'s `ALPHA_*`; OPAQUE for a material without one).
    pub alpha_mode: u32,
    /// glTF's `alphaCutoff` (MASK).
    pub alpha_cutoff: f32,
    /// `baseColorFactor`'s alpha, which the texture's alpha multiplies.
    pub alpha: f32,
    /// `normalTexture`'s scale: the factor of the texel's x and y.
    pub normal_scale: f32,
    /// `KHR_materials_clearcoat`'s clearcoatTexture (linear; R the coat's intensity).
    pub clearcoat: TextureRef,
    /// `KHR_materials_clearcoat`'s clearcoatRoughnessTexture (linear; G the coat's roughness).
    pub clearcoat_roughness: TextureRef,
    /// clearcoatFactor, which the texture's R multiplies.
    pub clearcoat_factor: f32,
    /// clearcoatRoughnessFactor, which the texture's G multiplies (the material's
    /// `clearcoat_alpha` is the product's square).
    pub clearcoat_roughness_factor: f32,
    /// `KHR_materials_clearcoat`'s clearcoatNormalTexture (linear; a tangent-space normal of the
    /// coat alone, in the normal texture's tangent frame).
    pub clearcoat_normal: TextureRef,
    /// clearcoatNormalTexture's scale.
    pub clearcoat_normal_scale: f32,
    /// 1 where the material's triangles carry `COLOR_0` ([`TriangleColors`]), which multiplies
    /// the base colour; 0 otherwise.
    pub vertex_colors: u32,
    /// 1 where the material is anisotropic (`Material::anisotropy`), so that [`normals_at`]
    /// gives its direction; 0 otherwise (isotropic materials without textures read no entry).
    pub anisotropic: u32,
    /// `KHR_materials_anisotropy`'s anisotropyTexture (linear; R and G a direction in the
    /// tangent frame, [`anisotropy_direction`]; B the strength's factor).
    pub anisotropy: TextureRef,
    /// `KHR_materials_specular`'s specularTexture (linear; A the specularFactor's factor).
    pub specular: TextureRef,
    /// `KHR_materials_specular`'s specularColorTexture (sRGB; rgb the specularColorFactor's).
    pub specular_color: TextureRef,
    /// `KHR_materials_transmission`'s transmissionTexture (linear; R the transmissionFactor's
    /// factor).
    pub transmission: TextureRef,
    /// `KHR_materials_sheen`'s sheenColorTexture (sRGB; rgb the sheenColorFactor's factor).
    pub sheen_color: TextureRef,
    /// `KHR_materials_sheen`'s sheenRoughnessTexture (linear; A the sheenRoughnessFactor's
    /// factor).
    pub sheen_roughness: TextureRef,
}

impl MaterialTextures {
    /// Every texture slot, in a fixed order (for the host's checks; the shading reads them by
    /// name).
    pub fn slots(&self) -> [TextureRef; 13] {
        [
            self.base_color,
            self.metallic_roughness,
            self.emissive,
            self.normal,
            self.clearcoat,
            self.clearcoat_roughness,
            self.clearcoat_normal,
            self.anisotropy,
            self.specular,
            self.specular_color,
            self.transmission,
            self.sheen_color,
            self.sheen_roughness,
        ]
    }
}

/// A triangle's texture coordinates (uploaded as it is, one per triangle in the triangles'
/// order, where any material has textures): (u, v) of its three vertices from `TEXCOORD_0`,
/// then from `TEXCOORD_1` (zeros where the mesh has none).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TriangleTexcoords {
    #[allow(missing_docs)] // see the struct
    pub uv: [f32; 12],
}

impl TriangleTexcoords {
    /// Set `set`'s (0 or 1) coordinates at barycentric coordinates `b` (weights of v0, v1).
    #[inline]
    pub fn at(&self, set: u32, b: Vec2) -> Vec2 {
        // Constant indices only: rust-gpu cannot index a local array by a value.
        let u = &self.uv;
        let (a, c, d) = if set == 1 {
            (Vec2::new(u[6], u[7]), Vec2::new(u[8], u[9]), Vec2::new(u[10], u[11]))
        } else {
            (Vec2::new(u[0], u[1]), Vec2::new(u[2], u[3]), Vec2::new(u[4], u[5]))
        };
        a * b.x + c * b.y + d * (1.0 - b.x - b.y)
    }
}

/// A triangle's vertex colours (glTF's `COLOR_0`, linear RGB; uploaded as it is, one per triangle
/// in the triangles' order where any material has them), which multiply the base colour where the
/// triangle's material says so ([`MaterialTextures::vertex_colors`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TriangleColors {
    /// RGB of v0, v1, v2.
    pub rgb: [f32; 9],
}

impl TriangleColors {
    /// The colour at barycentric coordinates `b` (weights of v0, v1).
    #[inline]
    pub fn at(&self, b: Vec2) -> Vec3 {
        // Constant indices only: rust-gpu cannot index a local array by a value.
        let c = &self.rgb;
        Vec3::new(c[0], c[1], c[2]) * b.x
            + Vec3::new(c[3], c[4], c[5]) * b.y
            + Vec3::new(c[6], c[7], c[8]) * (1.0 - b.x - b.y)
    }
}

/// The barycentric coordinates (b0, b1) (weights of v0 and v1, as [`Triangle::point`] takes
/// them) of `p`, projected onto the triangle's plane; the centroid's for a degenerate triangle.
#[inline]
pub fn barycentrics(tri: &Triangle, p: Vec3) -> Vec2 {
    let v0 = Vec3::from_array(tri.v0);
    let (e1, e2, w) = (Vec3::from_array(tri.v1) - v0, Vec3::from_array(tri.v2) - v0, p - v0);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (w1, w2) = (w.dot(e1), w.dot(e2));
    let det = d11 * d22 - d12 * d12;
    if !(det > 0.0) {
        return Vec2::splat(1.0 / 3.0);
    }
    let b1 = (d22 * w1 - d12 * w2) / det;
    let b2 = (d11 * w2 - d12 * w1) / det;
    Vec2::new(1.0 - b1 - b2, b1)
}

/// The material of triangle `triangle` at the point `p` on it (see the module doc).
#[inline]
pub fn material_at<R>(scene: &Scene<R>, triangle: u32, p: Vec3) -> Material {
    let tri = scene.triangles[triangle as usize];
    let m = scene.materials[tri.material as usize];
    if m.textures == 0 {
        return m;
    }
    textured(scene, m, triangle, barycentrics(&tri, p))
}

/// The geometric, shading and coat normals of triangle `triangle` at the point `p` on it: the
/// flat triangle's normal as all three where it has no vertex normals, the shading normal bent
/// by the material's normal texture and the coat's by its clearcoatNormalTexture where it has
/// them (`crate::normal_map`: in the triangle's vertex tangents where it has them, else in the
/// texture coordinates' own frame — the normal texture's, else the coat's); and an anisotropic
/// material's direction (`Material::anisotropy`) in that frame, as `Normals::anisotropy`.
#[inline]
pub fn normals_at<R>(scene: &Scene<R>, triangle: u32, p: Vec3) -> Normals {
    let tri = scene.triangles[triangle as usize];
    let ng = tri.normal();
    // No panic path (`crate::element`); a triangle beyond the buffer (a scene without normals
    // has one entry) is flat.
    let vertex = element_or(scene.normals, triangle as usize, TriangleNormals::default());
    // Stored normals are unit, so a zero first one marks a flat triangle.
    let flat = vertex.n[0] == 0.0 && vertex.n[1] == 0.0 && vertex.n[2] == 0.0;
    // The material's textures index alone (not the whole material, which the callers copy
    // once, for shading), and its textures only where it has some.
    let textures = scene.materials[tri.material as usize].textures;
    let (normal_texture, coat_texture, anisotropic) = if textures != 0 {
        let t = element_or(scene.material_textures, textures as usize, MaterialTextures::default());
        (t.normal.is_some(), t.clearcoat_normal.is_some(), t.anisotropic != 0)
    } else {
        (false, false, false)
    };
    let framed = normal_texture || coat_texture || anisotropic;
    if flat && !framed {
        return Normals::flat(ng);
    }
    let b = barycentrics(&tri, p);
    let interpolated = if flat { ng } else { vertex.at(b) };
    let n = if flat { ng } else { shading_normal(interpolated, ng) };
    if !framed {
        return Normals::shaded(ng, n);
    }
    let t = element_or(scene.material_textures, textures as usize, MaterialTextures::default());
    let coords = element_or(scene.texcoords, triangle as usize, TriangleTexcoords::default());
    // The frame's coordinates: the normal texture's (its set, its transform), else the coat's,
    // else TEXCOORD_0 as it is (an anisotropic material's without either).
    let r = if normal_texture {
        t.normal
    } else if coat_texture {
        t.clearcoat_normal
    } else {
        TextureRef::NONE
    };
    // The vertex tangents' frame, else the one of the texture coordinates' own.
    let tangents = element_or(scene.tangents, triangle as usize, TriangleTangents::default());
    // The vertex normal as interpolated (MikkTSpace's), but where vertex normals cancel, the
    // normal the shading falls back to.
    let frame_normal = if interpolated.length_squared() > 1e-12 { interpolated } else { n };
    let mut frame = TangentFrame::of_vertex_tangents(frame_normal, tangents.at(b));
    if frame.tangent == Vec3::ZERO {
        let (dp_du, dp_dv) = position_derivatives(
            &tri,
            r.coordinates(coords.at(0, Vec2::X), coords.at(1, Vec2::X)),
            r.coordinates(coords.at(0, Vec2::Y), coords.at(1, Vec2::Y)),
            r.coordinates(coords.at(0, Vec2::ZERO), coords.at(1, Vec2::ZERO)),
        );
        frame = TangentFrame::of_mapping(n, dp_du, dp_dv);
    }
    let (uv0, uv1) = (coords.at(0, b), coords.at(1, b));
    let (mut shading, mut coat) = (n, n);
    // The anisotropyTexture's red and green (read only where the material has one).
    let mut local = Vec2::ZERO;
    // One lookup in a loop over the three textures (the device module keeps one copy of it).
    let mut slot = 0;
    while slot < 3 {
        let (r, scale) = if slot == 0 {
            (t.normal, t.normal_scale)
        } else if slot == 1 {
            (t.clearcoat_normal, t.clearcoat_normal_scale)
        } else {
            (t.anisotropy, 1.0)
        };
        if r.is_some() {
            let texel = lookup(scene, r, uv0, uv1, false).truncate();
            if slot == 2 {
                local = texel.truncate();
            } else {
                let bent = shading_normal(frame.bend(texel, scale, n), ng);
                if slot == 0 {
                    shading = bent;
                } else {
                    coat = bent;
                }
            }
        }
        slot += 1;
    }
    // The anisotropy's direction in the frame (none where the triangle has no frame: its
    // lobes take any direction about the normal).
    // The frame's axes normalised first (MikkTSpace's are not, and their lengths differ), as
    // the extension's sample viewer mixes them.
    let direction = if anisotropic {
        let factor = Vec2::from_array(scene.materials[tri.material as usize].anisotropy);
        let d = if t.anisotropy.is_some() {
            anisotropy_direction(factor, local)
        } else {
            factor.normalize_or_zero()
        };
        frame.tangent.normalize_or_zero() * d.x + frame.bitangent.normalize_or_zero() * d.y
    } else {
        Vec3::ZERO
    };
    Normals { geometric: ng, shading, coat, anisotropy: direction }
}

/// The direction of an anisotropic lobe in the tangent frame (x the tangent, y the bitangent),
/// unit or zero, where the material has an anisotropyTexture: `KHR_materials_anisotropy`'s
/// direction from the texel's red and green channels `rg` (2·rg − 1, normalised) turned by
/// anisotropyRotation θ, which `factor` (`Material::anisotropy`, s·(cos θ, sin θ)) carries.
#[inline]
pub fn anisotropy_direction(factor: Vec2, rg: Vec2) -> Vec2 {
    factor.normalize_or_zero().rotate((rg * 2.0 - Vec2::ONE).normalize_or_zero())
}

/// The material of triangle `triangle` at barycentric coordinates `b` (see the module doc).
#[inline]
pub fn material_at_barycentrics<R>(scene: &Scene<R>, triangle: u32, b: Vec2) -> Material {
    let m = scene.materials[scene.triangles[triangle as usize].material as usize];
    if m.textures == 0 {
        return m;
    }
    textured(scene, m, triangle, b)
}

/// `m` with its textures applied at barycentric coordinates `b` of triangle `triangle` (on the
/// device inlined at each call, as it takes the scene's buffers: the callers look up a vertex's
/// material once, and the slots and texels are loops, to keep the copies small).
#[inline]
fn textured<R>(scene: &Scene<R>, m: Material, triangle: u32, b: Vec2) -> Material {
    // No panic path (`crate::element`): rust-gpu keeps this a function of its own.
    let t = element_or(scene.material_textures, m.textures as usize, MaterialTextures::default());
    let coords = element_or(scene.texcoords, triangle as usize, TriangleTexcoords::default());
    let (uv0, uv1) = (coords.at(0, b), coords.at(1, b));
    let mut out = m;
    // glTF's metallic and transmission at the point, mixed once after the loop.
    let (mut metallic, mut transmission) = (t.metallic, t.transmission_factor);
    // One lookup in a loop over the slots (the device module keeps one copy of it).
    let mut slot = 0;
    while slot < 11 {
        let r = if slot == 0 {
            t.base_color
        } else if slot == 1 {
            t.metallic_roughness
        } else if slot == 2 {
            t.emissive
        } else if slot == 3 {
            t.clearcoat
        } else if slot == 4 {
            t.clearcoat_roughness
        } else if slot == 5 {
            t.anisotropy
        } else if slot == 6 {
            t.specular
        } else if slot == 7 {
            t.specular_color
        } else if slot == 8 {
            t.transmission
        } else if slot == 9 {
            t.sheen_color
        } else {
            t.sheen_roughness
        };
        if r.is_some() {
            // Base colour, emission, specular colour and sheen colour are sRGB, the others linear.
            let c = lookup(scene, r, uv0, uv1, slot == 0 || slot == 2 || slot == 7 || slot == 9);
            if slot == 0 {
                out.albedo = (Vec3::from_array(m.albedo) * c.truncate()).to_array();
            } else if slot == 1 {
                let roughness = t.roughness * c.y;
                out.alpha = roughness * roughness;
                metallic = t.metallic * c.z;
            } else if slot == 2 {
                out.emission = (Vec3::from_array(m.emission) * c.truncate()).to_array();
            } else if slot == 3 {
                out.clearcoat = t.clearcoat_factor * c.x;
            } else if slot == 4 {
                let roughness = t.clearcoat_roughness_factor * c.y;
                out.clearcoat_alpha = roughness * roughness;
            } else if slot == 5 {
                // The strength's factor (the direction is `normals_at`'s).
                out.anisotropy = (Vec2::from_array(m.anisotropy) * c.z).to_array();
            } else if slot == 6 {
                out.specular = m.specular * c.w;
            } else if slot == 7 {
                out.specular_color = (Vec3::from_array(m.specular_color) * c.truncate()).to_array();
            } else if slot == 8 {
                transmission = t.transmission_factor * c.x;
            } else if slot == 9 {
                out.sheen_color = (Vec3::from_array(m.sheen_color) * c.truncate()).to_array();
            } else {
                out.sheen_roughness = m.sheen_roughness * c.w;
            }
        }
        slot += 1;
    }
    if t.metallic_roughness.is_some() || t.transmission.is_some() {
        out = out.with_metallic(metallic, transmission);
    }
    if t.vertex_colors != 0 {
        let c = element_or(scene.colors, triangle as usize, TriangleColors::default()).at(b);
        out.albedo = (Vec3::from_array(out.albedo) * c).to_array();
    }
    out
}

/// The texture `r` refers to at the mesh's coordinates `uv0`, `uv1`.
#[inline]
fn lookup<R>(scene: &Scene<R>, r: TextureRef, uv0: Vec2, uv1: Vec2, srgb: bool) -> Vec4 {
    let texture = element_or(scene.textures, r.texture as usize, Texture::default());
    sample(scene.texels, texture, r.coordinates(uv0, uv1), srgb)
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests;
