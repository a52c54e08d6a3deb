//! The GGX (Trowbridge–Reitz) microfacet distribution, anisotropic, of roughnesses α = (αx, αy)
//! along the local frame's x and y axes (glTF's α = roughness², the same on both axes but where
//! `KHR_materials_anisotropy` widens one, `crate::bsdf::Material::alphas`), with Smith's
//! shadowing–masking and sampling of the visible normals (Heitz 2018, "Sampling the GGX
//! Distribution of Visible Normals"). Directions are in a local frame whose z axis is the macro
//! surface normal on the side of `wo` and whose x axis is the direction of αx.
//!
//! - `D(m) = 1 / (π αx αy ((m_x/αx)² + (m_y/αy)² + m_z²)²)` (normalised: ∫ D cos θ_m dω_m = 1;
//!   with αx = αy = α, the isotropic `α² / (π ((α² − 1) cos²θ_m + 1)²)`);
//! - `Λ(w) = (√(1 + ((αx w_x)² + (αy w_y)²) / w_z²) − 1) / 2`, `G1(w) = 1 / (1 + Λ(w))`, and
//!   the height-correlated `G(wo, wi) = 1 / (1 + Λ(wo) + Λ(wi))` (Heitz 2014);
//! - the visible normals' density `D_wo(m) = G1(wo) max(0, wo·m) D(m) / cos θ_o`;
//! - the reflection lobe `D(h) G / (4 cos θ_o cos θ_i)`, sampled by reflecting `wo` about a
//!   visible normal, with density `D_wo(h) / (4 wo·h)`.
//!
//! `KHR_materials_anisotropy`'s `D_GGX_anisotropic` and `V_GGX_anisotropic` are these D and
//! G / (4 cos θ_o cos θ_i) in another arrangement (its at, ab are αx, αy).

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use core::f32::consts::PI;
use glam::{Vec2, Vec3};

/// The density of micro-normals `D(m)` of the unit micro-normal `m` (local), roughnesses
/// `alpha`, in the extension's arrangement: `a² w² / π`, `w = a / |(αy m_x, αx m_y, a m_z)|²`,
/// a = αx αy (one division; the sum of squares has no cancellation: near the peak of a narrow
/// lobe, α ~ 10⁻³, the isotropic form `(α² − 1) cos²θ + 1` would cancel to a handful of f32
/// levels).
#[inline]
pub fn ggx_d(alpha: Vec2, m: Vec3) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let a = alpha.x * alpha.y;
    let len2 = Vec3::new(alpha.y * m.x, alpha.x * m.y, a * m.z).length_squared();
    if !(len2 > 0.0) {
        return 0.0;
    }
    let w = a / len2;
    a * w * w / PI
}

/// Smith's Λ of the unit direction `w` (local; either side).
#[inline]
pub fn smith_lambda(alpha: Vec2, w: Vec3) -> f32 {
    let c2 = w.z * w.z;
    if !(c2 > 0.0) {
        return f32::INFINITY;
    }
    let (x, y) = (alpha.x * w.x, alpha.y * w.y);
    let tan2 = (x * x + y * y) / c2;
    ((1.0 + tan2).sqrt() - 1.0) * 0.5
}

/// Smith's masking G1 of the direction `w` (local).
#[inline]
pub fn smith_g1(alpha: Vec2, w: Vec3) -> f32 {
    1.0 / (1.0 + smith_lambda(alpha, w))
}

/// The height-correlated shadowing–masking G(wo, wi) of the directions `wo`, `wi` (local).
#[inline]
pub fn smith_g(alpha: Vec2, wo: Vec3, wi: Vec3) -> f32 {
    1.0 / (1.0 + smith_lambda(alpha, wo) + smith_lambda(alpha, wi))
}

/// The density of the visible normal `m` seen from `wo` (both local, `wo.z` > 0): what
/// [`sample_visible_normal`] samples.
#[inline]
pub fn visible_normal_pdf(alpha: Vec2, wo: Vec3, m: Vec3) -> f32 {
    let cos_om = wo.dot(m);
    if !(wo.z > 0.0 && cos_om > 0.0) {
        return 0.0;
    }
    smith_g1(alpha, wo) * cos_om * ggx_d(alpha, m) / wo.z
}

