//! The GGX (Trowbridge–Reitz) microfacet distribution, isotropic, of roughness α (glTF's
//! α = roughness²), with Smith's shadowing–masking and sampling of the visible normals (Heitz
//! 2018, "Sampling the GGX Distribution of Visible Normals"). Directions are in a local frame
//! whose z axis is the macro surface normal on the side of `wo`.
//!
//! - `D(m) = α² / (π ((α² − 1) cos²θ_m + 1)²)` (normalised: ∫ D cos θ_m dω_m = 1);
//! - `Λ(w) = (√(1 + α² tan²θ) − 1) / 2`, `G1(w) = 1 / (1 + Λ(w))`, and the height-correlated
//!   `G(wo, wi) = 1 / (1 + Λ(wo) + Λ(wi))` (Heitz 2014);
//! - the visible normals' density `D_wo(m) = G1(wo) max(0, wo·m) D(m) / cos θ_o`;
//! - the reflection lobe `D(h) G / (4 cos θ_o cos θ_i)`, sampled by reflecting `wo` about a
//!   visible normal, with density `D_wo(h) / (4 wo·h)`.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

use core::f32::consts::PI;
use glam::{Vec2, Vec3};

/// The density of micro-normals `D(m)` of the unit micro-normal `m` (local). The denominator
/// `(α² − 1) cos²θ + 1` is computed as `α² cos²θ + sin²θ` from m's components: near the peak
/// of a narrow lobe (α ~ 10⁻³) the first form cancels to a handful of f32 levels.
#[inline]
pub fn ggx_d(alpha: f32, m: Vec3) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let d = a2 * m.z * m.z + (m.x * m.x + m.y * m.y);
    if !(d > 0.0) {
        return 0.0;
    }
    a2 / (PI * d * d)
}

/// Smith's Λ of a direction at cosine `cos` from the macro normal (either side).
#[inline]
pub fn smith_lambda(alpha: f32, cos: f32) -> f32 {
    let c2 = cos * cos;
    if !(c2 > 0.0) {
        return f32::INFINITY;
    }
    let tan2 = ((1.0 - c2) / c2).max(0.0);
    ((1.0 + alpha * alpha * tan2).sqrt() - 1.0) * 0.5
}

/// Smith's masking G1 of a direction at cosine `cos`.
#[inline]
pub fn smith_g1(alpha: f32, cos: f32) -> f32 {
    1.0 / (1.0 + smith_lambda(alpha, cos))
}

/// The height-correlated shadowing–masking G(wo, wi) of directions at cosines `cos_o`, `cos_i`.
#[inline]
pub fn smith_g(alpha: f32, cos_o: f32, cos_i: f32) -> f32 {
    1.0 / (1.0 + smith_lambda(alpha, cos_o) + smith_lambda(alpha, cos_i))
}

/// The density of the visible normal `m` seen from `wo` (both local, `wo.z` > 0): what
/// [`sample_visible_normal`] samples.
#[inline]
pub fn visible_normal_pdf(alpha: f32, wo: Vec3, m: Vec3) -> f32 {
    let cos_om = wo.dot(m);
    if !(wo.z > 0.0 && cos_om > 0.0) {
        return 0.0;
    }
    smith_g1(alpha, wo.z) * cos_om * ggx_d(alpha, m) / wo.z
}

