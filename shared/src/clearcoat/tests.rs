use super::*;
use crate::bsdf::{bsdf_eval, bsdf_pdf, bsdf_sample, Material, Normals};
use crate::normals::scattering_cosine;
use crate::testing::{dir, sphere, u2};
use core::f32::consts::PI;
use std::f64::consts::PI as PI64;

/// White Lambert under a coat of intensity `c` and roughness `r`.
fn coated_lambert(albedo: f32, c: f32, r: f32) -> Material {
    Material { albedo: [albedo; 3], clearcoat: c, clearcoat_alpha: r * r, ..Default::default() }
}

/// The glTF BRDF (a rough red plastic) under a coat.
fn coated_plastic(c: f32, r: f32) -> Material {
    Material {
        albedo: [0.7, 0.1, 0.08],
        alpha: 0.25,
        specular: 1.0,
        specular_color: [1.0; 3],
        ior: 1.5,
        clearcoat: c,
        clearcoat_alpha: r * r,
        ..Default::default()
    }
}

/// The extension's formulas written out independently, in f64: `clearcoat_fresnel` at |V·Nc|,
/// and the spec's V_GGX (closed form) times D_GGX for the layer.
fn spec_layer(clearcoat: f64, alpha: f64, v: Vec3, l: Vec3) -> (f64, f64) {
    let (v, l) = (v.as_dvec3(), l.as_dvec3());
    let fresnel = 0.04 + (1.0 - 0.04) * (1.0 - v.z.abs()).powi(5);
    let h = (v + l).normalize();
    let (n_v, n_l, n_h) = (v.z, l.z, h.z);
    let a2 = alpha * alpha;
    let vis = 0.5 / (n_l * (n_v * n_v * (1.0 - a2) + a2).sqrt() + n_v * (n_l * n_l * (1.0 - a2) + a2).sqrt());
    let d = a2 / (PI64 * (n_h * n_h * (a2 - 1.0) + 1.0).powi(2));
    (clearcoat * fresnel, vis * d)
}

#[test]
fn fresnel_is_schlicks_of_index_1_5() {
    assert!((coat_fresnel(1.0) - 0.04).abs() < 1e-7);
    assert_eq!(coat_fresnel(0.0), 1.0);
    assert!((coat_fresnel(-0.5) - (0.04 + 0.96 * 0.5f32.powi(5))).abs() < 1e-7, "either side");
    assert!((layer_weight(0.5, 0.3) - 0.5 * (0.04 + 0.96 * 0.7f32.powi(5))).abs() < 1e-7);
    assert_eq!(probability(1.0, 0.0), MAX_PROBABILITY);
}

/// The coated material is the extension's `mix(material, clearcoat_brdf, clearcoat ·
/// clearcoat_fresnel)` at reference angles, the layer and its weight computed independently,
/// with the viewer on `wo`'s side in radiance transport and on `wi`'s in importance transport.
#[test]
fn eval_is_the_extensions_mix() {
    let n = Normals::flat(Vec3::Z);
    for (c, r) in [(1.0f32, 0.3f32), (0.5, 0.6), (0.8, 0.1)] {
        for base in [coated_lambert(0.6, c, r), coated_plastic(c, r)] {
            let bare = Material { clearcoat: 0.0, ..base };
            for (co, ci, phi) in
                [(0.9f32, 0.7f32, 2.5f32), (0.3, 0.8, 3.0), (0.6, 0.2, 1.0), (0.95, 0.95, 3.1)]
            {
                let (wo, wi) = (dir(co, 0.0), dir(ci, phi));
                for radiance in [true, false] {
                    let viewer = if radiance { wo } else { wi };
                    let (w, layer) =
                        spec_layer(c as f64, (r * r) as f64, viewer, if radiance { wi } else { wo });
                    let expected = bsdf_eval(&bare, n, wo, wi, radiance).as_dvec3() * (1.0 - w) + layer * w;
                    let f = bsdf_eval(&base, n, wo, wi, radiance).as_dvec3();
                    assert!(
                        (f - expected).abs().max_element() < 1e-4 * expected.max_element(),
                        "c {c} r {r} cos {co} {ci} radiance {radiance}: {f} vs {expected}"
                    );
                }
            }
        }
    }
}

