//! A surface point's two normals: the geometric one (the triangle's, by its winding) and the
//! shading one (glTF's `NORMAL` attribute interpolated over the triangle), and the cosine
//! factor a scattering there contributes in each transport direction.
//!
//! **Who uses which.** The BSDF is evaluated and sampled in the shading normal's frame
//! (`crate::bsdf`), and the cosine of the scattering equation is the shading normal's
//! ([`scattering_cosine`]). The geometric normal decides everything about the surface as a
//! surface: which side a direction lies on (reflection or transmission, so that a direction the
//! shading normal calls reflected but which enters the surface — light through the wall — gives
//! 0, see `crate::bsdf`), a dielectric's inside, one-sided emission, the ray origin's offset, and
//! the conversion of densities between solid angle and area (an area's projection is the
//! geometric one).
//!
//! **The adjoint** (Veach's thesis §5.3). With shading normals the BSDF times its cosine is no
//! longer symmetric, so a light subpath, which carries importance, must weigh a scattering by
//! the adjoint's cosine: for light arriving along `wo` and the subpath leaving along `wi`,
//! `|ns·wo| |ng·wi| / |ng·wo|` instead of `|ns·wi|`. With it, a path's contribution is the same
//! whichever end it was traced from ([`scattering_cosine`]'s test); without it the
//! bidirectional techniques disagree with the path tracer wherever ns ≠ ng.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use glam::{Vec2, Vec3};

/// The geometric and shading normals at a surface point, and the clear coat's (unit; the
/// shading and coat ones on the geometric one's side), and an anisotropic lobe's direction.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Normals {
    /// The triangle's normal, by its winding.
    pub geometric: Vec3,
    /// The interpolated vertex normal, bent by the material's normal texture; the geometric
    /// one where the mesh has none.
    pub shading: Vec3,
    /// The clear coat's normal (`crate::clearcoat`): the interpolated vertex normal, bent by the
    /// material's clearcoatNormalTexture only — `KHR_materials_clearcoat` keeps the coat unbent
    /// by the base's normal texture. The shading one where the material has no normal texture.
    pub coat: Vec3,
    /// The world direction of an anisotropic lobe's wider roughness (`KHR_materials_anisotropy`,
    /// from the surface's tangent frame, `crate::surface::normals_at`), not yet made orthogonal
    /// to the shading normal (`crate::bsdf::LobeFrame`); zero for an isotropic material, whose
    /// lobes take any frame about it. Turning the normals to a side keeps it.
    pub anisotropy: Vec3,
}

impl Normals {
    /// A flat surface: the shading and coat normals are the geometric one.
    #[inline]
    pub fn flat(n: Vec3) -> Self {
        Self { geometric: n, shading: n, coat: n, anisotropy: Vec3::ZERO }
    }

    /// A surface whose coat, if any, follows the shading normal (no normal texture).
    #[inline]
    pub fn shaded(geometric: Vec3, shading: Vec3) -> Self {
        Self { geometric, shading, coat: shading, anisotropy: Vec3::ZERO }
    }

    /// The normals turned to the side of the surface (by the geometric normal) that `w` lies
    /// on.
    #[inline]
    pub fn facing(self, w: Vec3) -> Self {
        if self.geometric.dot(w) >= 0.0 {
            self
        } else {
            Self { geometric: -self.geometric, shading: -self.shading, coat: -self.coat, ..self }
        }
    }
}

/// A triangle's vertex normals (uploaded as it is, one per triangle in the triangles' order
/// where any mesh has normals): `NORMAL` of its three vertices in world space, unit; all zeros
/// for a flat triangle (no `NORMAL`, or all three the geometric normal).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TriangleNormals {
    #[allow(missing_docs)] // see the struct
    pub n: [f32; 9],
}

impl TriangleNormals {
    /// The vertex normals interpolated at barycentric coordinates `b` (weights of v0, v1),
    /// not normalised.
    #[inline]
    pub fn at(&self, b: Vec2) -> Vec3 {
        let n = &self.n;
        let (a, c, d) =
            (Vec3::new(n[0], n[1], n[2]), Vec3::new(n[3], n[4], n[5]), Vec3::new(n[6], n[7], n[8]));
        a * b.x + c * b.y + d * (1.0 - b.x - b.y)
    }
}

/// The shading normal from the interpolated vertex normal `interpolated` and the geometric
/// normal `ng` (unit): `interpolated` normalised and turned to `ng`'s side (normals that
/// disagree with the winding are read as the winding says: the geometry decides the sides);
/// `ng` where it is zero (a flat triangle, or vertex normals that cancel).
#[inline]
pub fn shading_normal(interpolated: Vec3, ng: Vec3) -> Vec3 {
    let len2 = interpolated.length_squared();
    if !(len2 > 1e-12) {
        return ng;
    }
    let n = interpolated / len2.sqrt();
    if n.dot(ng) < 0.0 {
        -n
    } else {
        n
    }
}

