//! Textures as glTF 2.0 defines them, looked up the same way by the kernels and the CPU backend:
//! every texel of every texture in one storage buffer (no sampled images, so that the CPU
//! backend runs the same body), read with the texture's sampler.
//!
//! **Texels** (`texels`): RGBA8, one `u32` a texel (red in the low byte), row after row from the
//! image's top, each texture from its [`Texture::offset`]. Colour textures (base colour,
//! emission) hold sRGB-encoded values, decoded to linear per texel before filtering
//! ([`srgb_to_linear`]); data textures (metallic-roughness) are linear.
//!
//! **Coordinates**: glTF's, (0, 0) the image's top-left corner, u to the right, v down; texel
//! (x, y) covers [x/w, (x+1)/w] × [y/h, (y+1)/h]. A texture reference ([`TextureRef`]) picks the
//! mesh's `TEXCOORD_0` or `TEXCOORD_1` and transforms it by `KHR_texture_transform`
//! ([`texture_transform`]) before the lookup.
//!
//! **Sampler**: the wrap modes of glTF (REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT) per axis, and
//! the magnification filter: NEAREST, or bilinear (LINEAR, glTF's default) between the four
//! texels around the point. No mip-maps: a path tracer's samples over a pixel average the
//! magnified texture over the pixel's footprint, which is what a minification filter
//! approximates — the image converges to the pixel-filtered texture, aliasing included only
//! as noise.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use glam::{Vec2, Vec3, Vec4};

use crate::element::element_or;

/// No texture ([`TextureRef::texture`]).
pub const NONE: u32 = u32::MAX;

/// Wrap mode: REPEAT (glTF 10497).
pub const WRAP_REPEAT: u32 = 0;
/// Wrap mode: CLAMP_TO_EDGE (glTF 33071).
pub const WRAP_CLAMP: u32 = 1;
/// Wrap mode: MIRRORED_REPEAT (glTF 33648).
pub const WRAP_MIRROR: u32 = 2;

/// One texture: where its texels are and how they are sampled (uploaded as it is).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Texture {
    /// Index of its first texel in the texel buffer.
    pub offset: u32,
    #[allow(missing_docs)] // in texels
    pub width: u32,
    #[allow(missing_docs)] // in texels
    pub height: u32,
    /// The sampler ([`Texture::sampler`]): wrap S in bits 0–1, wrap T in bits 2–3, bit 4 set
    /// for NEAREST magnification.
    pub sampler: u32,
}

impl Texture {
    /// The packed sampler of wrap modes `wrap_s`, `wrap_t` (`WRAP_*`) and the filter.
    pub const fn sampler(wrap_s: u32, wrap_t: u32, nearest: bool) -> u32 {
        wrap_s | (wrap_t << 2) | if nearest { 16 } else { 0 }
    }
}

/// A material's use of a texture: which, with which texture coordinates, transformed how
/// (uploaded as it is).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TextureRef {
    /// Index into the scene's textures, or [`NONE`].
    pub texture: u32,
    /// 0 for `TEXCOORD_0`, 1 for `TEXCOORD_1`.
    pub tex_coord: u32,
    /// The affine map of the texture coordinates, (a, b, c, d, e, f): u' = a u + c v + e,
    /// v' = b u + d v + f (columns of a 2 × 3 matrix).
    pub transform: [f32; 6],
}

impl TextureRef {
    /// No texture.
    pub const NONE: TextureRef = TextureRef { texture: NONE, tex_coord: 0, transform: IDENTITY };

    /// Whether a texture is referenced.
    #[inline]
    pub fn is_some(&self) -> bool {
        self.texture != NONE
    }

    /// The texture coordinates the lookup uses for the mesh's coordinates `uv0`, `uv1`.
    #[inline]
    pub fn coordinates(&self, uv0: Vec2, uv1: Vec2) -> Vec2 {
        let uv = if self.tex_coord == 1 { uv1 } else { uv0 };
        let m = self.transform;
        Vec2::new(m[0] * uv.x + m[2] * uv.y + m[4], m[1] * uv.x + m[3] * uv.y + m[5])
    }
}

impl Default for TextureRef {
    fn default() -> Self {
        Self::NONE
    }
}

/// The identity transform of texture coordinates.
pub const IDENTITY: [f32; 6] = [1.0, 0.0, 0.0, 1.0, 0.0, 0.0];