/// The adjoint is the transpose (f for importance from wo to wi is f for radiance from wi to
/// wo), and the coat makes the material non-reciprocal, as the extension's N·V Fresnel does.
#[test]
fn the_adjoint_is_the_transpose() {
    let n = Normals::flat(Vec3::Y);
    let m = coated_plastic(1.0, 0.4);
    let mut asymmetric = 0;
    for i in 0..2000 {
        let (wo, wi) = (sphere(i, 1), sphere(i, 2));
        let a = bsdf_eval(&m, n, wo, wi, false);
        let b = bsdf_eval(&m, n, wi, wo, true);
        assert!((a - b).abs().max_element() <= 1e-5 * a.max_element().max(1e-3), "{a} vs {b}");
        let c = bsdf_eval(&m, n, wo, wi, true);
        asymmetric += usize::from((c - b).abs().max_element() > 1e-3 * c.max_element());
    }
    assert!(asymmetric > 100, "{asymmetric}");
}

/// The layer's density is one (∫ pdf over the hemisphere, by the midpoint rule, is what
/// sampling finds above the surface), and its samples follow it: χ² over 20 × 12 bins in
/// cos θ and φ.
#[test]
fn the_layers_samples_follow_its_density() {
    for (alpha, c) in [(0.09f32, 0.8f32), (0.36, 0.4), (0.7, 0.95)] {
        let wo = dir(c, 0.7);
        let samples = 200_000u32;
        let (nc, np) = (20usize, 12usize);
        let mut counts = vec![0u32; nc * np];
        let mut found = 0;
        for i in 0..samples {
            if let Some(wi) = sample(alpha, wo, u2(i, 3)) {
                found += 1;
                let phi = wi.y.atan2(wi.x) + PI;
                let ci = (wi.z * nc as f32).clamp(0.0, nc as f32 - 0.001) as usize;
                let pj = (phi / (2.0 * PI) * np as f32).clamp(0.0, np as f32 - 0.001) as usize;
                counts[ci * np + pj] += 1;
            }
        }
        let (mut chi2, mut bins, mut integral) = (0.0f64, 0, 0.0f64);
        let k = 24;
        for ci in 0..nc {
            for pj in 0..np {
                let mut p = 0.0f64;
                for a in 0..k {
                    for b in 0..k {
                        let cz = (ci as f64 + (a as f64 + 0.5) / k as f64) / nc as f64;
                        let phi = 2.0 * PI64 * (pj as f64 + (b as f64 + 0.5) / k as f64) / np as f64 - PI64;
                        let cell = (1.0 / nc as f64 / k as f64) * (2.0 * PI64 / np as f64 / k as f64);
                        p += pdf(alpha, wo, dir(cz as f32, phi as f32)) as f64 * cell;
                    }
                }
                integral += p;
                let expected = p * samples as f64;
                if expected > 10.0 {
                    chi2 += (counts[ci * np + pj] as f64 - expected).powi(2) / expected;
                    bins += 1;
                }
            }
        }
        let share = found as f64 / samples as f64;
        assert!((integral - share).abs() < 0.01, "α {alpha}: ∫ pdf {integral}, {share} found");
        let dof = (bins - 1) as f64;
        assert!(chi2 < dof + 5.0 * (2.0 * dof).sqrt(), "α {alpha}: χ² {chi2} over {dof} dof");
    }
}

/// Every sample of a coated material reports the f and density that eval and pdf give its
/// direction, in both transport modes, with shading normals too; a smooth coat's mirror has its
/// weight over its probability.
#[test]
fn coated_samples_agree_with_eval_and_pdf() {
    let ns = Vec3::new(20f32.to_radians().sin(), 20f32.to_radians().cos(), 0.0);
    for n in [Normals::flat(Vec3::Y), Normals::shaded(Vec3::Y, ns)] {
        for m in [
            coated_lambert(0.7, 1.0, 0.0),
            coated_lambert(0.7, 0.6, 0.3),
            coated_plastic(1.0, 0.0),
            coated_plastic(0.7, 0.2),
        ] {
            let (mut found, mut mirrors) = (0, 0);
            for i in 0..6000 {
                let wo = sphere(i, 4);
                let radiance = i % 2 == 0;
                let s = bsdf_sample(&m, n, wo, u2(i, 5), radiance);
                if !(s.pdf > 0.0) {
                    continue;
                }
                found += 1;
                if s.delta {
                    mirrors += 1;
                    continue;
                }
                let (f, pdf) = (bsdf_eval(&m, n, wo, s.wi, radiance), bsdf_pdf(&m, n, wo, s.wi));
                assert!((s.f - f).abs().max_element() <= 1e-4 * f.max_element().max(1e-3), "{} {f}", s.f);
                assert!((s.pdf - pdf).abs() <= 1e-4 * pdf.max(1e-3), "{} {pdf}", s.pdf);
            }
            assert!(found > 2000, "{m:?}: {found}");
            assert_eq!(mirrors > 0, m.has_delta_lobe(), "{m:?}: {mirrors} mirrors");
        }
    }
}