/// A micro-normal visible from `wo` (local, `wo.z` > 0) for `u` ∈ [0,1)², with density
/// [`visible_normal_pdf`] (Heitz 2018: the hemisphere stretched to α = 1 along each axis, a
/// point on the projected disk, lifted and unstretched).
#[inline]
pub fn sample_visible_normal(alpha: Vec2, wo: Vec3, u: Vec2) -> Vec3 {
    let vh = Vec3::new(alpha.x * wo.x, alpha.y * wo.y, wo.z).normalize();
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = if len2 > 0.0 { Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt() } else { Vec3::X };
    let t2 = vh.cross(t1);
    let r = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    let p1 = r * phi.cos();
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
    let nh = t1 * p1 + t2 * p2 + vh * (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    Vec3::new(alpha.x * nh.x, alpha.y * nh.y, nh.z.max(1e-7)).normalize()
}

/// The GGX reflection lobe without a Fresnel factor, `D(h) G(wo, wi) / (4 cos θ_o cos θ_i)`,
/// h = normalize(wo + wi), for `wo` and `wi` local and above the surface (the callers' test); 0
/// where the cosines' product underflows. glTF's specular term (its BRDF's, times Fresnel; the
/// clear coat's, as it is).
#[inline]
pub fn reflection(alpha: Vec2, wo: Vec3, wi: Vec3) -> f32 {
    let denominator = 4.0 * wo.z * wi.z;
    if !(denominator > 0.0) {
        return 0.0;
    }
    ggx_d(alpha, (wo + wi).normalize()) * smith_g(alpha, wo, wi) / denominator
}

/// The solid-angle density of [`sample_reflection`]'s `wi` given `wo` (local, both above the
/// surface): the visible normal's density over the reflection's Jacobian `4 wo·h`.
#[inline]
pub fn reflection_pdf(alpha: Vec2, wo: Vec3, wi: Vec3) -> f32 {
    let h = (wo + wi).normalize();
    visible_normal_pdf(alpha, wo, h) / (4.0 * wo.dot(h))
}

/// `wo` (local, `wo.z` > 0) reflected about a visible normal sampled with `u` ∈ [0,1)²; None
/// where the reflection falls below the surface.
#[inline]
pub fn sample_reflection(alpha: Vec2, wo: Vec3, u: Vec2) -> Option<Vec3> {
    let m = sample_visible_normal(alpha, wo, u);
    let wi = 2.0 * wo.dot(m) * m - wo;
    if wi.z > 0.0 {
        Some(wi.normalize())
    } else {
        None
    }
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;
    use crate::rng::{uniform, RngKey};

    fn u2(i: u32, seed: u32) -> Vec2 {
        let k = |d| uniform(RngKey { seed, chain: i, iteration: 0, dimension: d });
        Vec2::new(k(0), k(1))
    }

    /// Isotropic roughnesses and anisotropic pairs, both ways round.
    const ALPHAS: [Vec2; 6] = [
        Vec2::splat(0.05),
        Vec2::splat(0.2),
        Vec2::splat(0.5),
        Vec2::splat(1.0),
        Vec2::new(0.6, 0.08),
        Vec2::new(0.1, 0.9),
    ];

    /// ∫ D(m) cos θ_m dω_m = 1 (the projected micro-area is the macro area), and the visible
    /// normals' density integrates to 1, by quadrature over the hemisphere.
    #[test]
    fn the_distribution_and_the_visible_normals_are_normalised() {
        for alpha in ALPHAS {
            let wo = Vec3::new(0.6, 0.1, 0.5).normalize();
            let (n_theta, n_phi) = (2000, 200);
            let (mut d_sum, mut v_sum) = (0.0f64, 0.0f64);
            for i in 0..n_theta {
                // Quadrature in cos θ, denser near the pole where a narrow D lives.
                let c = 1.0 - ((i as f64 + 0.5) / n_theta as f64).powi(3);
                let dc = 3.0 * ((i as f64 + 0.5) / n_theta as f64).powi(2) / n_theta as f64;
                let s = (1.0 - c * c).max(0.0).sqrt();
                for j in 0..n_phi {
                    let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / n_phi as f64;
                    let m = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32);
                    let w = dc * 2.0 * std::f64::consts::PI / n_phi as f64;
                    d_sum += ggx_d(alpha, m) as f64 * c * w;
                    v_sum += visible_normal_pdf(alpha, wo, m) as f64 * w;
                }
            }
            assert!((d_sum - 1.0).abs() < 2e-3, "α {alpha}: ∫ D cos = {d_sum}");
            assert!((v_sum - 1.0).abs() < 2e-3, "α {alpha}: ∫ D_wo = {v_sum}");
        }
    }

    /// χ² of sampled visible normals against their density, over 10 × 10 bins uniform in
    /// cos θ_m and φ.
    #[test]
    fn visible_normals_are_sampled_by_their_density() {
        for (alpha, wo) in [
            (Vec2::splat(0.3), Vec3::new(0.5, 0.2, 0.8)),
            (Vec2::splat(0.8), Vec3::new(-0.9, 0.3, 0.2)),
            (Vec2::new(0.7, 0.15), Vec3::new(0.4, -0.6, 0.5)),
            (Vec2::new(0.05, 0.5), Vec3::new(-0.3, 0.8, 0.3)),
        ] {
            let wo = wo.normalize();
            let n = 200_000u32;
            let mut counts = [[0u32; 10]; 10];
            for i in 0..n {
                let m = sample_visible_normal(alpha, wo, u2(i, 21));
                assert!((m.length() - 1.0).abs() < 1e-4 && m.z > 0.0 && m.dot(wo) > -1e-4);
                let ci = (m.z * 10.0).clamp(0.0, 9.999) as usize;
                let pj = ((m.y.atan2(m.x) + PI) / (2.0 * PI) * 10.0).clamp(0.0, 9.999) as usize;
                counts[ci][pj] += 1;
            }
            let mut chi2 = 0.0f64;
            for (ci, row) in counts.iter().enumerate() {
                for (pj, &count) in row.iter().enumerate() {
                    // The bin's probability by a Q × Q midpoint rule inside it (fine enough
                    // for the narrow axis of an anisotropic lobe).
                    const Q: usize = 160;
                    let mut p = 0.0f64;
                    for a in 0..Q {
                        for b in 0..Q {
                            let c = (ci as f64 + (a as f64 + 0.5) / Q as f64) / 10.0;
                            let phi = -std::f64::consts::PI
                                + 2.0 * std::f64::consts::PI * (pj as f64 + (b as f64 + 0.5) / Q as f64)
                                    / 10.0;
                            let s = (1.0 - c * c).sqrt();
                            let m = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32);
                            p += visible_normal_pdf(alpha, wo, m) as f64
                                * (0.1 / Q as f64)
                                * (2.0 * std::f64::consts::PI / (10 * Q) as f64);
                        }
                    }
                    let expected = p * n as f64;
                    if expected > 5.0 {
                        chi2 += (count as f64 - expected).powi(2) / expected;
                    }
                }
            }
            assert!(chi2 < 99.0 + 5.0 * (2.0f64 * 99.0).sqrt(), "α {alpha}: χ² = {chi2}");
        }
    }

    /// The unit direction at cosine `c` from the normal, at azimuth `phi`.
    fn at(c: f32, phi: f32) -> Vec3 {
        let s = (1.0 - c * c).max(0.0).sqrt();
        Vec3::new(s * phi.cos(), s * phi.sin(), c)
    }

    /// G1 is 1 at normal incidence and falls towards grazing; the height-correlated G lies
    /// between the uncorrelated product G1·G1 and the smaller G1.
    #[test]
    fn shadowing_behaves() {
        let a = Vec2::splat(0.5);
        assert!((smith_g1(a, Vec3::Z) - 1.0).abs() < 1e-6);
        assert!(smith_g1(a, at(0.1, 0.3)) < smith_g1(a, at(0.5, 0.3)));
        for (co, ci) in [(0.3f32, 0.7f32), (0.9, -0.4), (0.05, 0.2)] {
            let a = Vec2::splat(0.4);
            let (wo, wi) = (at(co, 1.0), at(ci, 2.5));
            let (go, gi) = (smith_g1(a, wo), smith_g1(a, wi));
            let g = smith_g(a, wo, wi);
            assert!(g >= go * gi - 1e-6 && g <= go.min(gi) + 1e-6, "{g} {go} {gi}");
        }
    }

    /// Isotropic, Λ depends on the direction's cosine alone (the textbook tan² form);
    /// anisotropic, on its azimuth too: along x it is the isotropic Λ of αx, along y of αy.
    #[test]
    fn shadowing_follows_the_roughness_along_the_direction() {
        for c in [0.1f32, 0.4, 0.9] {
            let tan2 = (1.0 - c * c) / (c * c);
            let textbook = |a: f32| ((1.0 + a * a * tan2).sqrt() - 1.0) * 0.5;
            for phi in [0.0f32, 0.7, 2.0, 4.0] {
                let l = smith_lambda(Vec2::splat(0.3), at(c, phi));
                assert!((l - textbook(0.3)).abs() <= 1e-5 * textbook(0.3).max(1.0), "{l}");
            }
            let a = Vec2::new(0.8, 0.1);
            let along_x = smith_lambda(a, at(c, 0.0));
            let along_y = smith_lambda(a, at(c, PI / 2.0));
            assert!((along_x - textbook(0.8)).abs() <= 1e-5 * textbook(0.8).max(1.0));
            assert!((along_y - textbook(0.1)).abs() <= 1e-4 * textbook(0.1).max(1.0));
        }
    }

    /// D is glTF's `D_GGX_anisotropic` (`KHR_materials_anisotropy`'s arrangement, in f64) and
    /// `reflection` its `V_GGX_anisotropic` · D, at directions off both axes.
    #[test]
    fn the_lobe_is_the_extension_s() {
        let (at_, ab) = (0.7f64, 0.2f64);
        let alpha = Vec2::new(at_ as f32, ab as f32);
        for (wo, wi) in
            [(at(0.8, 0.4), at(0.6, 3.0)), (at(0.3, 1.2), at(0.9, -2.0)), (at(0.5, 2.2), at(0.5, 0.9))]
        {
            let h = (wo + wi).normalize();
            let (t, b, n) = (|v: Vec3| v.x as f64, |v: Vec3| v.y as f64, |v: Vec3| v.z as f64);
            let a2 = at_ * ab;
            let f = [ab * t(h), at_ * b(h), a2 * n(h)];
            let w2 = a2 / (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
            let d = a2 * w2 * w2 / std::f64::consts::PI;
            let len = |x: f64, y: f64, z: f64| (x * x + y * y + z * z).sqrt();
            let ggx_v = n(wi) * len(at_ * t(wo), ab * b(wo), n(wo));
            let ggx_l = n(wo) * len(at_ * t(wi), ab * b(wi), n(wi));
            let v = 0.5 / (ggx_v + ggx_l);
            let got = ggx_d(alpha, h) as f64;
            assert!((got - d).abs() <= 1e-5 * d, "D {got} vs {d}");
            let lobe = reflection(alpha, wo, wi) as f64;
            assert!((lobe - d * v).abs() <= 1e-5 * d * v, "lobe {lobe} vs {}", d * v);
        }
    }

    /// D stays accurate at the peak of a narrow lobe (α 10⁻³), against f64 at angles within it.
    #[test]
    fn a_narrow_lobe_is_accurate_near_its_peak() {
        let alpha = 1e-3f32;
        for theta in [0.0f64, 2e-4, 5e-4, 1e-3, 3e-3] {
            let m = Vec3::new(theta.sin() as f32, 0.0, theta.cos() as f32);
            let a2 = (alpha as f64).powi(2);
            let d = a2 * theta.cos().powi(2) + theta.sin().powi(2);
            let exact = a2 / (std::f64::consts::PI * d * d);
            let got = ggx_d(Vec2::splat(alpha), m) as f64;
            assert!((got - exact).abs() <= 1e-4 * exact, "θ {theta}: {got} vs {exact}");
        }
    }
}
