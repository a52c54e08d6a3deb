//! Cut-outs: glTF 2.0's `alphaMode` MASK and BLEND, decided in the ray casters, so that a ray
//! passes through the cut-away part of a triangle as if it were not there — in every query,
//! closest-hit and occlusion alike, on the device and on the CPU backend.
//!
//! A triangle's **opacity** at a point is glTF's: `baseColorFactor`'s alpha times
//! `baseColorTexture`'s alpha (linear; the texture's colour is sRGB, its alpha is not) at the
//! point's texture coordinates ([`Cutouts::opacity`]). What it does with it:
//! - OPAQUE (the default): nothing; the triangle stops every ray that hits it.
//! - MASK: the triangle stops a ray where its opacity is at least `alphaCutoff` (0.5 by
//!   default), and is absent elsewhere — a leaf's silhouette.
//! - BLEND: the triangle stops a ray with probability equal to its opacity (stochastic
//!   opacity: a surface of coverage α, seen through where it is not). In expectation a ray
//!   meets α of the surface and passes (1 − α) of the time, which is the coverage BLEND means,
//!   and the estimate stays unbiased. The number that decides is a hash of the ray's **key** and
//!   the triangle ([`blend_draw`]). The key is a hash of the two uniforms that chose the ray's
//!   direction ([`blend_key`]), so a path stays a function of its random numbers (a Metropolis
//!   chain re-traces a path and meets the same decisions) and every caster, on the device and
//!   on the CPU, decides alike. pbrt-v4 hashes the ray's origin and direction instead; those
//!   differ by an ulp between casters whose triangle tests round differently, and a draw
//!   hashed from them flips, so the device and the CPU backend part ways on BLEND scenes. The
//!   triangle is hashed too, so two BLEND layers along one ray decide independently.
//!
//! Emitters are never cut out (the loader makes an emissive cut-out opaque, with a warning):
//! light sampling picks points on an emitter's whole surface.

use glam::{Vec2, Vec3};

use crate::bsdf::Material;
use crate::element::element_or;
use crate::rng::{pcg4d, unit_f32};
use crate::surface::{barycentrics, MaterialTextures, TriangleTexcoords};
use crate::texture::{sample, Texture};
use crate::triangle::Triangle;

/// `alphaMode` OPAQUE ([`MaterialTextures::alpha_mode`]).
pub const ALPHA_OPAQUE: u32 = 0;
/// `alphaMode` MASK.
pub const ALPHA_MASK: u32 = 1;
/// `alphaMode` BLEND.
pub const ALPHA_BLEND: u32 = 2;

/// What a ray caster reads to decide whether a triangle it hits stops the ray: the scene's
/// triangles, materials and their textures (the same buffers shading reads).
#[derive(Clone, Copy)]
pub struct Cutouts<'a> {
    /// The triangles, indexed by the caster's slots.
    pub triangles: &'a [Triangle],
    #[allow(missing_docs)] // indexed by Triangle::material
    pub materials: &'a [Material],
    /// Indexed by `Material::textures`; entry 0 is unused, so a scene whose list holds only it
    /// has no textures and no cut-outs.
    pub material_textures: &'a [MaterialTextures],
    /// Per triangle slot, where any material has textures.
    pub texcoords: &'a [TriangleTexcoords],
    #[allow(missing_docs)] // indexed by TextureRef::texture
    pub textures: &'a [Texture],
    /// Every texture's texels.
    pub texels: &'a [u32],
}

impl Cutouts<'_> {
    /// No cut-outs: every triangle stops every ray (a caster over bare triangles).
    #[cfg(not(target_arch = "spirv"))]
    pub const NONE: Cutouts<'static> = Cutouts {
        triangles: &[],
        materials: &[],
        material_textures: &[],
        texcoords: &[],
        textures: &[],
        texels: &[],
    };

    /// Whether any material can be a cut-out (only materials with a textures entry can).
    #[inline]
    pub fn any(&self) -> bool {
        self.material_textures.len() > 1
    }

    /// The textures entry of triangle `slot`'s material where its `alphaMode` is MASK or
    /// BLEND; an OPAQUE entry ([`ALPHA_OPAQUE`]) otherwise. (A value rather than an `Option`,
    /// which rust-gpu does not lower cleanly.)
    #[inline]
    pub fn of(&self, slot: u32) -> MaterialTextures {
        let opaque = MaterialTextures::default();
        if !self.any() {
            return opaque;
        }
        let tri = element_or(self.triangles, slot as usize, Triangle::default());
        let textures = element_or(self.materials, tri.material as usize, Material::default()).textures;
        if textures == 0 {
            return opaque;
        }
        element_or(self.material_textures, textures as usize, opaque)
    }

    /// Whether triangle `slot` can let a ray through (its material is MASK or BLEND).
    #[inline]
    pub fn is_cutout(&self, slot: u32) -> bool {
        self.of(slot).alpha_mode != ALPHA_OPAQUE
    }

    /// Whether triangle `slot`, hit at distance `t` by the ray (`o`, `d`) whose draws are
    /// keyed by `key` ([`blend_key`]), stops it.
    #[inline]
    pub fn stops(&self, slot: u32, o: Vec3, d: Vec3, t: f32, key: u32) -> bool {
        let m = self.of(slot);
        if m.alpha_mode == ALPHA_OPAQUE {
            return true;
        }
        let alpha = self.opacity(slot, &m, o + d * t);
        if m.alpha_mode == ALPHA_MASK {
            alpha >= m.alpha_cutoff
        } else {
            blend_draw(key, slot) < alpha
        }
    }

    /// The opacity of triangle `slot` (material textures `m`) at the point `p` on it:
    /// `baseColorFactor`'s alpha × `baseColorTexture`'s alpha there.
    #[inline]
    pub fn opacity(&self, slot: u32, m: &MaterialTextures, p: Vec3) -> f32 {
        let r = m.base_color;
        if !r.is_some() {
            return m.alpha;
        }
        let tri = element_or(self.triangles, slot as usize, Triangle::default());
        let b: Vec2 = barycentrics(&tri, p);
        let coords = element_or(self.texcoords, slot as usize, TriangleTexcoords::default());
        let texture = element_or(self.textures, r.texture as usize, Texture::default());
        let uv = r.coordinates(coords.at(0, b), coords.at(1, b));
        m.alpha * sample(self.texels, texture, uv, false).w
    }
}

/// The key of a ray's BLEND draws: a hash of the two uniforms `u` that chose its direction
/// (a camera ray's raster position, a BSDF sample's, a light sample's point). The uniforms are
/// bit for bit the same on every backend, where the ray they give is not.
#[inline]
pub fn blend_key(u: Vec2) -> u32 {
    pcg4d([u.x.to_bits(), u.y.to_bits(), 0x2545_f491, 0x9e37_79b9])[0]
}

/// The uniform number in [0, 1) that decides whether BLEND triangle `slot` stops a ray whose
/// draws are keyed by `key`.
#[inline]
pub fn blend_draw(key: u32, slot: u32) -> f32 {
    unit_f32(pcg4d([key, slot, 0x85eb_ca6b, 0xc2b2_ae35])[0])
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests;
