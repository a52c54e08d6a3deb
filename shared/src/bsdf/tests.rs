use super::*;
use crate::testing::u2;

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
        let s = bsdf_sample(&m, Normals::flat(n), wo, u2(i, 3), true);
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
            let a = bsdf_eval(&m, Normals::flat(n), wo, wi, true);
            let b = bsdf_eval(&m, Normals::flat(n), wi, wo, true);
            assert!((a - b).abs().max_element() <= 1e-5 * a.max_element().max(1.0));
            assert_eq!(bsdf_eval(&m, Normals::flat(n), wo, -wi, true), Vec3::ZERO);
            assert_eq!(bsdf_pdf(&m, Normals::flat(n), wo, -wi), 0.0);
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
            integral += (bsdf_pdf(&m, Normals::flat(n), wo, wi) * 4.0 * PI) as f64 / samples as f64;
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
        let s = bsdf_sample(&m, Normals::flat(n), wo, u2(i, 7), true);
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
            let s = bsdf_sample(&m, Normals::flat(n), wo, u2(i, 8), true);
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
    let f = bsdf_eval(&m, Normals::flat(n), wo, wo, true);
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
                    let s = bsdf_sample(&m, Normals::flat(n), wo, u2(i, 31 + k as u32), radiance);
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
                    assert_eq!(bsdf_eval(&m, Normals::flat(n), wo, s.wi, radiance), Vec3::ZERO);
                    assert_eq!(bsdf_pdf(&m, Normals::flat(n), wo, s.wi), 0.0);
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
        let s = bsdf_sample(&m, Normals::flat(n), wo, u2(i, 40), false);
        let w = s.f * s.wi.dot(n).abs() / s.pdf;
        if !s.delta {
            diffuse += 1;
            assert!((s.pdf - bsdf_pdf(&m, Normals::flat(n), wo, s.wi)).abs() < 1e-6);
            assert!((s.f - bsdf_eval(&m, Normals::flat(n), wo, s.wi, false)).abs().max_element() < 1e-6);
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

fn rough_glass(alpha: f32, t: f32) -> Material {
    Material { alpha, ..glass(t, true) }
}

/// A rough thin wall (no `KHR_materials_volume`): its transmission is its reflection lobe seen
/// through the plane.
fn rough_thin(alpha: f32, t: f32) -> Material {
    Material { alpha, ..glass(t, false) }
}

/// The directions of a rough dielectric's test: from outside (n = +Y side) and from inside,
/// at normal, oblique and grazing incidence.
fn rough_cases() -> Vec<(f32, Vec3)> {
    let mut cases = Vec::new();
    for alpha in [0.05f32, 0.25, 0.7] {
        for (y, x) in [(1.0f32, 0.0f32), (0.6, 0.8), (0.15, 0.99), (-0.9, 0.44), (-0.3, 0.95)] {
            cases.push((alpha, Vec3::new(x, y, 0.1).normalize()));
        }
    }
    cases
}

/// A rough dielectric's samples (a solid's and a thin wall's) report what eval and pdf give for
/// their direction, are never deltas, reflect on wo's side or transmit to the other, and the
/// density integrates to the share of samples that succeed (the rest failed: a refraction
/// beyond the critical angle of its micro-normal, a reflection below the surface), checked by
/// quadrature over the sphere.
#[test]
fn rough_dielectric_samples_match_eval_and_pdf() {
    let n = Vec3::Y;
    let cases = rough_cases()
        .into_iter()
        .flat_map(|(alpha, wo)| [(rough_glass(alpha, 1.0), wo), (rough_thin(alpha, 1.0), wo)]);
    // Anisotropic (strength 0.8 turned 0.6 rad from an arbitrary frame's x: the lobe's density
    // does not depend on which).
    let turned = [0.8 * 0.6f32.cos(), 0.8 * 0.6f32.sin()];
    let anisotropic = rough_cases()
        .into_iter()
        .filter(|(alpha, _)| *alpha == 0.25)
        .map(|(alpha, wo)| (Material { anisotropy: turned, ..rough_glass(alpha, 1.0) }, wo));
    for (m, wo) in cases.chain(anisotropic) {
        let alpha = m.alphas();
        let trials = 20_000;
        let mut ok = 0;
        for i in 0..trials {
            for radiance in [true, false] {
                let s = bsdf_sample(&m, Normals::flat(n), wo, u2(i, 50), radiance);
                if !(s.pdf > 0.0) {
                    continue;
                }
                ok += usize::from(radiance);
                assert!(!s.delta);
                let (pdf, f) = (
                    bsdf_pdf(&m, Normals::flat(n), wo, s.wi),
                    bsdf_eval(&m, Normals::flat(n), wo, s.wi, radiance),
                );
                assert!((s.pdf - pdf).abs() <= 1e-3 * pdf, "α {alpha} wo {wo}: pdf {} vs {pdf}", s.pdf);
                assert!((s.f - f).abs().max_element() <= 1e-3 * f.max_element(), "{} vs {f}", s.f);
            }
        }
        // ∫ pdf over the sphere, by the midpoint rule on a grid fine enough for the narrowest
        // lobe (α 0.05, about 3°) wherever it lies: 0.03° in θ at the horizon, 0.5° in φ.
        let (nt, np) = (4000, 720);
        let mut integral = 0.0f64;
        let (t, b) = orthonormal_basis(n);
        for i in 0..nt {
            let c = (i as f64 + 0.5) / nt as f64 * 2.0 - 1.0;
            let dc = 2.0 / nt as f64;
            let s = (1.0 - c * c).max(0.0).sqrt();
            for j in 0..np {
                let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / np as f64;
                let wi = (t * (s * phi.cos()) as f32 + b * (s * phi.sin()) as f32 + n * c as f32).normalize();
                integral += bsdf_pdf(&m, Normals::flat(n), wo, wi) as f64 * dc * 2.0 * std::f64::consts::PI
                    / np as f64;
            }
        }
        let share = ok as f64 / trials as f64;
        assert!(integral <= 1.0 + 5e-3, "α {alpha} wo {wo}: ∫ pdf = {integral}");
        assert!((integral - share).abs() < 0.02, "α {alpha} wo {wo}: ∫ pdf = {integral}, {share} succeed");
    }
}

/// χ² of a rough dielectric's (a solid's, a thin wall's) sampled directions against its density, over 20 × 12 bins
/// uniform in cos θ about n (both hemispheres) and φ, the bins' probabilities by a midpoint
/// rule inside each.
#[test]
fn rough_dielectric_sampling_follows_its_density() {
    let n = Vec3::Y;
    let (t, b) = orthonormal_basis(n);
    let thin = |alpha, wo| (rough_thin(alpha, 1.0), alpha, wo);
    for (m, alpha, wo) in [
        (rough_glass(0.25, 1.0), 0.25f32, Vec3::new(0.6, 0.8, 0.0)),
        (rough_glass(0.7, 1.0), 0.7, Vec3::new(0.9, -0.4, 0.1).normalize()),
        thin(0.25, Vec3::new(0.6, 0.8, 0.0)),
        thin(0.7, Vec3::new(0.9, -0.4, 0.1).normalize()),
    ] {
        let samples = 200_000u32;
        let (nc, np) = (20usize, 12usize);
        let mut counts = vec![0u32; nc * np];
        for i in 0..samples {
            let s = bsdf_sample(&m, Normals::flat(n), wo, u2(i, 60), true);
            if s.pdf > 0.0 {
                let c = s.wi.dot(n);
                let phi = s.wi.dot(b).atan2(s.wi.dot(t)) + PI;
                let ci = (((c + 1.0) * 0.5) * nc as f32).clamp(0.0, nc as f32 - 0.001) as usize;
                let pj = (phi / (2.0 * PI) * np as f32).clamp(0.0, np as f32 - 0.001) as usize;
                counts[ci * np + pj] += 1;
            }
        }
        let mut chi2 = 0.0f64;
        let mut bins = 0;
        for ci in 0..nc {
            for pj in 0..np {
                let mut p = 0.0f64;
                let k = 24;
                for a in 0..k {
                    for bb in 0..k {
                        let c = -1.0 + 2.0 * (ci as f64 + (a as f64 + 0.5) / k as f64) / nc as f64;
                        let phi = 2.0 * std::f64::consts::PI * (pj as f64 + (bb as f64 + 0.5) / k as f64)
                            / np as f64
                            - std::f64::consts::PI;
                        let s = (1.0 - c * c).max(0.0).sqrt();
                        let wi = (t * (s * phi.cos()) as f32 + b * (s * phi.sin()) as f32 + n * c as f32)
                            .normalize();
                        let cell = (2.0 / nc as f64 / k as f64)
                            * (2.0 * std::f64::consts::PI / np as f64 / k as f64);
                        p += bsdf_pdf(&m, Normals::flat(n), wo, wi) as f64 * cell;
                    }
                }
                let expected = p * samples as f64;
                if expected > 10.0 {
                    chi2 += (counts[ci * np + pj] as f64 - expected).powi(2) / expected;
                    bins += 1;
                }
            }
        }
        let dof = (bins - 1) as f64;
        assert!(chi2 < dof + 5.0 * (2.0 * dof).sqrt(), "α {alpha} wo {wo}: χ² {chi2} over {dof} dof");
    }
}

/// The adjoint is the transpose: f for importance from wo to wi is f for radiance from wi to
/// wo (Veach's §5.2), on reflection and transmission pairs alike, solid or thin; and a lossless rough glass
/// scatters at most what arrives — close to all of it when smooth-ish (single scattering loses
/// what bounces between micro-facets), less in radiance by 1/η² entering.
#[test]
fn rough_dielectric_adjoint_and_energy() {
    let n = Vec3::Y;
    for (m, (alpha, wo)) in
        rough_cases().into_iter().flat_map(|c| [(rough_glass(c.0, 1.0), c), (rough_thin(c.0, 1.0), c)])
    {
        for i in 0..2000 {
            let wi = crate::punctual::uniform_sphere(u2(i, 70));
            let a = bsdf_eval(&m, Normals::flat(n), wo, wi, false);
            let b = bsdf_eval(&m, Normals::flat(n), wi, wo, true);
            // Within f32's reach of the Fresnel factor where a micro-normal's refraction grazes.
            let scale = a.max_element().max(b.max_element());
            assert!((a - b).abs().max_element() <= 2e-3 * scale + 1e-5, "α {alpha}: {a} vs {b}");
        }
        let trials = 40_000;
        let mut albedo = 0.0f64;
        for i in 0..trials {
            let s = bsdf_sample(&m, Normals::flat(n), wo, u2(i, 71), false);
            if s.pdf > 0.0 {
                albedo += (s.f.x * s.wi.dot(n).abs() / s.pdf) as f64;
            }
        }
        let albedo = albedo / trials as f64;
        assert!(albedo <= 1.0 + 0.01, "α {alpha} wo {wo}: albedo {albedo}");
        if alpha <= 0.05 && wo.y.abs() > 0.5 {
            assert!(albedo > 0.97, "α {alpha} wo {wo}: albedo {albedo}");
        }
    }
}

/// A rough thin wall's transmission is its reflection lobe through the plane, as
/// `KHR_materials_transmission` defines it: f(wo, wi) for wi below is the tint × (1 − F) share of
/// the GGX reflection f(wo, wi') (wi' = wi mirrored), F the Fresnel factor at wo·m; light passes
/// unbent on average (a narrow lobe about −wo); and a smooth thin wall stays a delta.
#[test]
fn a_rough_thin_wall_passes_its_reflection_lobe_through() {
    let n = Vec3::Z;
    let m = Material { albedo: [0.9, 0.6, 0.3], ..rough_thin(0.2, 1.0) };
    assert!(m.is_rough_dielectric() && !m.has_delta_lobe());
    assert!(rough_thin(SMOOTH_ALPHA * 0.5, 1.0).has_delta_lobe());
    for (i, wo) in
        [Vec3::new(0.3, 0.1, 0.9), Vec3::new(-0.7, 0.2, 0.3), Vec3::new(0.1, 0.0, -0.8)].iter().enumerate()
    {
        let wo = wo.normalize();
        let side = wo.z.signum();
        for k in 0..200 {
            let wi = crate::punctual::uniform_sphere(u2(k, 80 + i as u32));
            if wi.z * side >= 0.0 {
                continue;
            }
            // In the frame of the side wo lies on.
            let (wo_l, wi_l) = (wo * side, wi * side);
            let h = (wo_l + mirrored(wi_l)).normalize();
            let f_fresnel = fresnel_dielectric(wo_l.dot(h), 1.5);
            let reflected = crate::microfacet::ggx_d(Vec2::splat(0.2), h)
                * crate::microfacet::smith_g(Vec2::splat(0.2), wo_l, mirrored(wi_l))
                / (4.0 * wo_l.z * wi_l.z).abs();
            let expected = Vec3::new(0.9, 0.6, 0.3) * reflected * (1.0 - f_fresnel);
            for radiance in [true, false] {
                let f = bsdf_eval(&m, Normals::flat(n), wo, wi, radiance);
                assert!(
                    (f - expected).abs().max_element() <= 1e-4 * expected.max_element() + 1e-7,
                    "{f} vs {expected}"
                );
            }
        }
        // Away from grazing, its transmitted samples of a narrow lobe average to −wo: the light
        // goes on as it came (at grazing angles the lobe's shadowing and the samples below the
        // plane skew its mean).
        if wo.z.abs() < 0.5 {
            continue;
        }
        let mut mean = Vec3::ZERO;
        for k in 0..20_000 {
            let s = bsdf_sample(&rough_thin(0.05, 1.0), Normals::flat(n), wo, u2(k, 90), true);
            if s.pdf > 0.0 && s.wi.z * side < 0.0 {
                mean += s.wi;
            }
        }
        assert!((mean.normalize() - (-wo)).length() < 0.02, "{} vs {}", mean.normalize(), -wo);
    }
}

/// The Lambertian share of a partly rough glass is there on wo's side only, and the mixture's
/// samples are the ones eval and pdf see.
#[test]
fn partial_rough_transmission_mixes_with_lambert() {
    let m = Material { albedo: [0.6; 3], ..rough_glass(0.3, 0.4) };
    let n = Vec3::Y;
    let wo = Vec3::new(0.3, 0.9, 0.0).normalize();
    for i in 0..5000 {
        let s = bsdf_sample(&m, Normals::flat(n), wo, u2(i, 80), true);
        if s.pdf > 0.0 {
            assert!((s.pdf - bsdf_pdf(&m, Normals::flat(n), wo, s.wi)).abs() <= 1e-3 * s.pdf);
        }
    }
    let wi = Vec3::new(-0.2, 0.95, 0.1).normalize();
    let glass_only = bsdf_eval(&rough_glass(0.3, 0.4), Normals::flat(n), wo, wi, true);
    let diffuse = Vec3::splat(0.6 * 0.6 / PI);
    // the tint applies to transmission only: here wi reflects
    let f = bsdf_eval(&m, Normals::flat(n), wo, wi, true);
    assert!((f - (glass_only + diffuse - Vec3::splat(0.6 / PI))).abs().max_element() < 1e-5, "{f}");
}

/// The spec's mix of metal, opaque dielectric and glass: shares m, (1 − m)(1 − tr) and
/// (1 − m) tr of the whole, whatever the factors.
#[test]
fn metallic_and_transmission_mix_as_the_spec_does() {
    for (m, tr) in [(0.0, 0.0), (1.0, 0.0), (0.3, 0.0), (0.0, 1.0), (0.3, 0.6), (1.0, 1.0), (0.7, 0.25)] {
        let mat = Material::default().with_metallic(m, tr);
        let glass = mat.transmission;
        let metal = (1.0 - glass) * mat.metallic;
        let dielectric = (1.0 - glass) * (1.0 - mat.metallic);
        assert!((metal - m).abs() < 1e-6, "metal {metal} for ({m}, {tr})");
        assert!((glass - (1.0 - m) * tr).abs() < 1e-6, "glass {glass} for ({m}, {tr})");
        assert!(
            (dielectric - (1.0 - m) * (1.0 - tr)).abs() < 1e-6,
            "dielectric {dielectric} for ({m}, {tr})"
        );
    }
}

/// The materials of the shading-normal tests: Lambert, a rough metal (glTF's BRDF), a smooth
/// and a rough solid glass, a thin glass wall, and the metal and the rough glass anisotropic
/// (`KHR_materials_anisotropy`, strength 0.8 turned 40° from the tangent).
fn shading_cases() -> [Material; 7] {
    let metal = metal();
    let thin = Material { thin_walled: 1, ..glass(1.0, false) };
    let turned = [0.8 * 40f32.to_radians().cos(), 0.8 * 40f32.to_radians().sin()];
    let brushed = Material { anisotropy: turned, ..metal };
    let frosted = Material { anisotropy: turned, ..rough_glass(0.2, 1.0) };
    [lambert(0.7), metal, glass(1.0, true), rough_glass(0.2, 1.0), thin, brushed, frosted]
}

/// A rough metal (glTF's BRDF, roughness 0.3).
fn metal() -> Material {
    Material {
        albedo: [0.9, 0.6, 0.2],
        alpha: 0.09,
        metallic: 1.0,
        specular: 1.0,
        specular_color: [1.0; 3],
        ior: 1.5,
        ..Default::default()
    }
}

/// [`metal`] anisotropic: strength 0.7 along the tangent.
fn brushed() -> Material {
    Material { anisotropy: [0.7, 0.0], ..metal() }
}

/// `KHR_materials_anisotropy`'s roughnesses: mix(α, 1, s²) along the direction, α across it;
/// none without a strength; a smooth material widened along one axis keeps the other at the
/// smooth limit, and one widened too little to leave it stays a mirror.
#[test]
fn anisotropy_widens_the_roughness_along_its_direction() {
    let m = brushed();
    let a = m.alphas();
    assert!((a.x - (0.09 + 0.91 * 0.49)).abs() < 1e-6 && a.y == 0.09, "{a}");
    // The rotation does not change the roughnesses, only their direction.
    let turned = Material { anisotropy: [0.7 * 0.6, 0.7 * 0.8], ..m };
    assert!((turned.alphas() - a).abs().max_element() < 1e-6);
    assert_eq!(Material { anisotropy: [0.0; 2], ..m }.alphas(), Vec2::splat(0.09));
    let mirror = Material { alpha: 0.0, ..m };
    assert!((mirror.alphas() - Vec2::new(0.49, SMOOTH_ALPHA)).abs().max_element() < 1e-6);
    assert!(!mirror.has_delta_lobe());
    let barely = Material { alpha: 0.0, anisotropy: [0.01, 0.0], ..m };
    assert!(barely.alphas().max_element() < SMOOTH_ALPHA && barely.has_delta_lobe());
}

/// The lobes' frame: x the direction made orthogonal to the normal (the wide roughness's axis,
/// which `alphas` gives first), y = n × x, z the normal; without a direction off the normal, the
/// isotropic basis.
#[test]
fn the_lobe_frame_puts_the_direction_on_x() {
    let n = Vec3::new(0.3, 0.9, -0.1).normalize();
    let d = Vec3::new(0.2, 0.5, 1.0).normalize();
    let f = LobeFrame::new(n, d);
    let x = (d - n * n.dot(d)).normalize();
    assert!((f.x - x).length() < 1e-6 && (f.y - n.cross(x)).length() < 1e-6 && f.z == n);
    assert!((f.to_local(d).x - d.dot(x)).abs() < 1e-6 && f.to_local(d).y.abs() < 1e-6);
    assert!((f.from_local(f.to_local(d)) - d).length() < 1e-6);
    let (t, b) = orthonormal_basis(n);
    for none in [Vec3::ZERO, n, -n * 2.0, Vec3::NAN] {
        let f = LobeFrame::new(n, none);
        assert_eq!((f.x, f.y, f.z), (t, b, n), "{none}");
    }
    // The wide axis is x: a grazing wo along the direction is masked as by αx alone.
    let m = brushed();
    let wo = (x * 0.995 + n * 0.1).normalize();
    let local = f.to_local(wo);
    assert!(local.y.abs() < 1e-6 && local.x > 0.9, "{local}");
    let lambda = |a: Vec2| crate::microfacet::smith_lambda(a, local);
    let (wide, narrow) = (lambda(Vec2::splat(m.alphas().x)), lambda(Vec2::splat(m.alphas().y)));
    assert!((lambda(m.alphas()) - wide).abs() <= 1e-4 * wide && wide > 2.0 * narrow, "{wide} {narrow}");
}

/// The lobe turns with the surface's tangent: f with the tangent t equals f with −t, with t
/// plus any part along the normal, and f with the bitangent at directions turned 90° about the
/// normal. Reciprocal, and nothing below.
#[test]
fn anisotropic_lobes_follow_the_tangent() {
    let n = Vec3::new(0.3, 0.9, -0.1).normalize();
    let (t, b) = orthonormal_basis(n);
    let with = |anisotropy: Vec3| Normals { anisotropy, ..Normals::flat(n) };
    let m = brushed();
    let quarter = |w: Vec3| {
        let (x, y, z) = (w.dot(t), w.dot(b), w.dot(n));
        (b * x - t * y + n * z).normalize()
    };
    let mut differs = 0;
    for i in 0..500 {
        let wo = cosine_hemisphere(n, u2(i, 90));
        let wi = cosine_hemisphere(n, u2(i, 91));
        let f = bsdf_eval(&m, with(t), wo, wi, true);
        let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() <= 1e-4 * a.max_element().max(1e-3);
        assert!(close(f, bsdf_eval(&m, with(-t), wo, wi, true)));
        assert!(close(f, bsdf_eval(&m, with(t * 2.0 + n * 0.7), wo, wi, true)));
        assert!(close(f, bsdf_eval(&m, with(b), quarter(wo), quarter(wi), true)), "{i}");
        assert!(close(f, bsdf_eval(&m, with(t), wi, wo, true)), "reciprocal");
        assert_eq!(bsdf_eval(&m, with(t), wo, -wi, true), Vec3::ZERO);
        // Not the isotropic lobe, nor the lobe turned by the tangent's quarter.
        if !close(f, bsdf_eval(&m, with(b), wo, wi, true)) {
            differs += 1;
        }
    }
    assert!(differs > 400, "{differs} of 500 directions see the tangent");
}

/// A shading normal tilted 25° from the geometric +Y, and directions on a sphere.
fn tilted() -> (Normals, impl Fn(u32, u32) -> Vec3) {
    let ns = Vec3::new(25f32.to_radians().sin(), 25f32.to_radians().cos(), 0.0);
    let sphere = |i: u32, seed: u32| {
        let u = u2(i, seed);
        let z = 1.0 - 2.0 * u.x;
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * (2.0 * PI * u.y).cos(), r * (2.0 * PI * u.y).sin(), z)
    };
    // A tangent off the normals, for the anisotropic materials' frame.
    let n = Normals { anisotropy: Vec3::new(0.3, 0.2, 1.0), ..Normals::shaded(Vec3::Y, ns) };
    (n, sphere)
}

