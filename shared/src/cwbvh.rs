//! Ray traversal of a compressed 8-wide BVH (CWBVH: Ylitie, Karras and Laine, "Efficient
//! Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", HPG 2017) in the node format
//! obvhs builds, so the host uploads obvhs's nodes as they are: every node holds its eight
//! children's boxes quantised to bytes on a per-node grid, which child slots are inner nodes,
//! and where their nodes and triangles start. The triangles are stored in the BVH's order, so a
//! leaf's triangles are consecutive slots.
//!
//! Traversal keeps a "node group" (the base index of a node's children and a mask of the hit
//! ones, ordered front to back for the ray's octant) and a "triangle group" (the hit leaves'
//! triangles as bits), as the paper's Algorithm 1; a stack holds the groups still to visit.
//!
//! Robustness: the box test uses a safe reciprocal (±1e30 for a zero direction component), so
//! an axis-parallel ray never computes 0·∞; the quantised boxes enclose the exact ones (obvhs
//! rounds them outwards); the triangle test is [`intersect_triangle`] with its (tmin, tmax)
//! interval, both faces, degenerate triangles never hit and NaN never a hit. A hit on a cut-out
//! triangle counts only where [`Cutouts::stops`] says it stops the ray.

use glam::Vec3;

use crate::cutout::Cutouts;
use crate::ray_caster::{Hit, RayCaster};
use crate::triangle::{intersect_triangle, Triangle};

/// Depth of the traversal stack (one entry a level at most); the host refuses deeper BVHs.
pub const WIDE_BVH_STACK_SIZE: usize = 32;

/// A CWBVH node: 80 bytes, byte for byte obvhs's `CwBvhNode` (its byte arrays read as
/// little-endian words here, since SPIR-V storage buffers hold no bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct WideNode {
    /// Origin of the node's quantisation grid (the lower corner of its box).
    pub origin: [f32; 3],
    /// Bytes 0–2: the grid's spacing on each axis as a biased exponent (spacing =
    /// 2^(byte − 127)); byte 3: a bit for each child slot that holds an inner node.
    pub exponents_imask: u32,
    /// Index of the first child node; the inner children follow it in slot order.
    pub child_base: u32,
    /// Slot of the first triangle of this node's leaves.
    pub triangle_base: u32,
    /// One byte a child slot: 0 when empty; an inner node: 0b001 then slot + 24 in five bits;
    /// a leaf: its triangle count in unary in the high three bits, then the offset of its
    /// first triangle from `triangle_base`.
    pub meta: [u32; 2],
    /// The children's boxes on the grid, one byte a child, two words each of: min x, max x,
    /// min y, max y, min z, max z.
    pub bounds: [u32; 12],
}

impl WideNode {
    /// The grid's spacing on `axis`.
    #[inline]
    fn spacing(&self, axis: u32) -> f32 {
        f32::from_bits(((self.exponents_imask >> (axis * 8)) & 0xff) << 23)
    }

    /// Which child slots hold inner nodes.
    #[inline]
    pub fn imask(&self) -> u32 {
        self.exponents_imask >> 24
    }

    /// The children whose boxes the ray (origin `o`, reciprocal direction `inv`) enters before
    /// `tmax`, as a traversal mask: hit inner children as bits 24–31 at their front-to-back
    /// rank for the ray's octant (`octant_inv`, see [`octant_inv`]), hit leaves' triangles as
    /// bits 0–23 at their offsets from `triangle_base`. Every word is read at a constant index
    /// (children 0–3, then 4–7, one byte each), so a device keeps the node in registers
    /// instead of indexing a private array per child.
    #[inline]
    pub fn intersect(&self, o: Vec3, inv: Vec3, octant_inv: u32, tmax: f32) -> u32 {
        let ray = NodeRay {
            scaled_inv: Vec3::new(self.spacing(0), self.spacing(1), self.spacing(2)) * inv,
            shifted: (Vec3::from_array(self.origin) - o) * inv,
            negative_x: inv.x < 0.0,
            negative_y: inv.y < 0.0,
            negative_z: inv.z < 0.0,
            octant_inv,
            tmax,
        };
        let b = &self.bounds;
        ray.intersect_quad(self.meta[0], [b[0], b[2], b[4], b[6], b[8], b[10]])
            | ray.intersect_quad(self.meta[1], [b[1], b[3], b[5], b[7], b[9], b[11]])
    }
}

