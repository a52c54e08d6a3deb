//! glTF's normal texture (`normalTexture`): the shading normal bent by a texel that is a normal
//! in the surface's tangent space ([`TangentFrame::bend`]), and the tangent frame that space is.
//!
//! **The frame.** Its x axis (the tangent) runs along the texture's +u, its y axis (the
//! bitangent) up in the texture's image — towards decreasing v, as glTF's v runs down the image
//! — and its z axis is the unbent shading normal ([`TangentFrame`]). Where a triangle has
//! vertex tangents ([`TriangleTangents`]: the mesh's `TANGENT`, or MikkTSpace's, which the spec
//! asks for where a mesh has none and which the host computes), the frame is theirs and the
//! vertex normals' interpolated over the triangle, with the spec's bitangent `w · (n × t)`, as
//! MikkTSpace reconstructs it ([`TangentFrame::of_vertex_tangents`]); MikkTSpace averages each
//! vertex's tangent over the triangles that share it, which is what the tools that bake normal
//! maps (Blender among them) assume. Otherwise (a flat mesh, which has no normals to weld by)
//! the frame is the triangle's own: the tangent dp/du and the bitangent on the side of −dp/dv
//! ([`TangentFrame::of_mapping`], [`position_derivatives`]), as pbrt-v4 and Mitsuba 3 build
//! it — the same frame on a flat, evenly mapped surface.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use glam::{Vec2, Vec3, Vec4};

use crate::triangle::Triangle;

/// A triangle's vertex tangents (uploaded as it is, one per triangle in the triangles' order
/// where any triangle has them): xyz and the bitangent's sign w (±1) of its three vertices in
/// world space; all zeros where it has none (its material has no normal texture, its mesh no
/// normals, or MikkTSpace found no tangent for it), and the triangle keeps its own frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TriangleTangents {
    #[allow(missing_docs)] // see the struct
    pub t: [f32; 12],
}

impl TriangleTangents {
    /// The vertex tangents (xyz, w) interpolated at barycentric coordinates `b` (weights of v0,
    /// v1), not normalised; zero where the triangle has none.
    #[inline]
    pub fn at(&self, b: Vec2) -> Vec4 {
        let t = &self.t;
        let (a, c, d) = (
            Vec4::new(t[0], t[1], t[2], t[3]),
            Vec4::new(t[4], t[5], t[6], t[7]),
            Vec4::new(t[8], t[9], t[10], t[11]),
        );
        a * b.x + c * b.y + d * (1.0 - b.x - b.y)
    }
}

/// The derivatives dp/du and dp/dv of the points of `tri` over texture coordinates that are
/// `uv0`, `uv1`, `uv2` at its vertices (the plane's affine map, inverted); zero where the
/// coordinates span no area.
#[inline]
pub fn position_derivatives(tri: &Triangle, uv0: Vec2, uv1: Vec2, uv2: Vec2) -> (Vec3, Vec3) {
    let v0 = Vec3::from_array(tri.v0);
    let (e1, e2) = (Vec3::from_array(tri.v1) - v0, Vec3::from_array(tri.v2) - v0);
    let (d1, d2) = (uv1 - uv0, uv2 - uv0);
    let det = d1.x * d2.y - d2.x * d1.y;
    if !(det.abs() > 0.0) || !det.is_finite() {
        return (Vec3::ZERO, Vec3::ZERO);
    }
    ((e1 * d2.y - e2 * d1.y) / det, (e2 * d1.x - e1 * d2.x) / det)
}

/// The frame a normal texture's texel is a direction in ([`TangentFrame::bend`]): tangent
/// (the texel's x), bitangent (its y) and normal (its z). No frame where the tangent is zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentFrame {
    #[allow(missing_docs)] // see the struct
    pub tangent: Vec3,
    #[allow(missing_docs)]
    pub bitangent: Vec3,
    #[allow(missing_docs)]
    pub normal: Vec3,
}

impl TangentFrame {
    /// No frame: the normal stays as it is.
    pub const NONE: Self = Self { tangent: Vec3::ZERO, bitangent: Vec3::ZERO, normal: Vec3::ZERO };

    /// The frame of vertex tangents as MikkTSpace reconstructs it where it is sampled: the
    /// interpolated tangent `t` (xyz; w the bitangent's sign), the interpolated vertex normal
    /// `n` and the bitangent `w · (n × t)`, none of them normalised or made orthogonal —
    /// MikkTSpace's condition for a texel to turn back into the normal a baker saw (its
    /// header: "the normal map sampler must likewise use the interpolated and 'unnormalized'
    /// tangent, bitangent and vertex normal"); the spec's bitangent. No frame where `t` is
    /// zero (the triangle has no vertex tangents).
    #[inline]
    pub fn of_vertex_tangents(n: Vec3, t: Vec4) -> Self {
        let tangent = t.truncate();
        if !(tangent.length_squared() > 0.0) || !tangent.is_finite() {
            return Self::NONE;
        }
        let sign = if t.w < 0.0 { -1.0 } else { 1.0 };
        Self { tangent, bitangent: n.cross(tangent) * sign, normal: n }
    }

    /// The orthonormal frame of a triangle's own mapping at unit normal `n`: the tangent
    /// dp/du made orthogonal to `n`, the bitangent ±n × tangent on the side of −dp/dv (up the
    /// image, as glTF's v runs down it). No frame where dp/du has no direction off `n`.
    #[inline]
    pub fn of_mapping(n: Vec3, dp_du: Vec3, dp_dv: Vec3) -> Self {
        let along = dp_du - n * n.dot(dp_du);
        let len2 = along.length_squared();
        if !(len2 > 0.0) || !len2.is_finite() {
            return Self::NONE;
        }
        let t = along / len2.sqrt();
        let cross = n.cross(t);
        Self { tangent: t, bitangent: if cross.dot(dp_dv) > 0.0 { -cross } else { cross }, normal: n }
    }

    /// glTF's normal texture: the normal that `texel` (linear rgb in [0, 1]) says in this
    /// frame, (2 rgb − 1) with x and y times `scale` (the spec's `scaledNormal`),
    /// normalised; `unbent` where there is no frame or the texel gives no direction.
    #[inline]
    pub fn bend(&self, texel: Vec3, scale: f32, unbent: Vec3) -> Vec3 {
        let m = texel * 2.0 - Vec3::ONE;
        let bent = self.tangent * (m.x * scale) + self.bitangent * (m.y * scale) + self.normal * m.z;
        let len2 = bent.length_squared();
        if self.tangent == Vec3::ZERO || !(len2 > 0.0) || !len2.is_finite() {
            return unbent;
        }
        bent / len2.sqrt()
    }
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests;