/// With a shading normal, the lobes are the flat BSDF's about the shading normal wherever the
/// two normals agree on both directions' sides, and 0 (f and density) wherever they do not:
/// `wo` below the shading hemisphere, or `wi` reflected by one normal and transmitted by the
/// other (a leak through the surface).
#[test]
fn shading_normals_turn_the_lobes_and_sides_follow_the_geometry() {
    let (n, sphere) = tilted();
    for m in shading_cases() {
        let (mut agreeing, mut disagreeing) = (0, 0);
        for i in 0..4000 {
            let (wo, wi) = (sphere(i, 11), sphere(i, 12));
            let g = n.facing(wo);
            let wo_ok = g.geometric.dot(wo) > 0.0 && g.shading.dot(wo) > 0.0;
            let wi_ok = (g.geometric.dot(wi) > 0.0) == (g.shading.dot(wi) > 0.0);
            let (f, pdf) = (bsdf_eval(&m, n, wo, wi, true), bsdf_pdf(&m, n, wo, wi));
            if wo_ok && wi_ok {
                agreeing += 1;
                // The flat BSDF about the shading normal (outward as the geometric one: the
                // dielectric's inside is the same side).
                let flat = Normals { anisotropy: n.anisotropy, ..Normals::flat(n.shading) };
                assert_eq!((f, pdf), (bsdf_eval(&m, flat, wo, wi, true), bsdf_pdf(&m, flat, wo, wi)));
            } else {
                disagreeing += 1;
                assert_eq!((f, pdf), (Vec3::ZERO, 0.0), "wo {wo} wi {wi}");
            }
        }
        assert!(agreeing > 1000 && disagreeing > 500, "{agreeing} {disagreeing}");
    }
}

