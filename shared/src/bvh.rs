//! Ray traversal of a binary BVH built on the host by obvhs (its `Bvh2` node layout: an inner
//! node's children are the two consecutive nodes at `first`; a leaf holds `count` triangles
//! from slot `first`, the triangles being stored in BVH order), and the ray–triangle test.
//!
//! Robustness: the slab test uses a safe reciprocal (±1e30 for a zero direction component)
//! so an axis-parallel ray never computes 0·∞; a triangle whose edges are parallel (zero
//! area) is never hit; NaN distances never compare as hits.

use glam::Vec3;

/// "No hit" distance (finite: naga rejects infinite literals).
pub const NO_HIT: f32 = 3.0e38;
/// Depth of the traversal stack; the host refuses BVHs deeper than this.
pub const BVH_STACK_SIZE: usize = 64;

/// A BVH node (uploaded to the device as it is).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BvhNode {
    /// Lower corner of the box.
    pub min: [f32; 3],
    /// Number of triangles of a leaf; 0 for an inner node.
    pub count: u32,
    /// Upper corner of the box.
    pub max: [f32; 3],
    /// Inner node: index of the first child (the second follows it). Leaf: first triangle slot.
    pub first: u32,
}

/// A triangle with what shading and light sampling need (uploaded to the device as it is).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Triangle {
    /// First vertex (world space).
    pub v0: [f32; 3],
    /// Material index.
    pub material: u32,
    /// Second vertex.
    pub v1: [f32; 3],
    /// Area density of this triangle's points under light sampling (pick / area); 0 if the
    /// triangle does not emit.
    pub light_area_pdf: f32,
    /// Third vertex.
    pub v2: [f32; 3],
    /// Area.
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

/// The closest hit of a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the (unit) direction, or [`NO_HIT`].
    pub t: f32,
    /// Triangle slot.
    pub triangle: u32,
}

impl Hit {
    /// Whether the ray hit anything.
    #[inline]
    pub fn found(&self) -> bool {
        self.t < NO_HIT
    }
}

