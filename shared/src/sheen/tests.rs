use super::*;
use crate::bsdf::{bsdf_eval, bsdf_pdf, bsdf_sample, Material, Normals};
use crate::testing::{dir, u2};
use glam::Vec3;
use std::f64::consts::PI as PI64;

/// The nodes along each axis of the fit's data.
const NODES: usize = 32;

/// The cosine of node column `i`: (i / 31)², the first at 10⁻⁴ (the albedo grows without bound
/// as the cosine goes to 0, where Λ stays finite).
fn column_cosine(i: usize) -> f32 {
    let x = i as f32 / (NODES - 1) as f32;
    (x * x).max(1e-4)
}

/// The roughness r of node row `j`, uniform over [MIN_ROUGHNESS, 1].
fn row_roughness(j: usize) -> f32 {
    MIN_ROUGHNESS + (1.0 - MIN_ROUGHNESS) * j as f32 / (NODES - 1) as f32
}

/// E by quadrature of [`eval`] over the hemisphere: cos θ_i = t², t by the midpoint rule
/// (dense near grazing, where the lobe peaks), φ over [0, π] (the lobe is symmetric about wo's
/// plane).
fn albedo_by_quadrature(roughness: f32, cos_o: f32) -> f64 {
    let (n_t, n_phi) = (384, 192);
    let a = alpha(roughness);
    let wo = dir(cos_o, 0.0);
    let mut sum = 0.0f64;
    for i in 0..n_t {
        let t = (i as f64 + 0.5) / n_t as f64;
        let c = t * t;
        for j in 0..n_phi {
            let phi = PI64 * (j as f64 + 0.5) / n_phi as f64;
            let wi = dir(c as f32, phi as f32);
            // dω = dcos dφ, dcos = 2t dt; both halves of the circle.
            sum += eval(a, wo, wi) as f64 * c * 2.0 * t / n_t as f64 * 2.0 * PI64 / n_phi as f64;
        }
    }
    sum
}

/// The fitted series (`albedo.rs`) is the quadrature of the lobe within 0.004 (+ 0.5 %) at the
/// nodes it was fitted to (every fourth of each axis here; all of them written to the CSV that
/// `scripts/sheen_albedo_fit.py` fits, with `SMLT_WRITE_SHEEN_ALBEDO=PATH`).
#[test]
fn the_albedo_fit_is_the_lobes_quadrature() {
    let write = std::env::var_os("SMLT_WRITE_SHEEN_ALBEDO");
    let step = if write.is_some() { 1 } else { 4 };
    let mut csv = String::from("x,r,e\n");
    for j in (0..NODES).step_by(step) {
        for i in (0..NODES).step_by(step) {
            let (r, c) = (row_roughness(j), column_cosine(i));
            let e = albedo_by_quadrature(r, c);
            csv.push_str(&format!("{},{},{}\n", (c as f64).sqrt(), r, e));
            let fitted = albedo(r, c) as f64;
            assert!(
                write.is_some() || (fitted - e).abs() <= 4e-3 + 5e-3 * e,
                "E(r {r}, cos {c}) = {e} by quadrature, {fitted} fitted"
            );
        }
    }
    if let Some(path) = write {
        std::fs::write(path, csv).unwrap();
    }
}

/// Between the nodes the fit follows the quadrature within 1.5 % (or 0.01) from cos θ = 0.01
/// up, where the lobe is resolved.
#[test]
fn the_albedo_between_nodes_follows_the_quadrature() {
    for r in [0.07f32, 0.15, 0.33, 0.5, 0.81, 1.0] {
        for c in [0.013f32, 0.03, 0.07, 0.2, 0.45, 0.66, 0.9, 0.999] {
            let (e, table) = (albedo_by_quadrature(r, c), albedo(r, c) as f64);
            assert!((table - e).abs() <= 0.01 + 0.015 * e, "r {r}, cos {c}: table {table}, quadrature {e}");
        }
    }
    // Roughness outside [0.07, 1] reads the limit; the cosine's sign is ignored.
    assert_eq!(albedo(0.0, 0.5), albedo(MIN_ROUGHNESS, 0.5));
    assert_eq!(albedo(3.0, 0.5), albedo(1.0, 0.5));
    assert_eq!(albedo(0.5, -0.3), albedo(0.5, 0.3));
}

