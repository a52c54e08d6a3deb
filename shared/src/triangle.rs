//! The scene's triangles: what shading and light sampling read, and the ray–triangle test
//! every ray caster uses, so that all of them answer a query the same way.

use glam::Vec3;

/// "No hit" distance (finite: naga rejects infinite literals).
pub const NO_HIT: f32 = 3.0e38;

/// A triangle with what shading and light sampling need (uploaded to the device as it is).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Triangle {
    /// First vertex (world space).
    pub v0: [f32; 3],
    /// Index into the scene's materials.
    pub material: u32,
    #[allow(missing_docs)] // the second vertex
    pub v1: [f32; 3],
    /// Area density of this triangle's points under light sampling (pick / area); 0 if the
    /// triangle does not emit.
    pub light_area_pdf: f32,
    #[allow(missing_docs)] // the third vertex
    pub v2: [f32; 3],
    #[allow(missing_docs)] // in the scene's units squared
    pub area: f32,
}

impl Triangle {
    /// Unit geometric normal, along (v1 − v0) × (v2 − v0); zero for a degenerate triangle.
    #[inline]
    pub fn normal(&self) -> Vec3 {
        let (a, b, c) = (Vec3::from_array(self.v0), Vec3::from_array(self.v1), Vec3::from_array(self.v2));
        (b - a).cross(c - a).normalize_or_zero()
    }

    /// The point with barycentric coordinates (b0, b1) (weights of v0 and v1).
    #[inline]
    pub fn point(&self, b0: f32, b1: f32) -> Vec3 {
        Vec3::from_array(self.v0) * b0
            + Vec3::from_array(self.v1) * b1
            + Vec3::from_array(self.v2) * (1.0 - b0 - b1)
    }
}

/// A triangle as the ray test reads it: a vertex and the two edges from it. Casters that keep
/// these precomputed (the CPU backend's) answer exactly as [`intersect_triangle`]: the edges
/// are the same f32 differences it computes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriangleEdges {
    /// The first vertex.
    pub v0: Vec3,
    /// v1 − v0.
    pub e1: Vec3,
    /// v2 − v0.
    pub e2: Vec3,
}

impl TriangleEdges {
    /// The edges of `tri`.
    #[inline]
    pub fn of(tri: &Triangle) -> Self {
        let v0 = Vec3::from_array(tri.v0);
        Self { v0, e1: Vec3::from_array(tri.v1) - v0, e2: Vec3::from_array(tri.v2) - v0 }
    }

    /// Möller–Trumbore: the distance in (tmin, tmax) at which the ray hits the triangle, or
    /// [`NO_HIT`]. Both faces are hit; degenerate triangles never are; NaN is never a hit.
    #[allow(clippy::manual_range_contains)] // explicit comparisons reject NaN on the device too
    #[inline]
    pub fn intersect(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> f32 {
        let pvec = d.cross(self.e2);
        let det = self.e1.dot(pvec);
        if !(det.abs() > 0.0) {
            return NO_HIT;
        }
        let inv = 1.0 / det;
        let tvec = o - self.v0;
        let u = tvec.dot(pvec) * inv;
        if !(u >= 0.0 && u <= 1.0) {
            return NO_HIT;
        }
        let qvec = tvec.cross(self.e1);
        let v = d.dot(qvec) * inv;
        if !(v >= 0.0 && u + v <= 1.0) {
            return NO_HIT;
        }
        let t = self.e2.dot(qvec) * inv;
        if t > tmin && t < tmax {
            t
        } else {
            NO_HIT
        }
    }
}

/// The distance in (tmin, tmax) at which the ray hits `tri`, or [`NO_HIT`]
/// ([`TriangleEdges::intersect`]).
#[inline]
pub fn intersect_triangle(tri: &Triangle, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> f32 {
    TriangleEdges::of(tri).intersect(o, d, tmin, tmax)
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    fn tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Triangle {
        Triangle { v0: a, v1: b, v2: c, ..Default::default() }
    }

    #[test]
    fn hits_inside_and_misses_outside() {
        let t = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let d = Vec3::new(0.0, 0.0, -1.0);
        assert_eq!(intersect_triangle(&t, Vec3::new(0.25, 0.25, 2.0), d, 0.0, NO_HIT), 2.0);
        assert_eq!(intersect_triangle(&t, Vec3::new(0.25, 0.25, -2.0), -d, 0.0, NO_HIT), 2.0, "back face");
        assert_eq!(intersect_triangle(&t, Vec3::new(0.75, 0.75, 2.0), d, 0.0, NO_HIT), NO_HIT);
        assert_eq!(intersect_triangle(&t, Vec3::new(0.25, 0.25, 2.0), d, 0.0, 1.5), NO_HIT, "beyond tmax");
        assert_eq!(intersect_triangle(&t, Vec3::new(0.25, 0.25, 2.0), d, 2.5, NO_HIT), NO_HIT, "before tmin");
        let nan = Vec3::new(f32::NAN, 0.0, -1.0);
        assert_eq!(intersect_triangle(&t, Vec3::new(0.25, 0.25, 2.0), nan, 0.0, NO_HIT), NO_HIT, "NaN");
        assert_eq!(t.normal(), Vec3::Z);
    }

    #[test]
    fn degenerate_triangles_are_never_hit() {
        let line = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]);
        let point = tri([1.0, 1.0, 1.0], [1.0, 1.0, 1.0], [1.0, 1.0, 1.0]);
        for (o, d) in [
            (Vec3::new(1.0, 0.0, 1.0), Vec3::new(0.0, 0.0, -1.0)),
            (Vec3::new(1.0, 1.0, 2.0), Vec3::new(0.0, 0.0, -1.0)),
            (Vec3::new(-1.0, 0.0, 0.0), Vec3::X),
        ] {
            assert_eq!(intersect_triangle(&line, o, d, 0.0, NO_HIT), NO_HIT);
            assert_eq!(intersect_triangle(&point, o, d, 0.0, NO_HIT), NO_HIT);
        }
        assert_eq!(line.normal(), Vec3::ZERO);
    }
}