/// Samples with a shading normal: every one lands where the normals agree, reports the f and
/// density that eval and pdf give its direction (a delta its lobe's weight), and `wo` below
/// the shading hemisphere gives none.
#[test]
fn shading_normal_samples_agree_with_eval_and_pdf() {
    let (n, sphere) = tilted();
    for m in shading_cases() {
        let mut found = 0;
        for i in 0..4000 {
            let wo = sphere(i, 13);
            let s = bsdf_sample(&m, n, wo, u2(i, 14), i % 2 == 0);
            let g = n.facing(wo);
            if !(g.geometric.dot(wo) > 0.0 && g.shading.dot(wo) > 0.0) {
                assert_eq!(s.pdf, 0.0, "wo below the shading hemisphere samples nothing");
                continue;
            }
            if !(s.pdf > 0.0) {
                continue;
            }
            found += 1;
            assert_eq!(g.geometric.dot(s.wi) > 0.0, g.shading.dot(s.wi) > 0.0, "{m:?}: {wo} → {}", s.wi);
            if !s.delta {
                let (f, pdf) = (bsdf_eval(&m, n, wo, s.wi, i % 2 == 0), bsdf_pdf(&m, n, wo, s.wi));
                assert!((s.f - f).abs().max_element() <= 1e-4 * f.max_element().max(1e-3), "{} {f}", s.f);
                assert!((s.pdf - pdf).abs() <= 1e-4 * pdf.max(1e-3), "{} {pdf}", s.pdf);
            }
        }
        assert!(found > 1000, "{m:?}: {found} samples");
    }
}

