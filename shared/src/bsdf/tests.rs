use super::*;
use crate::rng::{uniform, RngKey};

fn u2(i: u32, seed: u32) -> Vec2 {
    let k = |d| uniform(RngKey { seed, chain: i, iteration: 0, dimension: d });
    Vec2::new(k(0), k(1))
}

fn lambert(a: f32) -> Material {
    Material { albedo: [a; 3], ..Default::default() }
}

fn phong(e: f32) -> Material {
    Material { albedo: [0.8; 3], phong_exponent: e, ..Default::default() }
}

#[test]
fn basis_is_orthonormal() {
    for i in 0..1000 {
        let n = cosine_hemisphere(Vec3::new(0.0, 0.0, if i % 2 == 0 { 1.0 } else { -1.0 }), u2(i, 1));
        let (t, b) = orthonormal_basis(n);
        assert!((t.length() - 1.0).abs() < 1e-5 && (b.length() - 1.0).abs() < 1e-5);
        assert!(t.dot(n).abs() < 1e-5 && b.dot(n).abs() < 1e-5 && t.dot(b).abs() < 1e-5);
    }
}

/// For a Lambertian surface f · cos / pdf is the albedo for every sample, on either side.
#[test]
fn lambert_weight_is_the_albedo() {
    let m = lambert(0.6);
    let n = Vec3::Y;
    for i in 0..1000 {
        let wo = cosine_hemisphere(if i % 2 == 0 { n } else { -n }, u2(i, 2));
        let s = bsdf_sample(&m, n, wo, u2(i, 3), true);
        assert!(s.pdf > 0.0);
        let w = s.f * s.wi.dot(n).abs() / s.pdf;
        assert!((w - Vec3::splat(0.6)).abs().max_element() < 1e-4, "{w}");
        assert!(s.wi.dot(n) * wo.dot(n) > 0.0, "reflection stays on the side of wo");
    }
}

#[test]
fn bsdfs_are_reciprocal_and_reflect_only() {
    for m in [lambert(0.5), phong(10.0), phong(1000.0)] {
        for i in 0..500 {
            let n = Vec3::new(0.3, 0.9, -0.1).normalize();
            let wo = cosine_hemisphere(n, u2(i, 4));
            let wi = cosine_hemisphere(n, u2(i, 5));
            let a = bsdf_eval(&m, n, wo, wi);
            let b = bsdf_eval(&m, n, wi, wo);
            assert!((a - b).abs().max_element() <= 1e-5 * a.max_element().max(1.0));
            assert_eq!(bsdf_eval(&m, n, wo, -wi), Vec3::ZERO);
            assert_eq!(bsdf_pdf(&m, n, wo, -wi), 0.0);
        }
    }
}

/// The sampling density integrates to at most 1 over the hemisphere (less where the lobe is
/// cut off by the surface), checked by uniform sphere sampling, and the sampled directions
/// follow it: a histogram of cos α of the samples against the analytic distribution.
#[test]
fn phong_pdf_is_a_density_and_sampling_follows_it() {
    for e in [1.0f32, 10.0, 100.0] {
        let m = phong(e);
        let n = Vec3::Z;
        let wo = Vec3::new(0.0, 0.0, 1.0);
        let samples = 400_000;
        let mut integral = 0.0f64;
        for i in 0..samples {
            let u = u2(i, 6);
            let z = 1.0 - 2.0 * u.x;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = 2.0 * PI * u.y;
            let wi = Vec3::new(r * phi.cos(), r * phi.sin(), z);
            integral += (bsdf_pdf(&m, n, wo, wi) * 4.0 * PI) as f64 / samples as f64;
        }
        // wo = n: the lobe about the mirror direction n lies wholly above the surface.
        assert!((integral - 1.0).abs() < 0.02, "e = {e}: ∫pdf = {integral}");
    }
    // Histogram of cos α for exponent 1e5: P(cos α > c) = 1 − c^(n+1).
    let e = 1e5f32;
    let m = phong(e);
    let n = Vec3::Z;
    let wo = Vec3::new(0.6, 0.0, 0.8);
    let r = Vec3::new(-0.6, 0.0, 0.8);
    let samples = 100_000;
    let mut below_median = 0;
    let median_delta = 1.0 - (0.5f64).powf(1.0 / (e as f64 + 1.0)); // 1 − cos α at the median
    for i in 0..samples {
        let s = bsdf_sample(&m, n, wo, u2(i, 7), true);
        assert!(s.pdf > 0.0 && s.pdf.is_finite() && s.f.is_finite());
        let delta = (r - s.wi).length_squared() as f64 * 0.5;
        if delta < median_delta {
            below_median += 1;
        }
    }
    let share = below_median as f64 / samples as f64;
    assert!((share - 0.5).abs() < 0.01, "median of the 1e5 lobe: {share}");
}