/// A micro-normal visible from `wo` (local, `wo.z` > 0) for `u` ∈ [0,1)², with density
/// [`visible_normal_pdf`] (Heitz 2018: the hemisphere stretched to α = 1, a point on the
/// projected disk, lifted and unstretched).
#[inline]
pub fn sample_visible_normal(alpha: f32, wo: Vec3, u: Vec2) -> Vec3 {
    let vh = Vec3::new(alpha * wo.x, alpha * wo.y, wo.z).normalize();
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = if len2 > 0.0 { Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt() } else { Vec3::X };
    let t2 = vh.cross(t1);
    let r = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    let p1 = r * phi.cos();
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
    let nh = t1 * p1 + t2 * p2 + vh * (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    Vec3::new(alpha * nh.x, alpha * nh.y, nh.z.max(1e-7)).normalize()
}

/// The GGX reflection lobe without a Fresnel factor, `D(h) G(wo, wi) / (4 cos θ_o cos θ_i)`,
/// h = normalize(wo + wi), for `wo` and `wi` local and above the surface (the callers' test); 0
/// where the cosines' product underflows. glTF's specular term (its BRDF's, times Fresnel; the
/// clear coat's, as it is).
#[inline]
pub fn reflection(alpha: f32, wo: Vec3, wi: Vec3) -> f32 {
    let denominator = 4.0 * wo.z * wi.z;
    if !(denominator > 0.0) {
        return 0.0;
    }
    ggx_d(alpha, (wo + wi).normalize()) * smith_g(alpha, wo.z, wi.z) / denominator
}

/// The solid-angle density of [`sample_reflection`]'s `wi` given `wo` (local, both above the
/// surface): the visible normal's density over the reflection's Jacobian `4 wo·h`.
#[inline]
pub fn reflection_pdf(alpha: f32, wo: Vec3, wi: Vec3) -> f32 {
    let h = (wo + wi).normalize();
    visible_normal_pdf(alpha, wo, h) / (4.0 * wo.dot(h))
}

/// `wo` (local, `wo.z` > 0) reflected about a visible normal sampled with `u` ∈ [0,1)²; None
/// where the reflection falls below the surface.
#[inline]
pub fn sample_reflection(alpha: f32, wo: Vec3, u: Vec2) -> Option<Vec3> {
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

    /// ∫ D(m) cos θ_m dω_m = 1 (the projected micro-area is the macro area), and the visible
    /// normals' density integrates to 1, by quadrature over the hemisphere.
    #[test]
    fn the_distribution_and_the_visible_normals_are_normalised() {
        for alpha in [0.05f32, 0.2, 0.5, 1.0] {
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
        for (alpha, wo) in [(0.3f32, Vec3::new(0.5, 0.2, 0.8)), (0.8, Vec3::new(-0.9, 0.3, 0.2))] {
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
                    // The bin's probability by a 40 × 40 midpoint rule inside it.
                    let mut p = 0.0f64;
                    for a in 0..40 {
                        for b in 0..40 {
                            let c = (ci as f64 + (a as f64 + 0.5) / 40.0) / 10.0;
                            let phi = -std::f64::consts::PI
                                + 2.0 * std::f64::consts::PI * (pj as f64 + (b as f64 + 0.5) / 40.0) / 10.0;
                            let s = (1.0 - c * c).sqrt();
                            let m = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32);
                            p += visible_normal_pdf(alpha, wo, m) as f64
                                * (0.1 / 40.0)
                                * (2.0 * std::f64::consts::PI / 400.0);
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

    /// G1 is 1 at normal incidence and falls towards grazing; the height-correlated G lies
    /// between the uncorrelated product G1·G1 and the smaller G1.
    #[test]
    fn shadowing_behaves() {
        assert!((smith_g1(0.5, 1.0) - 1.0).abs() < 1e-6);
        assert!(smith_g1(0.5, 0.1) < smith_g1(0.5, 0.5));
        for (co, ci) in [(0.3f32, 0.7f32), (0.9, -0.4), (0.05, 0.2)] {
            let (go, gi) = (smith_g1(0.4, co), smith_g1(0.4, ci));
            let g = smith_g(0.4, co, ci);
            assert!(g >= go * gi - 1e-6 && g <= go.min(gi) + 1e-6, "{g} {go} {gi}");
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
            let got = ggx_d(alpha, m) as f64;
            assert!((got - exact).abs() <= 1e-4 * exact, "θ {theta}: {got} vs {exact}");
        }
    }
}