/// A white Lambertian base under a smooth coat reflects exactly what arrives: every sample's
/// weight f cos / pdf is 1 (the coat's mirror w / w, the base's (1 − w) / (1 − w)), in radiance
/// transport where the coat's weight is the viewer's; under a rough coat at most 1 (the GGX
/// layer loses what single scattering does).
#[test]
fn a_white_furnace_keeps_its_energy() {
    let n = Normals::flat(Vec3::Z);
    for c in [1.0f32, 0.4] {
        for cos_o in [1.0f32, 0.5, 0.1] {
            let wo = dir(cos_o, 0.2);
            let smooth = coated_lambert(1.0, c, 0.0);
            for i in 0..2000 {
                let s = bsdf_sample(&smooth, n, wo, u2(i, 6), true);
                assert!(s.pdf > 0.0);
                let weight = s.f * s.wi.z / s.pdf;
                assert!((weight - Vec3::ONE).abs().max_element() < 1e-4, "c {c} cos {cos_o}: {weight}");
            }
            let rough = coated_lambert(1.0, c, 0.5);
            let trials = 40_000;
            let mut albedo = 0.0f64;
            for i in 0..trials {
                let s = bsdf_sample(&rough, n, wo, u2(i, 7), true);
                if s.pdf > 0.0 {
                    albedo += (s.f.x * s.wi.z / s.pdf) as f64;
                }
            }
            let albedo = albedo / trials as f64;
            let w = layer_weight(c, cos_o) as f64;
            assert!(albedo <= 1.0 + 0.01 && albedo > 1.0 - w * 0.2, "c {c} cos {cos_o}: {albedo}");
        }
    }
}

/// The coat covers the transmission too: a coated glass's refraction carries (1 − w) of the
/// bare glass's, and the coat reflects where the bare glass would not.
#[test]
fn the_coat_covers_transmission() {
    let glass = Material { albedo: [1.0; 3], transmission: 1.0, ior: 1.5, ..Default::default() };
    let coated = Material { clearcoat: 1.0, clearcoat_alpha: 0.04, ..glass };
    let n = Normals::flat(Vec3::Z);
    let wo = dir(0.8, 0.0);
    let w = layer_weight(1.0, 0.8);
    let (mut bare_t, mut coated_t, mut coated_r) = (0.0f64, 0.0f64, 0.0f64);
    let trials = 40_000;
    for i in 0..trials {
        let b = bsdf_sample(&glass, n, wo, u2(i, 8), true);
        if b.pdf > 0.0 && b.wi.z < 0.0 {
            bare_t += (b.f.x * b.wi.z.abs() / b.pdf) as f64;
        }
        let s = bsdf_sample(&coated, n, wo, u2(i, 9), true);
        if s.pdf > 0.0 && s.wi.z < 0.0 {
            coated_t += (s.f.x * s.wi.z.abs() / s.pdf) as f64;
        } else if s.pdf > 0.0 && !s.delta {
            coated_r += (s.f.x * s.wi.z / s.pdf) as f64;
        }
    }
    let (bare_t, coated_t) = (bare_t / trials as f64, coated_t / trials as f64);
    assert!((coated_t - bare_t * (1.0 - w) as f64).abs() < 0.01, "{coated_t} vs {bare_t} · (1 − {w})");
    // The rough coat's reflection (the bare smooth glass reflects only as a delta): about its
    // weight at wo, less what the GGX layer's single scattering loses.
    let coated_r = coated_r / trials as f64;
    assert!(coated_r < w as f64 * 1.01 && coated_r > w as f64 * 0.8, "{coated_r} vs {w}");
}

/// Normals where the base's normal texture bent the shading normal 25° and the coat keeps the
/// geometric one (the extension's coat without its own normal texture).
fn apart() -> Normals {
    let ns = Vec3::new(25f32.to_radians().sin(), 25f32.to_radians().cos(), 0.0);
    Normals { geometric: Vec3::Y, shading: ns, coat: Vec3::Y, anisotropy: Vec3::ZERO }
}

