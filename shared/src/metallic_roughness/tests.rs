use super::*;
use crate::testing::{dir, u2};
use std::f64::consts::PI as PI64;

fn brdf(base: f32, metallic: f32, roughness: f32) -> MetallicRoughness {
    MetallicRoughness::new(
        Vec3::new(base, base * 0.8, base * 0.5),
        metallic,
        Vec2::splat(roughness * roughness),
        1.5,
        1.0,
        Vec3::ONE,
    )
}

/// The grid of the sampling tests: roughness × metallic × angle of incidence.
fn cases() -> Vec<(MetallicRoughness, Vec3)> {
    let mut cases = Vec::new();
    for roughness in [0.2f32, 0.5, 1.0] {
        for metallic in [0.0f32, 0.5, 1.0] {
            for c in [1.0f32, 0.6, 0.15] {
                cases.push((brdf(0.8, metallic, roughness), dir(c, 0.3)));
            }
        }
    }
    // Anisotropic (KHR_materials_anisotropy), the wide axis along x and along y.
    for (alpha, metallic) in [(Vec2::new(0.6, 0.05), 1.0f32), (Vec2::new(0.1, 0.5), 0.0)] {
        for c in [0.9f32, 0.3] {
            let b = MetallicRoughness { alpha, ..brdf(0.8, metallic, 0.5) };
            cases.push((b, dir(c, 0.7)));
        }
    }
    cases
}

/// The spec's Appendix B written out independently, in f64: its V_GGX (the height-correlated
/// Smith visibility in its closed form), D_GGX, Schlick's Fresnel and the mixes.
fn spec_reference(base: [f64; 3], metallic: f64, alpha: f64, wo: Vec3, wi: Vec3) -> [f64; 3] {
    let (v, l) = (wo.as_dvec3(), wi.as_dvec3());
    let h = (v + l).normalize();
    let (n_v, n_l, n_h, v_h) = (v.z, l.z, h.z, v.dot(h));
    let a2 = alpha * alpha;
    let vis = 0.5 / (n_l * (n_v * n_v * (1.0 - a2) + a2).sqrt() + n_v * (n_l * n_l * (1.0 - a2) + a2).sqrt());
    let d = a2 / (PI64 * (n_h * n_h * (a2 - 1.0) + 1.0).powi(2));
    let specular = vis * d;
    let w = (1.0 - v_h).powi(5);
    base.map(|c| {
        let f_metal = c + (1.0 - c) * w;
        let f_dielectric = 0.04 + 0.96 * w;
        let dielectric = (1.0 - f_dielectric) * c / PI64 + f_dielectric * specular;
        (1.0 - metallic) * dielectric + metallic * f_metal * specular
    })
}

/// eval equals the spec's formulas, computed independently, at a few angles.
#[test]
fn eval_matches_the_spec_at_reference_angles() {
    for (metallic, roughness) in [(0.0f32, 0.5f32), (1.0, 0.3), (0.4, 0.8), (0.0, 1.0)] {
        let b = brdf(0.7, metallic, roughness);
        for (wo, wi) in [
            (dir(1.0, 0.0), dir(1.0, 0.0)),
            (dir(0.8, 0.0), dir(0.8, PI)),
            (dir(0.5, 0.2), dir(0.9, 2.0)),
            (dir(0.2, 1.0), dir(0.3, -1.5)),
        ] {
            let f = eval(&b, wo, wi);
            let r = spec_reference(b.base.as_dvec3().to_array(), metallic as f64, b.alpha.x as f64, wo, wi);
            for k in 0..3 {
                assert!(
                    (f[k] as f64 - r[k]).abs() <= 1e-4 * r[k].abs() + 1e-7,
                    "metallic {metallic} roughness {roughness}: {f} vs {r:?}"
                );
            }
        }
    }
}

