//! Subpath vertices and what tracing a candidate produced, stored SoA (slot i of candidate k
//! at `k + i·C`), with the geometry helpers every stage uses: ray origins off a surface and
//! density conversions.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use glam::Vec3;

/// Vertex kind: the pinhole.
pub const KIND_CAMERA: u32 = 0;
/// Vertex kind: a point on a light, as the origin of a light subpath.
pub const KIND_LIGHT: u32 = 1;
/// Vertex kind: a scattering surface point (which may also emit).
pub const KIND_SURFACE: u32 = 2;

/// One subpath vertex (stored SoA: slot i of candidate k at `k + i·C`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PathVertex {
    /// World-space position.
    pub p: [f32; 3],
    /// [`KIND_CAMERA`], [`KIND_LIGHT`] or [`KIND_SURFACE`].
    pub kind: u32,
    /// Geometric normal (the camera's: its view direction).
    pub n: [f32; 3],
    /// Index into the scene's materials.
    pub material: u32,
    /// Throughput of the subpath up to this vertex.
    pub beta: [f32; 3],
    /// Area density with which this vertex's own subpath generated it.
    pub pdf_fwd: f32,
    /// Area density with which the other subpath would generate it.
    pub pdf_rev: f32,
    /// Triangle slot the vertex lies on; a light vertex's light (`LightEntry::light`: a
    /// triangle, or a punctual light).
    pub triangle: u32,
    /// 1 where the subpath left this vertex by a delta lobe (a dielectric's mirror or
    /// refraction): no connection is made to it and its neighbours' densities through it are
    /// remapped in the weights.
    pub delta: u32,
    /// Padding to 64 bytes.
    pub _pad: u32,
}

impl PathVertex {
    pub(crate) fn position(&self) -> Vec3 {
        Vec3::from_array(self.p)
    }
    pub(crate) fn normal(&self) -> Vec3 {
        Vec3::from_array(self.n)
    }
    pub(crate) fn throughput(&self) -> Vec3 {
        Vec3::from_array(self.beta)
    }
}

/// What tracing a candidate produced.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PathInfo {
    /// Light subpath vertices of the technique.
    pub s: u32,
    /// Camera subpath vertices of the technique.
    pub t: u32,
    /// Camera vertices actually generated (fewer when the path left the scene).
    pub camera_vertices: u32,
    /// Light vertices actually generated (0 for s ≤ 1: s = 1 is resampled at the connection).
    pub light_vertices: u32,
    /// Pixel of the raster sample.
    pub pixel: u32,
    /// Path depth k.
    pub depth: u32,
    /// Padding to 32 bytes.
    pub _pad: [u32; 2],
}

/// Whether `v` is the environment light's vertex, at infinity: its position is only where a
/// shadow ray towards it ends, its normal the direction its light travels, and the densities of
/// reaching it are solid-angle densities (pbrt's BDPT).
#[inline]
pub fn is_at_infinity(v: &PathVertex) -> bool {
    v.kind == KIND_LIGHT && crate::light::is_environment(v.triangle)
}

/// Slot of vertex `i` of a subpath in a candidate's `max_depth + 2` slots: camera vertices
/// from the front, light vertices from the back (s + t ≤ max_depth + 2, so they never meet).
#[inline]
pub fn vertex_slot(side: u32, i: u32, max_depth: u32) -> u32 {
    if side == 0 {
        i
    } else {
        max_depth + 1 - i
    }
}

/// Slots per candidate in the vertex buffer.
#[inline]
pub fn vertex_slots(max_depth: u32) -> u32 {
    max_depth + 2
}

/// Converts a solid-angle density at `from` into an area density at `to` (with normal `n`,
/// whose cosine is used only when `to` lies on a surface).
#[inline]
pub fn convert_density(pdf: f32, from: Vec3, to: Vec3, n: Vec3, on_surface: bool) -> f32 {
    let w = to - from;
    let d2 = w.length_squared();
    if !(d2 > 0.0) {
        return 0.0;
    }
    let mut out = pdf / d2;
    if on_surface {
        out *= n.dot(w).abs() / d2.sqrt();
    }
    out
}