/// With the coat's normal apart from the shading normal, the coated material is the base in
/// the shading frame under the layer in the coat's frame, its weight the coat normal's, the
/// layer's cosine the coat normal's once the callers' shading cosine multiplies it.
#[test]
fn the_layer_lies_in_the_coat_normals_frame() {
    let n = apart();
    let m = coated_plastic(1.0, 0.4);
    let bare = Material { clearcoat: 0.0, ..m };
    let (mut checked, mut differs) = (0, 0);
    for i in 0..4000 {
        let (wo, wi) = (sphere(i, 20), sphere(i, 21));
        if !(wo.y > 0.0 && n.shading.dot(wo) > 0.0 && wi.y > 0.0 && n.shading.dot(wi) > 0.0) {
            continue;
        }
        for radiance in [true, false] {
            let (v, l) = if radiance { (wo, wi) } else { (wi, wo) };
            // The layer in the coat's frame, which is the world's here (y up): (x, z, y) local.
            let local = |w: Vec3| Vec3::new(w.x, w.z, w.y);
            let (w, layer) = spec_layer(1.0, 0.16, local(v), local(l));
            let expected = bsdf_eval(&bare, n, wo, wi, radiance).as_dvec3() * (1.0 - w)
                + layer * w * (l.y as f64 / n.shading.dot(l) as f64);
            let f = bsdf_eval(&m, n, wo, wi, radiance).as_dvec3();
            assert!((f - expected).abs().max_element() < 1e-4 * expected.max_element(), "{f} vs {expected}");
            checked += 1;
            differs += usize::from(
                (f - bsdf_eval(&m, Normals::shaded(n.geometric, n.shading), wo, wi, radiance).as_dvec3())
                    .abs()
                    .max_element()
                    > 1e-3 * f.max_element(),
            );
        }
    }
    assert!(checked > 1000 && differs > checked / 2, "{checked} {differs}");
}

/// A path's contribution does not depend on the end it was traced from, with the coat's normal
/// apart from the shading normal: f times the callers' cosine over the geometric cosine of the
/// continuing direction, traced from the light (importance, light from wo) and from the camera
/// (radiance, the roles swapped), as `crate::normals`' own test asks of the shading normal.
#[test]
fn the_coat_keeps_contributions_independent_of_the_tracing_direction() {
    let n = apart();
    for m in [coated_plastic(1.0, 0.4), coated_lambert(0.6, 0.8, 0.2)] {
        let mut checked = 0;
        for i in 0..4000 {
            let (wo, wi) = (sphere(i, 22), sphere(i, 23));
            let from_light = bsdf_eval(&m, n, wo, wi, false) * scattering_cosine(n, wo, wi, false)
                / n.geometric.dot(wi).abs();
            let from_camera = bsdf_eval(&m, n, wi, wo, true) * scattering_cosine(n, wi, wo, true)
                / n.geometric.dot(wo).abs();
            let scale = from_light.max_element().max(from_camera.max_element());
            if scale > 0.0 {
                checked += 1;
                assert!(
                    (from_light - from_camera).abs().max_element() <= 1e-4 * scale,
                    "{from_light} vs {from_camera}"
                );
            }
        }
        assert!(checked > 500, "{checked}");
    }
}

/// With the coat's normal apart: a smooth coat mirrors about the coat's normal, its weight over
/// its probability the coat's weight (radiance) or that times Veach's geometric ratio
/// (importance); every other sample reports the f and density that eval and pdf give it.
#[test]
fn coat_samples_in_the_coats_frame_agree_with_eval_and_pdf() {
    let n = apart();
    for m in [coated_plastic(1.0, 0.0), coated_lambert(0.7, 0.6, 0.3)] {
        let (mut mirrors, mut others) = (0, 0);
        for i in 0..6000 {
            let wo = sphere(i, 24);
            let radiance = i % 2 == 0;
            let s = bsdf_sample(&m, n, wo, u2(i, 25), radiance);
            if !(s.pdf > 0.0) {
                continue;
            }
            let g = n.facing(wo);
            if s.delta {
                mirrors += 1;
                let mirror = 2.0 * wo.dot(g.coat) * g.coat - wo;
                assert!((s.wi - mirror).length() < 1e-5, "{} vs {mirror}", s.wi);
                let weight = s.f.x * scattering_cosine(n, wo, s.wi, radiance) / s.pdf;
                let w = layer_weight(m.clearcoat, g.coat.dot(wo));
                let expected = if radiance { w } else { w * g.geometric.dot(s.wi) / g.geometric.dot(wo) };
                assert!(
                    (weight - expected / s.pdf).abs() < 1e-4 * expected / s.pdf,
                    "{weight} vs {expected} / {}",
                    s.pdf
                );
                continue;
            }
            others += 1;
            let (f, pdf) = (bsdf_eval(&m, n, wo, s.wi, radiance), bsdf_pdf(&m, n, wo, s.wi));
            assert!((s.f - f).abs().max_element() <= 1e-4 * f.max_element().max(1e-3), "{} {f}", s.f);
            assert!((s.pdf - pdf).abs() <= 1e-4 * pdf.max(1e-3), "{} {pdf}", s.pdf);
        }
        assert!(others > 1000 && (mirrors > 0) == m.has_smooth_coat(), "{others} {mirrors}");
    }
}