/// Without a metal and with specularFactor 0 the BRDF is exactly Lambert, sampled by cosine.
#[test]
fn no_specular_layer_is_exactly_lambert() {
    let b = MetallicRoughness::new(Vec3::splat(0.6), 0.0, Vec2::splat(0.25), 1.5, 0.0, Vec3::ONE);
    assert!(b.is_lambertian() && !b.has_mirror());
    assert_eq!(specular_probability(&b, 0.7), 0.0);
    for i in 0..100 {
        let wo = dir(0.1 + 0.009 * i as f32, 0.1 * i as f32);
        let s = sample(&b, wo, u2(i, 1));
        assert!(s.found && !s.delta);
        assert_eq!(eval(&b, wo, s.wi), Vec3::splat(0.6 / PI));
        assert!((pdf(&b, wo, s.wi) - s.wi.z / PI).abs() < 1e-7);
    }
    // KHR_materials_specular's colour scales the layer's normal reflectance, capped at 1.
    let tinted =
        MetallicRoughness::new(Vec3::ONE, 0.0, Vec2::splat(0.25), 1.5, 0.5, Vec3::new(2.0, 1.0, 0.0));
    assert!((tinted.f0 - Vec3::new(0.04, 0.02, 0.0)).abs().max_element() < 1e-7, "{}", tinted.f0);
    assert_eq!(tinted.f90, 0.5);
    assert!((f0_from_ior(1.5) - 0.04).abs() < 1e-7);
}

/// The BRDF is reciprocal, and zero below the surface.
#[test]
fn eval_is_reciprocal() {
    for (b, _) in cases() {
        for i in 0..400 {
            let (a, c) = (u2(i, 2), u2(i, 3));
            let wo = dir(a.x, a.y * 2.0 * PI);
            let wi = dir(c.x, c.y * 2.0 * PI);
            let (f, g) = (eval(&b, wo, wi), eval(&b, wi, wo));
            assert!((f - g).abs().max_element() <= 1e-4 * f.max_element(), "{f} vs {g}");
            assert_eq!(eval(&b, wo, Vec3::new(wi.x, wi.y, -wi.z)), Vec3::ZERO);
        }
    }
}

/// A sample reports a direction that eval and pdf see; the density integrates over the
/// hemisphere to the share of samples that succeed (a reflection below the surface fails).
#[test]
fn samples_match_their_density() {
    for (b, wo) in cases() {
        let trials = 20_000;
        let mut found = 0;
        for i in 0..trials {
            let s = sample(&b, wo, u2(i, 4));
            if !s.found {
                continue;
            }
            found += 1;
            assert!(!s.delta && s.wi.z > 0.0 && pdf(&b, wo, s.wi) > 0.0);
        }
        // The midpoint rule on a grid fine enough for the narrowest lobe (α 0.04, about 2°).
        let (nt, np) = (3000, 1080);
        let mut integral = 0.0f64;
        for i in 0..nt {
            let c = (i as f64 + 0.5) / nt as f64;
            for j in 0..np {
                let phi = 2.0 * PI64 * (j as f64 + 0.5) / np as f64;
                let wi = dir(c as f32, phi as f32);
                integral += pdf(&b, wo, wi) as f64 * (1.0 / nt as f64) * (2.0 * PI64 / np as f64);
            }
        }
        let share = found as f64 / trials as f64;
        assert!(integral <= 1.0 + 5e-3, "{b:?} wo {wo}: ∫ pdf = {integral}");
        assert!((integral - share).abs() < 0.015, "{b:?} wo {wo}: ∫ pdf = {integral}, {share} succeed");
    }
}