/// The cosine that multiplies the BSDF at a scattering where the subpath arrived from `wo`
/// and continues along `wi` (both unit, pointing away): where radiance is transported (a
/// camera subpath, the path tracer: light comes from `wi`) the shading cosine `|ns·wi|`; where
/// importance is (a light subpath: light comes from `wo`) Veach's adjoint
/// `|ns·wo| |ng·wi| / |ng·wo|` (0 when `wo` lies in the surface). Both are `|n·wi|` on a flat
/// surface.
#[inline]
pub fn scattering_cosine(n: Normals, wo: Vec3, wi: Vec3, radiance: bool) -> f32 {
    if radiance {
        return n.shading.dot(wi).abs();
    }
    let cos_go = n.geometric.dot(wo).abs();
    if !(cos_go > 0.0) {
        return 0.0;
    }
    n.shading.dot(wo).abs() * n.geometric.dot(wi).abs() / cos_go
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    fn unit(x: f32, y: f32, z: f32) -> Vec3 {
        Vec3::new(x, y, z).normalize()
    }

    #[test]
    fn flat_normals_give_the_plain_cosine_both_ways() {
        let n = Normals::flat(Vec3::Z);
        let (wo, wi) = (unit(0.3, 0.1, 0.9), unit(-0.5, 0.2, 0.4));
        for radiance in [true, false] {
            assert!((scattering_cosine(n, wo, wi, radiance) - wi.z).abs() < 1e-6);
        }
    }

    /// A path's contribution in the area measure must not depend on the end it was traced
    /// from: the cosine a vertex contributes, over the geometric cosine of the direction it
    /// continues along (what the next vertex's area density divides by), is the same traced
    /// from the light (importance, light from wo) as from the camera (radiance, the same pair
    /// with the roles swapped).
    #[test]
    fn the_adjoint_makes_the_contribution_independent_of_the_tracing_direction() {
        let n = Normals::shaded(Vec3::Z, unit(0.4, -0.2, 1.0));
        let pairs = [
            (unit(0.3, 0.1, 0.9), unit(-0.5, 0.2, 0.4)),
            (unit(0.9, 0.0, 0.1), unit(-0.1, 0.7, 0.2)),
            (unit(-0.2, -0.6, 0.3), unit(0.0, 0.3, -0.9)),
        ];
        for (wo, wi) in pairs {
            // From the light: arrived from wo (the light's side), continues along wi.
            let from_light = scattering_cosine(n, wo, wi, false) / n.geometric.dot(wi).abs();
            // From the camera: arrived from wi (the camera's side), continues along wo.
            let from_camera = scattering_cosine(n, wi, wo, true) / n.geometric.dot(wo).abs();
            assert!(
                (from_light - from_camera).abs() < 1e-6 * from_camera.max(1.0),
                "{from_light} {from_camera}"
            );
            // And the naive cosine would not be (the test can fail).
            let naive = n.shading.dot(wi).abs() / n.geometric.dot(wi).abs();
            assert!((naive - from_camera).abs() > 1e-3);
        }
    }

    #[test]
    fn shading_normals_are_normalised_turned_to_the_geometric_side_or_the_geometric_one() {
        let ng = Vec3::Z;
        assert_eq!(shading_normal(Vec3::new(0.0, 0.0, 2.0), ng), Vec3::Z);
        let s = shading_normal(Vec3::new(0.3, 0.0, -1.0), ng);
        assert!((s - unit(-0.3, 0.0, 1.0)).length() < 1e-6, "{s}");
        assert_eq!(shading_normal(Vec3::ZERO, ng), ng);
        assert_eq!(shading_normal(Vec3::splat(f32::NAN), ng), ng);
    }

    #[test]
    fn vertex_normals_interpolate_by_barycentrics() {
        let t = TriangleNormals { n: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0] };
        assert_eq!(t.at(Vec2::new(1.0, 0.0)), Vec3::X);
        assert_eq!(t.at(Vec2::new(0.0, 1.0)), Vec3::Y);
        assert_eq!(t.at(Vec2::new(0.0, 0.0)), Vec3::Z);
        assert!((t.at(Vec2::new(0.25, 0.5)) - Vec3::new(0.25, 0.5, 0.25)).length() < 1e-7);
    }

    #[test]
    fn facing_turns_the_normals_by_the_geometric_side() {
        let n = Normals {
            geometric: Vec3::Z,
            shading: unit(0.5, 0.0, 1.0),
            coat: unit(0.0, 0.2, 1.0),
            anisotropy: Vec3::X,
        };
        assert_eq!(n.facing(Vec3::new(0.0, 0.0, 1.0)), n);
        let back = n.facing(Vec3::new(0.9, 0.0, -0.1));
        assert_eq!((back.geometric, back.shading, back.coat), (-n.geometric, -n.shading, -n.coat));
        // An anisotropic lobe's direction is the surface's on either side.
        assert_eq!(back.anisotropy, n.anisotropy);
    }
}