/// `KHR_texture_transform`'s matrix T · R · S as a [`TextureRef::transform`]: scale by `scale`,
/// rotate by `rotation` radians counter-clockwise in glTF's UV space (u right, v down), then
/// offset by `offset`. R's columns are (cos, −sin) and (sin, cos): u' = cos u + sin v,
/// v' = −sin u + cos v — as the extension's sample model (TextureTransformTest), Blender's
/// importer and exporter, Babylon.js and three.js rotate, and as KhronosGroup/glTF#1563 shows;
/// the GLSL listing in the extension's README has the transposed matrix, which turns the other
/// way on every file those tools write.
pub fn texture_transform(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> [f32; 6] {
    let (s, c) = rotation.sin_cos();
    [c * scale[0], -s * scale[0], s * scale[1], c * scale[1], offset[0], offset[1]]
}

/// A texel channel value's sRGB encoding decoded to linear (IEC 61966-2-1).
#[inline]
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Texel `packed` (RGBA8, red in the low byte) as four values in [0, 1], its colour decoded
/// from sRGB when `srgb`.
#[inline]
pub fn unpack(packed: u32, srgb: bool) -> Vec4 {
    let channel = |k: u32| ((packed >> (8 * k)) & 255) as f32 / 255.0;
    let (r, g, b) = (channel(0), channel(1), channel(2));
    let rgb = if srgb {
        Vec3::new(srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b))
    } else {
        Vec3::new(r, g, b)
    };
    rgb.extend(channel(3))
}

/// Integer texel coordinate `i` wrapped into [0, n) by `mode`, for `i` within one period of the
/// mode around [0, n) (−n ≤ i < 2n for REPEAT, −2n ≤ i < 4n for MIRRORED_REPEAT; any for
/// CLAMP_TO_EDGE), which [`sample`]'s reduced coordinates keep it to. No integer division: its
/// panic path on a zero divisor would make rust-gpu inline every caller.
#[inline]
pub fn wrap(i: i32, n: i32, mode: u32) -> i32 {
    if mode == WRAP_CLAMP {
        i.max(0).min(n - 1)
    } else if mode == WRAP_MIRROR {
        let mut m = if i < 0 { i + 2 * n } else { i };
        if m >= 2 * n {
            m -= 2 * n;
        }
        if m >= n {
            2 * n - 1 - m
        } else {
            m
        }
    } else {
        let m = if i < 0 { i + n } else { i };
        if m >= n {
            m - n
        } else {
            m
        }
    }
}

/// Coordinate `u` reduced to one period of `mode` (so that the texel coordinates stay small
/// integers); a coordinate that is not finite reads as 0.
#[inline]
fn reduce(u: f32, mode: u32) -> f32 {
    let u = if u.abs() < 1e30 { u } else { 0.0 };
    if mode == WRAP_CLAMP {
        crate::float::clamp(u, 0.0, 1.0)
    } else if mode == WRAP_MIRROR {
        u - 2.0 * (u * 0.5).floor()
    } else {
        u - u.floor()
    }
}

/// The texture's value at texture coordinates `uv` (RGBA, colour decoded from sRGB when
/// `srgb`), filtered and wrapped by its sampler.
#[inline]
pub fn sample(texels: &[u32], tex: Texture, uv: Vec2, srgb: bool) -> Vec4 {
    let (wrap_s, wrap_t) = (tex.sampler & 3, (tex.sampler >> 2) & 3);
    let x = reduce(uv.x, wrap_s) * tex.width as f32;
    let y = reduce(uv.y, wrap_t) * tex.height as f32;
    let nearest = tex.sampler & 16 != 0;
    // NEAREST: the texel under the point; bilinear: the four texel centres around it, weighted
    // by the distances (one loop rather than four calls: the device module keeps one copy).
    let (x, y) = if nearest { (x, y) } else { (x - 0.5, y - 0.5) };
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = if nearest { (0.0, 0.0) } else { (x - x0, y - y0) };
    let (i, j) = (x0 as i32, y0 as i32);
    let corners = if nearest { 1 } else { 4 };
    let mut sum = Vec4::ZERO;
    let mut c = 0;
    while c < corners {
        let (di, dj) = (c & 1, c >> 1);
        let wx = if di == 1 { fx } else { 1.0 - fx };
        let wy = if dj == 1 { fy } else { 1.0 - fy };
        sum += fetch(texels, tex, i + di, j + dj, srgb) * (wx * wy);
        c += 1;
    }
    sum
}

/// Texel (i, j) of `tex`, wrapped by its sampler ([`wrap`]'s ranges) and unpacked (0 beyond
/// the buffer, which a loaded texture never reaches; [`element_or`]).
#[inline]
fn fetch(texels: &[u32], tex: Texture, i: i32, j: i32, srgb: bool) -> Vec4 {
    let (w, h) = (tex.width as i32, tex.height as i32);
    let (i, j) = (wrap(i, w, tex.sampler & 3), wrap(j, h, (tex.sampler >> 2) & 3));
    let at = (tex.offset + (j * w + i) as u32) as usize;
    unpack(element_or(texels, at, 0), srgb)
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests;