/// Möller–Trumbore: the distance in (tmin, tmax) at which the ray hits the triangle, or
/// [`NO_HIT`]. Both faces are hit; degenerate triangles never are.
#[allow(clippy::manual_range_contains)] // explicit comparisons reject NaN on the device too
#[inline]
pub fn intersect_triangle(tri: &Triangle, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> f32 {
    let v0 = Vec3::from_array(tri.v0);
    let e1 = Vec3::from_array(tri.v1) - v0;
    let e2 = Vec3::from_array(tri.v2) - v0;
    let pvec = d.cross(e2);
    let det = e1.dot(pvec);
    if !(det.abs() > 0.0) {
        return NO_HIT;
    }
    let inv = 1.0 / det;
    let tvec = o - v0;
    let u = tvec.dot(pvec) * inv;
    if !(u >= 0.0 && u <= 1.0) {
        return NO_HIT;
    }
    let qvec = tvec.cross(e1);
    let v = d.dot(qvec) * inv;
    if !(v >= 0.0 && u + v <= 1.0) {
        return NO_HIT;
    }
    let t = e2.dot(qvec) * inv;
    if t > tmin && t < tmax {
        t
    } else {
        NO_HIT
    }
}

/// 1/x, or ±1e30 (with the sign of x, zeros included) when |x| is below 1e-30.
#[inline]
pub fn safe_reciprocal(x: f32) -> f32 {
    if x.abs() < 1e-30 {
        if x.to_bits() >> 31 == 0 {
            1e30
        } else {
            -1e30
        }
    } else {
        1.0 / x
    }
}

/// Entry distance of the ray into a node's box, or [`NO_HIT`] when it misses within tmax.
#[inline]
fn slab(node: &BvhNode, o: Vec3, inv: Vec3, tmax: f32) -> f32 {
    let t0 = (Vec3::from_array(node.min) - o) * inv;
    let t1 = (Vec3::from_array(node.max) - o) * inv;
    let near = t0.min(t1).max_element().max(0.0);
    let far = t0.max(t1).min_element().min(tmax);
    if near <= far {
        near
    } else {
        NO_HIT
    }
}

/// Traverses the BVH; with `any` it stops at the first hit (shadow rays).
#[inline]
fn traverse(nodes: &[BvhNode], tris: &[Triangle], o: Vec3, d: Vec3, tmin: f32, tmax: f32, any: bool) -> Hit {
    let mut best = Hit { t: NO_HIT, triangle: 0 };
    let mut t_limit = tmax;
    let inv = Vec3::new(safe_reciprocal(d.x), safe_reciprocal(d.y), safe_reciprocal(d.z));
    let root = nodes[0];
    if slab(&root, o, inv, t_limit) >= NO_HIT {
        return best;
    }
    let mut stack = [0u32; BVH_STACK_SIZE];
    let mut sp = 0usize;
    // Work items are nodes to visit; the root may itself be a leaf.
    let mut current = 0u32;
    let mut have = true;
    while have {
        let node = nodes[current as usize];
        if node.count > 0 {
            let mut i = node.first;
            while i < node.first + node.count {
                let t = intersect_triangle(&tris[i as usize], o, d, tmin, t_limit);
                if t < t_limit {
                    t_limit = t;
                    best = Hit { t, triangle: i };
                    if any {
                        return best;
                    }
                }
                i += 1;
            }
            have = false;
        } else {
            let left = node.first;
            let right = node.first + 1;
            let tl = slab(&nodes[left as usize], o, inv, t_limit);
            let tr = slab(&nodes[right as usize], o, inv, t_limit);
            let hit_l = tl < NO_HIT;
            let hit_r = tr < NO_HIT;
            if hit_l && hit_r {
                let (near, far) = if tl <= tr { (left, right) } else { (right, left) };
                if sp < BVH_STACK_SIZE {
                    stack[sp] = far;
                    sp += 1;
                }
                current = near;
                continue;
            } else if hit_l {
                current = left;
                continue;
            } else if hit_r {
                current = right;
                continue;
            }
            have = false;
        }
        // Pop the next node whose box the ray still reaches.
        while !have && sp > 0 {
            sp -= 1;
            let next = stack[sp];
            if slab(&nodes[next as usize], o, inv, t_limit) < NO_HIT {
                current = next;
                have = true;
            }
        }
    }
    best
}

/// The closest triangle the ray (unit direction `d`) hits in (tmin, tmax).
#[inline]
pub fn closest_hit(nodes: &[BvhNode], tris: &[Triangle], o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Hit {
    #[cfg(not(target_arch = "spirv"))]
    crate::rays::record(crate::rays::Ray::new(crate::rays::RAY_CLOSEST, o, d, tmin, tmax));
    traverse(nodes, tris, o, d, tmin, tmax, false)
}

/// Whether anything blocks the ray in (tmin, tmax).
#[inline]
pub fn occluded(nodes: &[BvhNode], tris: &[Triangle], o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> bool {
    #[cfg(not(target_arch = "spirv"))]
    crate::rays::record(crate::rays::Ray::new(crate::rays::RAY_OCCLUSION, o, d, tmin, tmax));
    traverse(nodes, tris, o, d, tmin, tmax, true).found()
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

    /// Axis-parallel rays, zero components of both signs: the slab test stays NaN-free, rays
    /// grazing a box face count as hits, rays outside the slab as misses.
    #[test]
    fn slab_test_with_zero_direction_components() {
        let node = BvhNode { min: [0.0; 3], count: 1, max: [1.0; 3], first: 0 };
        let cases = [
            (Vec3::new(0.5, 0.5, -1.0), Vec3::new(0.0, 0.0, 1.0), true),
            (Vec3::new(0.5, 0.5, -1.0), Vec3::new(-0.0, 0.0, 1.0), true),
            (Vec3::new(1.5, 0.5, -1.0), Vec3::new(0.0, 0.0, 1.0), false),
            (Vec3::new(0.0, 0.5, -1.0), Vec3::new(0.0, -0.0, 1.0), true), // on the x = 0 face
            (Vec3::new(0.5, 2.0, 0.5), Vec3::new(0.0, -1.0, 0.0), true),
            (Vec3::new(0.5, 2.0, 0.5), Vec3::new(0.0, 1.0, 0.0), false), // pointing away
        ];
        for (o, d, expect) in cases {
            let inv = Vec3::new(safe_reciprocal(d.x), safe_reciprocal(d.y), safe_reciprocal(d.z));
            let t = slab(&node, o, inv, NO_HIT);
            assert!(!t.is_nan());
            assert_eq!(t < NO_HIT, expect, "o {o} d {d}: {t}");
        }
    }
}