/// Exponent 1e5 at grazing angles: values stay finite, and f·cos/pdf = ρ (n+2)/(n+1) cos θi.
#[test]
fn phong_1e5_at_grazing_angles_is_finite_and_consistent() {
    let e = 1e5f32;
    let m = phong(e);
    let n = Vec3::Y;
    for cos_o in [1e-4f32, 1e-3, 0.01, 0.1] {
        let wo = Vec3::new((1.0 - cos_o * cos_o).sqrt(), cos_o, 0.0);
        let mut ok = 0;
        for i in 0..10_000 {
            let s = bsdf_sample(&m, n, wo, u2(i, 8), true);
            if s.pdf == 0.0 {
                continue; // sampled below the surface: a failed sample, not an error
            }
            ok += 1;
            assert!(s.f.is_finite() && s.pdf.is_finite());
            let w = s.f.x * s.wi.dot(n) / s.pdf;
            let expected = 0.8 * (e + 2.0) / (e + 1.0) * s.wi.dot(n);
            assert!((w - expected).abs() <= 1e-3 * expected.max(1e-6), "cos_o {cos_o}: {w} vs {expected}");
        }
        assert!(ok > 1000, "cos_o {cos_o}: only {ok} samples above the surface");
    }
    // The peak value is large but finite.
    let wo = Vec3::new(0.0, 1.0, 0.0);
    let f = bsdf_eval(&m, n, wo, wo);
    assert!(f.is_finite() && f.x > 1e4);
}

fn glass(t: f32, solid: bool) -> Material {
    Material {
        albedo: [1.0; 3],
        transmission: t,
        ior: 1.5,
        thin_walled: u32::from(!solid),
        ..Default::default()
    }
}

/// Fresnel against the textbook values, computed here in f64 from the s- and p-polarised
/// amplitudes: 4 % at normal incidence into glass, nothing polarised in the plane of incidence
/// at Brewster's angle, and total internal reflection beyond the critical angle.
#[test]
fn fresnel_matches_the_textbook() {
    let reference = |cos_i: f64, eta: f64| {
        let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
        if sin2_t >= 1.0 {
            return 1.0;
        }
        let cos_t = (1.0 - sin2_t).sqrt();
        let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
        let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
        0.5 * (rs * rs + rp * rp)
    };
    assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
    let brewster = 1.5f64.atan();
    let cos_b = brewster.cos();
    let sin_t = brewster.sin() / 1.5;
    let rs = (cos_b - 1.5 * (1.0 - sin_t * sin_t).sqrt()) / (cos_b + 1.5 * (1.0 - sin_t * sin_t).sqrt());
    assert!((fresnel_dielectric(cos_b as f32, 1.5) as f64 - 0.5 * rs * rs).abs() < 1e-6, "Brewster");
    assert_eq!(fresnel_dielectric(0.5, 1.0 / 1.5), 1.0, "beyond the critical angle");
    for k in 1..=20 {
        let c = k as f64 / 20.0;
        for eta in [1.5, 1.0 / 1.5, 1.33, 2.4] {
            assert!((fresnel_dielectric(c as f32, eta as f32) as f64 - reference(c, eta)).abs() < 1e-5);
        }
    }
}

/// Refraction follows Snell's law and is reversible: refracting back from the other side
/// returns the original direction.
#[test]
fn refraction_follows_snell_and_reverses() {
    let n = Vec3::new(0.2, 1.0, -0.1).normalize();
    for i in 0..1000 {
        let wo = cosine_hemisphere(n, u2(i, 30));
        let wi = refract(wo, n, 1.5).expect("entering never reflects totally");
        let sin_o = (1.0 - n.dot(wo).powi(2)).max(0.0).sqrt();
        let sin_i = (1.0 - n.dot(wi).powi(2)).max(0.0).sqrt();
        assert!((sin_o - 1.5 * sin_i).abs() < 1e-4, "Snell: {sin_o} vs 1.5 · {sin_i}");
        assert!(n.dot(wi) < 0.0 && (-wo).cross(n).dot(wi.cross(n)) >= -1e-5, "on through, in the plane");
        let back = refract(wi, -n, 1.0 / 1.5).expect("the way back is open");
        assert!((back - wo).length() < 1e-3, "{back} vs {wo}");
    }
}