/// The quadrature against an independent Monte Carlo estimate (uniform directions) at points
/// where the lobe is far from a unit albedo either way, and the values quoted in the module
/// doc: E reaches 2.9 at r = 0.07 near grazing and stays below 1 for r ≥ 0.3.
#[test]
fn the_quadrature_agrees_with_monte_carlo_and_the_albedo_exceeds_one_only_for_small_roughness() {
    for (r, c) in [(0.1f32, 0.02f32), (0.5, 0.5), (1.0, 1.0), (0.25, 0.1)] {
        let a = alpha(r);
        let wo = dir(c, 0.0);
        let n = 400_000u32;
        let mut sum = 0.0f64;
        for i in 0..n {
            let wi = sample(u2(i, 91));
            sum += eval(a, wo, wi) as f64 * wi.z as f64 / PDF as f64;
        }
        let (mc, q) = (sum / n as f64, albedo_by_quadrature(r, c));
        assert!((mc - q).abs() < 0.01 * q.max(0.1), "r {r}, cos {c}: Monte Carlo {mc}, quadrature {q}");
    }
    assert!((albedo_by_quadrature(0.07, 0.002) - 2.9).abs() < 0.1);
    for j in 0..NODES {
        for i in 0..NODES {
            let (r, c) = (row_roughness(j), column_cosine(i));
            assert!(r < 0.3 || albedo(r, c) < 1.0, "r {r}, cos {c}: {}", albedo(r, c));
        }
    }
}

/// The distribution is normalised (∫ D cos θ_h dω_h = 1) for every roughness modelled.
#[test]
fn the_distribution_is_normalised() {
    for r in [MIN_ROUGHNESS, 0.2, 0.5, 1.0] {
        let a = alpha(r);
        let n = 20_000;
        let sum: f64 = (0..n)
            .map(|i| {
                let c = (i as f64 + 0.5) / n as f64;
                charlie_d(a, c as f32) as f64 * c * 2.0 * PI64 / n as f64
            })
            .sum();
        assert!((sum - 1.0).abs() < 1e-3, "r {r}: {sum}");
    }
    assert_eq!(alpha(0.0), MIN_ROUGHNESS * MIN_ROUGHNESS);
    assert_eq!(alpha(2.0), 1.0);
}

/// The lobe is the extension's formulas written out independently in f64 (D, the fit L, Λ
/// mirrored above 0.5, V), reciprocal, and 0 below the surface.
#[test]
fn eval_is_the_extensions_lobe() {
    let l = |x: f64, a: f64| {
        let t = (1.0 - a) * (1.0 - a);
        let m = |p: f64, q: f64| p * (1.0 - t) + q * t;
        m(21.5473, 25.3245) / (1.0 + m(3.82987, 3.32435) * x.powf(m(0.19823, 0.16801)))
            + m(-1.97760, -1.27393) * x
            + m(-4.32054, -4.85967)
    };
    let lam = |c: f64, a: f64| if c < 0.5 { l(c, a).exp() } else { (2.0 * l(0.5, a) - l(1.0 - c, a)).exp() };
    for r in [0.07f64, 0.3, 0.6, 1.0] {
        let a = r * r;
        for (co, ci, phi) in [(0.9f32, 0.7f32, 2.5f32), (0.3, 0.8, 3.0), (0.1, 0.15, 0.4), (0.6, 0.6, 3.1)] {
            let (wo, wi) = (dir(co, 0.0), dir(ci, phi));
            let h = (wo + wi).as_dvec3().normalize();
            let d = (2.0 + 1.0 / a) * (1.0 - h.z * h.z).powf(0.5 / a) / (2.0 * PI64);
            let (co, ci) = (co as f64, ci as f64);
            let expected = d / ((1.0 + lam(co, a) + lam(ci, a)) * 4.0 * co * ci);
            let got = eval(a as f32, wo, wi) as f64;
            assert!((got - expected).abs() <= 1e-4 * expected + 1e-9, "r {r}: {got} against {expected}");
            assert!((eval(a as f32, wi, wo) as f64 - got).abs() <= 1e-5 * got, "reciprocal");
        }
    }
    let a = alpha(0.5);
    assert_eq!(eval(a, dir(0.5, 0.0), dir(-0.5, 1.0)), 0.0);
    assert!((lambda(a, 0.49999) - lambda(a, 0.50001)).abs() < 1e-3 * lambda(a, 0.5), "continuous at 0.5");
}