/// χ² of the sampled directions against the density over 16 × 12 bins uniform in cos θ and φ,
/// for every (roughness, metallic, angle) of the grid.
#[test]
fn sampling_follows_the_density() {
    for (b, wo) in cases() {
        let samples = 100_000u32;
        let (nc, np) = (16usize, 12usize);
        let mut counts = vec![0u32; nc * np];
        for i in 0..samples {
            let s = sample(&b, wo, u2(i, 5));
            if s.found {
                let phi = s.wi.y.atan2(s.wi.x) + PI;
                let ci = (s.wi.z * nc as f32).clamp(0.0, nc as f32 - 0.001) as usize;
                let pj = (phi / (2.0 * PI) * np as f32).clamp(0.0, np as f32 - 0.001) as usize;
                counts[ci * np + pj] += 1;
            }
        }
        let (mut chi2, mut bins) = (0.0f64, 0);
        for ci in 0..nc {
            for pj in 0..np {
                let k = 48;
                let mut p = 0.0f64;
                for a in 0..k {
                    for bb in 0..k {
                        let c = (ci as f64 + (a as f64 + 0.5) / k as f64) / nc as f64;
                        let phi = 2.0 * PI64 * (pj as f64 + (bb as f64 + 0.5) / k as f64) / np as f64 - PI64;
                        let cell = (1.0 / nc as f64 / k as f64) * (2.0 * PI64 / np as f64 / k as f64);
                        p += pdf(&b, wo, dir(c as f32, phi as f32)) as f64 * cell;
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
        assert!(chi2 < dof + 5.0 * (2.0 * dof).sqrt(), "{b:?} wo {wo}: χ² {chi2} over {dof} dof");
    }
}

/// A white furnace. The metal reflects at most what arrives (single scattering loses what
/// bounces between facets, most at high roughness), nearly all of it when smooth-ish. The
/// spec's dielectric is not energy-conserving: its diffuse lobe is weighted by 1 − F(wo·h), not
/// by what the layer reflects, so near grazing a white one returns more than arrives (1.20 at
/// roughness 0.3 and cos θ_o 0.2, by quadrature of the spec's formulas); there the estimate by
/// this BRDF's own sampling must equal the quadrature of [`spec_reference`].
#[test]
fn energy_is_the_specs() {
    for roughness in [0.05f32, 0.3, 0.7, 1.0] {
        for metallic in [0.0f32, 1.0] {
            let b = MetallicRoughness::new(
                Vec3::ONE,
                metallic,
                Vec2::splat(roughness * roughness),
                1.5,
                1.0,
                Vec3::ONE,
            );
            for c in [1.0f32, 0.5, 0.2] {
                let wo = dir(c, 0.0);
                let trials = 40_000;
                let mut albedo = 0.0f64;
                for i in 0..trials {
                    let s = sample(&b, wo, u2(i, 6));
                    if s.found {
                        albedo += (eval(&b, wo, s.wi).x * s.wi.z / pdf(&b, wo, s.wi)) as f64;
                    }
                }
                let albedo = albedo / trials as f64;
                if metallic == 1.0 {
                    assert!(albedo <= 1.0 + 0.01, "roughness {roughness} metal, cos {c}: {albedo}");
                    if roughness <= 0.3 && c >= 0.5 {
                        assert!(albedo > 0.95, "roughness {roughness} metal, cos {c}: {albedo}");
                    }
                }
                if roughness >= 0.3 {
                    // The midpoint rule over the hemisphere, 0.03 in cos θ and 0.25° in φ.
                    let (nt, np) = (2000, 1440);
                    let mut independent = 0.0f64;
                    for i in 0..nt {
                        let cos_i = (i as f64 + 0.5) / nt as f64;
                        for j in 0..np {
                            let wi = dir(cos_i as f32, (2.0 * PI64 * (j as f64 + 0.5) / np as f64) as f32);
                            let f = spec_reference([1.0; 3], metallic as f64, b.alpha.x as f64, wo, wi)[0];
                            independent += f * cos_i / nt as f64 * 2.0 * PI64 / np as f64;
                        }
                    }
                    assert!(
                        (albedo - independent).abs() < 0.02 * independent,
                        "roughness {roughness} metallic {metallic} cos {c}: {albedo} vs the spec's {independent}"
                    );
                }
            }
        }
    }
}

/// A smooth specular lobe is a mirror: sampled as a delta of the lobe's probability and
/// Fresnel weight, never seen by eval and pdf; the diffuse rest is still there.
#[test]
fn a_smooth_lobe_is_a_mirror() {
    let b = brdf(0.5, 0.3, 0.0);
    assert!(b.has_mirror());
    let wo = dir(0.6, 0.4);
    let p = specular_probability(&b, wo.z);
    assert!(p > 0.0 && p < 1.0);
    let (mut mirrors, mut weight) = (0, Vec3::ZERO);
    let trials = 20_000;
    for i in 0..trials {
        let s = sample(&b, wo, u2(i, 7));
        if s.delta {
            mirrors += 1;
            assert_eq!((s.wi.z, s.pdf), (wo.z, p));
            assert!((s.wi.x + wo.x).abs() < 1e-6 && (s.wi.y + wo.y).abs() < 1e-6);
            weight += s.f / s.pdf;
        } else if s.found {
            weight += eval(&b, wo, s.wi) * s.wi.z / pdf(&b, wo, s.wi);
        }
    }
    assert!((mirrors as f32 / trials as f32 - p).abs() < 0.01);
    let weight = weight / trials as f32;
    // The mirror reflects F(cos θ_o) of the light; the diffuse lobe what the layer lets through.
    let expected_mirror = b.specular_fresnel(wo.z);
    assert!(weight.x > expected_mirror.x && weight.x < expected_mirror.x + b.base.x * 0.7 + 0.01, "{weight}");
    assert_eq!(eval(&b, wo, Vec3::new(-wo.x, -wo.y, wo.z)), b.diffuse_weight(wo.z) / PI);
}