/// Lossless white glass conserves energy sample by sample: in importance transport (light
/// subpaths, the adjoint) every sample's weight is 1, mirror or refraction; in radiance
/// transport a refraction scales by 1/η² (η the index of the side entered relative to the
/// side left), a mirror by 1. The mirror is taken with the Fresnel probability, and eval and
/// pdf see no delta lobe; a thin wall passes straight through with weight 1.
#[test]
fn glass_conserves_energy_and_mirrors_by_fresnel() {
    let n = Vec3::Y;
    for solid in [true, false] {
        let m = glass(1.0, solid);
        for (k, wo) in
            [Vec3::new(0.3, 0.8, 0.1), Vec3::new(0.6, -0.3, 0.2), Vec3::new(0.0, 1.0, 0.0)].iter().enumerate()
        {
            let wo = wo.normalize();
            let eta = relative_ior(&m, n, wo);
            let f_r = fresnel_dielectric(wo.dot(n).abs(), eta) as f64;
            let trials = 20_000;
            let mut mirrored = 0;
            for i in 0..trials {
                for radiance in [false, true] {
                    let s = bsdf_sample(&m, n, wo, u2(i, 31 + k as u32), radiance);
                    assert!(s.delta && s.pdf > 0.0);
                    let w = s.f * s.wi.dot(n).abs() / s.pdf;
                    let is_mirror = s.wi.dot(n) * wo.dot(n) > 0.0;
                    let expected = if is_mirror || !solid || !radiance { 1.0 } else { 1.0 / (eta * eta) };
                    assert!((w - Vec3::splat(expected)).abs().max_element() < 1e-4, "{w} vs {expected}");
                    if !solid && !is_mirror {
                        assert!((s.wi + wo).length() < 1e-6, "a thin wall does not bend light");
                    }
                    if !radiance && is_mirror {
                        mirrored += 1;
                    }
                    assert_eq!(bsdf_eval(&m, n, wo, s.wi), Vec3::ZERO);
                    assert_eq!(bsdf_pdf(&m, n, wo, s.wi), 0.0);
                }
            }
            let share = mirrored as f64 / trials as f64;
            let se = (f_r * (1.0 - f_r) / trials as f64).sqrt();
            assert!((share - f_r).abs() <= 4.0 * se + 1e-9, "mirror share {share} vs F = {f_r}");
        }
    }
}

/// A partly transmissive material is the dielectric on its share and Lambertian on the rest:
/// the expected weight is (1 − t) ρ + t in importance transport, and the diffuse samples are
/// the ones eval and pdf see.
#[test]
fn partial_transmission_mixes_glass_and_lambert() {
    let m = Material { albedo: [0.6; 3], transmission: 0.25, ior: 1.5, thin_walled: 0, ..Default::default() };
    let n = Vec3::Y;
    let wo = Vec3::new(0.2, 0.9, 0.1).normalize();
    let trials = 100_000;
    let mut sum = 0.0f64;
    let mut diffuse = 0;
    for i in 0..trials {
        let s = bsdf_sample(&m, n, wo, u2(i, 40), false);
        let w = s.f * s.wi.dot(n).abs() / s.pdf;
        if !s.delta {
            diffuse += 1;
            assert!((s.pdf - bsdf_pdf(&m, n, wo, s.wi)).abs() < 1e-6);
            assert!((s.f - bsdf_eval(&m, n, wo, s.wi)).abs().max_element() < 1e-6);
        }
        sum += w.x as f64;
    }
    let mean = sum / trials as f64;
    // The glass part reflects white and transmits its 0.6 tint: t (F + (1 − F) 0.6).
    let f_r = fresnel_dielectric(wo.dot(n), 1.5) as f64;
    let expected = 0.75 * 0.6 + 0.25 * (f_r + (1.0 - f_r) * 0.6);
    assert!((mean - expected).abs() < 0.01, "{mean} vs {expected}");
    assert!((diffuse as f64 / trials as f64 - 0.75).abs() < 0.01);
}