/// The scaling and the sampling probability are the module doc's formulas.
#[test]
fn scaling_and_probability_follow_the_albedo() {
    let (m, r) = (0.8f32, 0.4f32);
    let (eo, ei) = (albedo(r, 0.9), albedo(r, 0.2));
    assert!((albedo_scaling(m, r, 0.9, 0.2) - (1.0 - m * eo.max(ei))).abs() < 1e-7);
    assert_eq!(albedo_scaling(m, r, 0.9, 0.2), albedo_scaling(m, r, 0.2, 0.9), "symmetric");
    assert_eq!(albedo_scaling(1.0, MIN_ROUGHNESS, 0.01, 0.5), 0.0, "kept at 0 where E > 1");
    assert_eq!(albedo_scaling(0.0, r, 0.01, 0.5), 1.0);
    assert!((probability(m, r, 0.9) - m * eo).abs() < 1e-7);
    assert_eq!(probability(1.0, MIN_ROUGHNESS, 0.01), MAX_PROBABILITY);
    // Uniform directions over the hemisphere.
    let n = 100_000;
    let mean_z: f64 = (0..n).map(|i| sample(u2(i, 5)).z as f64).sum::<f64>() / n as f64;
    assert!((mean_z - 0.5).abs() < 0.005, "{mean_z}");
    assert!((0..1000).all(|i| (sample(u2(i, 6)).length() - 1.0).abs() < 1e-5 && sample(u2(i, 6)).z >= 0.0));
}

/// A material with the sheen `color` of roughness `r` over `base`.
fn sheened(base: Material, color: [f32; 3], r: f32) -> Material {
    Material { sheen_color: color, sheen_roughness: r, ..base }
}

/// Lambert of albedo `a`.
fn lambert(a: f32) -> Material {
    Material { albedo: [a; 3], ..Default::default() }
}

/// A rough red plastic (glTF's BRDF).
fn plastic() -> Material {
    Material {
        albedo: [0.7, 0.1, 0.08],
        alpha: 0.25,
        specular: 1.0,
        specular_color: [1.0; 3],
        ior: 1.5,
        ..Default::default()
    }
}

/// Smooth solid glass.
fn glass() -> Material {
    Material { albedo: [1.0; 3], transmission: 1.0, ior: 1.5, ..Default::default() }
}

/// The sheened materials of the tests: over Lambert, plastic, rough and smooth glass (a delta),
/// and under a clear coat.
fn sheened_cases() -> [Material; 6] {
    let velvet = [0.9, 0.5, 0.7];
    [
        sheened(lambert(0.5), velvet, 0.5),
        sheened(plastic(), [1.0; 3], 0.2),
        sheened(Material { alpha: 0.2, ..glass() }, velvet, 0.8),
        sheened(glass(), velvet, 0.4),
        Material { clearcoat: 0.8, clearcoat_alpha: 0.25, ..sheened(plastic(), velvet, 0.6) },
        Material { clearcoat: 1.0, clearcoat_alpha: 0.04, thin_walled: 1, ..sheened(glass(), velvet, 0.5) },
    ]
}

/// The material is the extension's `sheenColor · f_sheen + material · s` at reference angles,
/// over reflection and (through rough glass) transmission, where `s` takes |cos θ_i|.
#[test]
fn the_sheened_material_is_the_extensions_mix() {
    let n = Normals::flat(Vec3::Z);
    for m in sheened_cases().into_iter().take(3) {
        let bare = Material { sheen_color: [0.0; 3], ..m };
        let a = alpha(m.sheen_roughness);
        let c = Vec3::from_array(m.sheen_color);
        for (co, ci, phi) in [(0.9f32, 0.7f32, 2.5f32), (0.3, 0.8, 3.0), (0.6, -0.4, 0.5), (0.15, 0.25, 3.1)]
        {
            let (wo, wi) = (dir(co, 0.0), dir(ci, phi));
            let s = albedo_scaling(m.sheen_max(), m.sheen_roughness, co, ci);
            let layer = if ci > 0.0 { c * eval(a, wo, wi) } else { Vec3::ZERO };
            let expected = layer + bsdf_eval(&bare, n, wo, wi, true) * s;
            let got = bsdf_eval(&m, n, wo, wi, true);
            assert!(
                (got - expected).abs().max_element() <= 1e-5 * expected.max_element().max(1e-3),
                "{got} {expected}"
            );
            assert_eq!(got, bsdf_eval(&m, n, wo, wi, false), "reciprocal transport modes");
        }
    }
}

