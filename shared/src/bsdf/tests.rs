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
        let s = bsdf_sample(&m, n, wo, u2(i, 3));
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
        let s = bsdf_sample(&m, n, wo, u2(i, 7));
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
            let s = bsdf_sample(&m, n, wo, u2(i, 8));
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