/// [`bsdf_eval_pdf`] is [`bsdf_eval`] and [`bsdf_pdf`] at once, to the bit: on the shading
/// tests' materials, a Phong lobe, a coated metal, a sheen over Lambert and a half-transmitting
/// rough glass, in both transport modes, directions all round a tilted shading normal.
#[test]
fn eval_pdf_is_eval_and_pdf_to_the_bit() {
    let (n, sphere) = tilted();
    let mut cases = shading_cases().to_vec();
    cases.extend([
        phong(50.0),
        Material { clearcoat: 0.8, clearcoat_alpha: 0.04, ..metal() },
        Material { sheen_color: [0.5, 0.4, 0.3], sheen_roughness: 0.5, ..lambert(0.5) },
        rough_glass(0.2, 0.5),
    ]);
    for m in cases {
        let mut scattering = 0;
        for i in 0..2000 {
            let (wo, wi, radiance) = (sphere(i, 15), sphere(i, 16), i % 2 == 0);
            let (f, pdf) = bsdf_eval_pdf(&m, n, wo, wi, radiance);
            let bits = |v: Vec3| v.to_array().map(f32::to_bits);
            assert_eq!(bits(f), bits(bsdf_eval(&m, n, wo, wi, radiance)), "{m:?}: f at {wo} → {wi}");
            assert_eq!(pdf.to_bits(), bsdf_pdf(&m, n, wo, wi).to_bits(), "{m:?}: pdf at {wo} → {wi}");
            scattering += usize::from(pdf > 0.0 && f.max_element() > 0.0);
        }
        // A smooth glass scatters through its delta lobes only.
        let delta_only = m.transmission == 1.0 && !m.is_rough_dielectric();
        assert_eq!(scattering == 0, delta_only, "{m:?}: {scattering} of 2000 pairs scatter");
    }
}