/// Every sample of a sheened material reports the f and density that eval and pdf give its
/// direction, in both transport modes, with a shading normal too; a delta of the glass beneath
/// carries the scaling and the layer's probability.
#[test]
fn sheened_samples_agree_with_eval_and_pdf() {
    let ns = Vec3::new(20f32.to_radians().sin(), 20f32.to_radians().cos(), 0.0);
    for n in [Normals::flat(Vec3::Y), Normals::shaded(Vec3::Y, ns)] {
        for m in sheened_cases() {
            let (mut found, mut deltas) = (0, 0);
            for i in 0..6000 {
                let wo = crate::testing::sphere(i, 4);
                let radiance = i % 2 == 0;
                let s = bsdf_sample(&m, n, wo, u2(i, 5), radiance);
                if !(s.pdf > 0.0) {
                    continue;
                }
                found += 1;
                if s.delta {
                    deltas += 1;
                    let bare = Material { sheen_color: [0.0; 3], ..m };
                    let b = bsdf_sample(&bare, n, wo, u2(i, 5), radiance);
                    let ns = n.facing(wo).shading;
                    let p = probability(m.sheen_max(), m.sheen_roughness, ns.dot(wo));
                    let scale = albedo_scaling(m.sheen_max(), m.sheen_roughness, ns.dot(wo), ns.dot(s.wi));
                    // The bare glass's sample at the rescaled uniform is the same direction.
                    if b.delta && (b.wi - s.wi).length() < 1e-5 {
                        assert!((s.f - b.f * scale).abs().max_element() <= 1e-4 * b.f.max_element());
                        assert!((s.pdf - b.pdf * (1.0 - p)).abs() <= 1e-4 * b.pdf, "{} {}", s.pdf, b.pdf);
                    }
                    continue;
                }
                let (f, pdf) = (bsdf_eval(&m, n, wo, s.wi, radiance), bsdf_pdf(&m, n, wo, s.wi));
                assert!((s.f - f).abs().max_element() <= 1e-4 * f.max_element().max(1e-3), "{} {f}", s.f);
                assert!((s.pdf - pdf).abs() <= 1e-4 * pdf.max(1e-3), "{} {pdf}", s.pdf);
            }
            assert!(found > 2000, "{m:?}: {found}");
            assert_eq!(deltas > 0, m.has_delta_lobe(), "{m:?}: {deltas} deltas");
        }
    }
}

/// Sampling is unbiased for the whole material: the mean sample weight f cos / pdf equals the
/// quadrature of f cos over the sphere (which a density that disagreed with the sampling would
/// miss), for each reflecting case at three angles.
#[test]
fn sheened_sampling_estimates_the_albedo() {
    let n = Normals::flat(Vec3::Z);
    for m in sheened_cases().into_iter().filter(|m| m.transmission == 0.0 || m.alpha > 0.0) {
        for cos_o in [0.95f32, 0.5, 0.12] {
            let wo = dir(cos_o, 0.3);
            let trials = 200_000u32;
            let mut mc = 0.0f64;
            for i in 0..trials {
                let s = bsdf_sample(&m, n, wo, u2(i, 17), true);
                if s.pdf > 0.0 {
                    mc += (s.f.x * s.wi.z.abs() / s.pdf) as f64;
                }
            }
            let mc = mc / trials as f64;
            let (n_c, n_phi) = (400, 200);
            let mut q = 0.0f64;
            for side in [1.0f32, -1.0] {
                for a in 0..n_c {
                    let t = (a as f64 + 0.5) / n_c as f64;
                    for b in 0..n_phi {
                        let phi = 2.0 * PI64 * (b as f64 + 0.5) / n_phi as f64;
                        let wi = dir(side * (t * t) as f32, phi as f32);
                        let f = bsdf_eval(&m, n, wo, wi, true).x as f64;
                        q += f * t * t * 2.0 * t / n_c as f64 * 2.0 * PI64 / n_phi as f64;
                    }
                }
            }
            assert!((mc - q).abs() < 0.01 * q.max(0.2), "{m:?} cos {cos_o}: sampled {mc}, quadrature {q}");
        }
    }
}

/// A white Lambertian base under a white sheen of roughness 0.3 or more reflects at most what
/// arrives and loses little: the layer takes `E(cos θ_o)` and the base keeps at most the rest.
#[test]
fn a_white_furnace_keeps_its_energy_where_the_albedo_is_below_one() {
    let n = Normals::flat(Vec3::Z);
    for r in [0.3f32, 0.6, 1.0] {
        let m = sheened(lambert(1.0), [1.0; 3], r);
        for cos_o in [1.0f32, 0.6, 0.25, 0.05] {
            let wo = dir(cos_o, 0.0);
            let trials = 100_000u32;
            let mut total = 0.0f64;
            for i in 0..trials {
                let s = bsdf_sample(&m, n, wo, u2(i, 23), true);
                if s.pdf > 0.0 {
                    total += (s.f.x * s.wi.z / s.pdf) as f64;
                }
            }
            let total = total / trials as f64;
            assert!(total <= 1.0 + 0.01 && total > 0.75, "r {r} cos {cos_o}: {total}");
        }
    }
}