/// A ray as one node's box tests see it: on the node's grid, with its direction's signs.
struct NodeRay {
    /// The grid's spacing over the direction, per axis.
    scaled_inv: Vec3,
    /// (grid origin − ray origin) over the direction, per axis.
    shifted: Vec3,
    /// Whether the direction's x component is negative (it meets a box's max x plane first).
    negative_x: bool,
    /// Whether its y component is negative.
    negative_y: bool,
    /// Whether its z component is negative.
    negative_z: bool,
    octant_inv: u32,
    tmax: f32,
}

impl NodeRay {
    /// The traversal-mask bits of four children whose meta bytes are `meta` and whose box
    /// planes are the words `planes` (min x, max x, min y, max y, min z, max z; one byte a
    /// child).
    #[inline]
    fn intersect_quad(&self, meta: u32, planes: [u32; 6]) -> u32 {
        let (near_x, far_x) = if self.negative_x { (planes[1], planes[0]) } else { (planes[0], planes[1]) };
        let (near_y, far_y) = if self.negative_y { (planes[3], planes[2]) } else { (planes[2], planes[3]) };
        let (near_z, far_z) = if self.negative_z { (planes[5], planes[4]) } else { (planes[4], planes[5]) };
        let mut hits = 0u32;
        let mut shift = 0u32;
        while shift < 32 {
            let meta = (meta >> shift) & 0xff;
            if meta != 0 {
                let near =
                    Vec3::new(grid_byte(near_x, shift), grid_byte(near_y, shift), grid_byte(near_z, shift))
                        * self.scaled_inv
                        + self.shifted;
                let far =
                    Vec3::new(grid_byte(far_x, shift), grid_byte(far_y, shift), grid_byte(far_z, shift))
                        * self.scaled_inv
                        + self.shifted;
                let t_near = near.max_element().max(0.0);
                let t_far = far.min_element().min(self.tmax);
                if t_near <= t_far {
                    // Inner nodes have both bits 3 and 4 of their byte set (24..32), leaves never.
                    let inner = (meta & (meta << 1) & 0x10) != 0;
                    let bits = meta >> 5;
                    let index = if inner { (meta ^ self.octant_inv) & 0x1f } else { meta & 0x1f };
                    hits |= bits << index;
                }
            }
            shift += 8;
        }
        hits
    }
}

/// The byte of `word` at bit `shift`, as a grid coordinate.
#[inline]
fn grid_byte(word: u32, shift: u32) -> f32 {
    ((word >> shift) & 0xff) as f32
}

/// The ray's octant, inverted, as the three bits that reorder a node's child slots front to
/// back (obvhs builds its nodes for this order).
#[inline]
pub fn octant_inv(d: Vec3) -> u32 {
    (if d.x < 0.0 { 0 } else { 4 }) | (if d.y < 0.0 { 0 } else { 2 }) | (if d.z < 0.0 { 0 } else { 1 })
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

/// Index of the highest set bit of a non-zero word.
#[inline]
fn highest_bit(x: u32) -> u32 {
    31 - x.leading_zeros()
}

/// The device's ray caster: a CWBVH over the scene's triangles (in BVH order).
#[derive(Clone, Copy)]
pub struct WideBvh<'a> {
    /// The nodes, root first.
    pub nodes: &'a [WideNode],
    /// The triangles, in the BVH's order.
    pub triangles: &'a [Triangle],
    /// The cut-outs among them (over the same triangles).
    pub cutouts: Cutouts<'a>,
}

impl WideBvh<'_> {
    /// Walks the BVH; with `any` it stops at the first hit (shadow rays).
    #[inline]
    fn traverse(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32, any: bool) -> Hit {
        let inv = Vec3::new(safe_reciprocal(d.x), safe_reciprocal(d.y), safe_reciprocal(d.z));
        let octant = octant_inv(d);
        let mut best = Hit::NONE;
        let mut t_limit = tmax;
        let mut stack_base = [0u32; WIDE_BVH_STACK_SIZE];
        let mut stack_mask = [0u32; WIDE_BVH_STACK_SIZE];
        let mut sp = 0usize;
        // The root is the only "hit child" of a virtual node whose children start at 0.
        let mut group_base = 0u32;
        let mut group_mask = 0x8000_0000u32;
        let mut triangle_base = 0u32;
        let mut triangle_mask = 0u32;
        loop {
            while triangle_mask != 0 {
                let bit = highest_bit(triangle_mask);
                triangle_mask &= !(1 << bit);
                let slot = triangle_base + bit;
                let t = intersect_triangle(&self.triangles[slot as usize], o, d, tmin, t_limit);
                if t < t_limit && self.cutouts.stops(slot, o, d, t, key) {
                    t_limit = t;
                    best = Hit { t, triangle: slot };
                    if any {
                        return best;
                    }
                }
            }
            if group_mask & 0xff00_0000 != 0 {
                let rank = highest_bit(group_mask);
                let hits = group_mask;
                group_mask &= !(1 << rank);
                if group_mask & 0xff00_0000 != 0 && sp < WIDE_BVH_STACK_SIZE {
                    stack_base[sp] = group_base;
                    stack_mask[sp] = group_mask;
                    sp += 1;
                }
                // The child's slot, and its node's place among the inner children before it.
                let slot = (rank - 24) ^ octant;
                let relative = (hits & !(u32::MAX << slot)).count_ones();
                let node = self.nodes[(group_base + relative) as usize];
                let mask = node.intersect(o, inv, octant, t_limit);
                group_base = node.child_base;
                group_mask = (mask & 0xff00_0000) | node.imask();
                triangle_base = node.triangle_base;
                triangle_mask = mask & 0x00ff_ffff;
            } else {
                group_mask = 0;
            }
            if triangle_mask == 0 && group_mask & 0xff00_0000 == 0 {
                if sp == 0 {
                    break;
                }
                sp -= 1;
                group_base = stack_base[sp];
                group_mask = stack_mask[sp];
            }
        }
        best
    }
}

impl RayCaster for WideBvh<'_> {
    #[inline]
    fn closest_hit(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> Hit {
        self.traverse(o, d, tmin, tmax, key, false)
    }

    #[inline]
    fn occluded(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32, key: u32) -> bool {
        self.traverse(o, d, tmin, tmax, key, true).found()
    }
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;
    use crate::triangle::NO_HIT;

    /// One node whose child slot 0 is a leaf of one triangle, on a grid of spacing 1/255 from
    /// the origin (the node box [0, 1]³), as obvhs lays out a one-triangle scene.
    fn one_leaf(tri: Triangle) -> (Vec<WideNode>, Vec<Triangle>) {
        let exponent = ((1.0f32 / 255.0).to_bits() >> 23) & 0xff;
        let mut node = WideNode {
            origin: [0.0; 3],
            exponents_imask: exponent | exponent << 8 | exponent << 16,
            child_base: 1,
            triangle_base: 0,
            meta: [0b001_00000, 0],
            bounds: [0; 12],
        };
        for plane in [1, 3, 5] {
            node.bounds[plane * 2] = 255; // child 0's max planes at 255 · spacing = 1
        }
        (vec![node], vec![tri])
    }

    /// Axis-parallel rays, zero components of both signs: the box test stays NaN-free, rays
    /// along a box face count as hits, rays outside the slab or pointing away as misses.
    #[test]
    fn box_test_with_zero_direction_components() {
        let (nodes, _) = one_leaf(Triangle::default());
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
            let mask = nodes[0].intersect(o, inv, octant_inv(d), NO_HIT);
            assert_eq!(mask, if expect { 1 } else { 0 }, "o {o} d {d}");
        }
    }

    /// The one-leaf BVH answers as the triangle test does, through both queries.
    #[test]
    fn a_leaf_answers_as_its_triangle() {
        let tri =
            Triangle { v0: [0.0, 0.5, 0.0], v1: [1.0, 0.5, 0.0], v2: [0.0, 0.5, 1.0], ..Default::default() };
        let (nodes, tris) = one_leaf(tri);
        let bvh = WideBvh { nodes: &nodes, triangles: &tris, cutouts: Cutouts::NONE };
        let (o, down) = (Vec3::new(0.25, 2.0, 0.25), Vec3::NEG_Y);
        assert_eq!(bvh.closest_hit(o, down, 0.0, NO_HIT, 0), Hit { t: 1.5, triangle: 0 });
        assert!(!bvh.closest_hit(o, -down, 0.0, NO_HIT, 0).found());
        assert!(bvh.occluded(o, down, 0.0, 2.0, 0));
        assert!(!bvh.occluded(o, down, 0.0, 1.0, 0), "the triangle lies beyond tmax");
        assert!(!bvh.occluded(o, down, 1.6, NO_HIT, 0), "the triangle lies before tmin");
        assert!(!bvh.closest_hit(Vec3::new(0.9, 2.0, 0.9), down, 0.0, NO_HIT, 0).found(), "outside");
    }

    /// 80 bytes, laid out as obvhs's node (the host casts obvhs's nodes to these; the host's
    /// tests check the traversal against obvhs's own on real scenes).
    #[test]
    fn node_layout_is_obvhs_s() {
        assert_eq!(core::mem::size_of::<WideNode>(), 80);
        assert_eq!(core::mem::offset_of!(WideNode, child_base), 16);
        assert_eq!(core::mem::offset_of!(WideNode, meta), 24);
        assert_eq!(core::mem::offset_of!(WideNode, bounds), 32);
    }
}
