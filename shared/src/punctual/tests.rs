use super::*;
use crate::testing::u2;

fn spot() -> PunctualLight {
    PunctualLight::spot(
        Vec3::new(0.5, 2.0, -1.0),
        Vec3::new(0.2, -1.0, 0.3).normalize(),
        Vec3::new(3.0, 2.0, 1.0),
        20f32.to_radians(),
        35f32.to_radians(),
    )
}

/// The spec's reference falloff, computed here in f64 from its formula: full inside the
/// inner cone, nothing outside the outer one, the squared ramp in cos θ between.
#[test]
fn spot_falloff_is_the_spec_s() {
    let (inner, outer) = (20f64.to_radians(), 35f64.to_radians());
    let reference = |theta: f64| {
        let scale = 1.0 / (inner.cos() - outer.cos()).max(0.001);
        let t = ((theta.cos() - outer.cos()) * scale).clamp(0.0, 1.0);
        t * t
    };
    for deg in [0.0f64, 10.0, 19.9, 20.5, 25.0, 30.0, 34.9, 35.1, 60.0, 120.0] {
        let theta = deg.to_radians();
        let ours = spot_falloff(inner.cos() as f32, outer.cos() as f32, theta.cos() as f32) as f64;
        assert!((ours - reference(theta)).abs() < 2e-4, "{deg}°: {ours} vs {}", reference(theta));
    }
    assert_eq!(spot_falloff(inner.cos() as f32, outer.cos() as f32, 1.0), 1.0);
    assert_eq!(spot_falloff(inner.cos() as f32, outer.cos() as f32, 0.5), 0.0);
    // 25° is (cos 25° − cos 35°)/(cos 20° − cos 35°) = 0.72304 of the ramp: 0.52279 squared.
    let mid = spot_falloff(inner.cos() as f32, outer.cos() as f32, 25f32.to_radians().cos());
    assert!((mid - 0.52279).abs() < 1e-4, "{mid}");
}

/// χ² of sampled directions against the density, over 10 × 10 bins of equal solid angle
/// (uniform in cos θ about the axis and in φ) of the region the density covers.
fn chi2_directions(light: &PunctualLight, axis: Vec3, cos_min: f32) -> f64 {
    let (t, b) = orthonormal_basis(axis);
    let n = 200_000u32;
    let mut counts = [[0u32; 10]; 10];
    for i in 0..n {
        let s = light.sample_direction(u2(i, 11));
        assert!((s.w.length() - 1.0).abs() < 1e-4);
        assert!((s.pdf - light.pdf_direction(s.w)).abs() <= 1e-6 * s.pdf, "sample and pdf agree");
        let c = s.w.dot(axis);
        assert!(c >= cos_min - 1e-5, "outside the region: cos {c}");
        let ci = (((c - cos_min) / (1.0 - cos_min)) * 10.0).clamp(0.0, 9.999) as usize;
        let phi = s.w.dot(b).atan2(s.w.dot(t)) + PI;
        let pi = (phi / (2.0 * PI) * 10.0).clamp(0.0, 9.999) as usize;
        counts[ci][pi] += 1;
    }
    // Equal solid angles: the expected count of a bin is n · pdf · Ω_bin = n / 100.
    let expected = n as f64 / 100.0;
    counts.iter().flatten().map(|&c| (c as f64 - expected).powi(2) / expected).sum()
}

/// Point lights sample the sphere and spots their outer cone uniformly, each with the density
/// it reports (χ² with 99 degrees of freedom; 148.2 is its 0.1 % point).
#[test]
fn emitted_directions_follow_their_density() {
    let point = PunctualLight::point(Vec3::ZERO, Vec3::ONE);
    let chi2 = chi2_directions(&point, Vec3::Z, -1.0);
    assert!(chi2 < 148.2, "point: χ² = {chi2}");
    let s = spot();
    let chi2 = chi2_directions(&s, Vec3::from_array(s.direction), s.cos_outer);
    assert!(chi2 < 148.2, "spot: χ² = {chi2}");
}

/// Each density integrates to 1 over the sphere (uniform sphere sampling), and the spot's is 0
/// outside its outer cone.
#[test]
fn direction_densities_integrate_to_one() {
    for light in [PunctualLight::point(Vec3::ZERO, Vec3::ONE), spot()] {
        let n = 400_000;
        let integral: f64 = (0..n)
            .map(|i| (light.pdf_direction(uniform_sphere(u2(i, 12))) * 4.0 * PI) as f64 / n as f64)
            .sum();
        assert!((integral - 1.0).abs() < 0.01, "kind {}: ∫pdf = {integral}", light.kind);
    }
    let s = spot();
    assert_eq!(s.pdf_direction(-Vec3::from_array(s.direction)), 0.0);
    let d = PunctualLight::directional(Vec3::NEG_Y, Vec3::ONE, Vec3::ZERO, 1.0);
    assert_eq!(d.pdf_direction(Vec3::NEG_Y), 0.0, "a delta direction is no other technique's");
}

/// The power a light is picked by is its flux over π: the integral of its intensity's
/// luminance over the sphere, divided by π (here by uniform sphere sampling), and E r² for the
/// directional light (E · π r² through its disk).
#[test]
fn selection_power_is_the_flux_over_pi() {
    let narrow =
        PunctualLight::spot(Vec3::ZERO, Vec3::Y, Vec3::ONE, 29.9f32.to_radians(), 30f32.to_radians());
    for light in [PunctualLight::point(Vec3::ZERO, Vec3::new(1.0, 2.0, 0.5)), spot(), narrow] {
        let n = 1_000_000;
        let flux: f64 = (0..n)
            .map(|i| (luminance(light.emitted(uniform_sphere(u2(i, 13)))) * 4.0 * PI) as f64 / n as f64)
            .sum();
        let ours = light.selection_power() as f64;
        assert!(
            (ours - flux / core::f64::consts::PI).abs() < 0.01 * ours,
            "kind {}: {ours} vs {}",
            light.kind,
            flux / core::f64::consts::PI
        );
    }
    let d = PunctualLight::directional(Vec3::NEG_Y, Vec3::splat(2.0), Vec3::ZERO, 3.0);
    assert!((d.selection_power() - 18.0).abs() < 1e-4);
}

/// Incident light: inverse square for point and spot (times the falloff towards the point),
/// the irradiance itself from outside the bounding sphere for the directional light.
#[test]
fn incident_light_is_inverse_square_or_parallel() {
    let p = Vec3::new(1.0, 0.0, 0.0);
    let point = PunctualLight::point(Vec3::new(1.0, 2.0, 0.0), Vec3::splat(8.0));
    let inc = point.incident(p);
    assert!((inc.wi - Vec3::Y).length() < 1e-6);
    assert_eq!(inc.from, Vec3::new(1.0, 2.0, 0.0));
    assert!((inc.radiance - Vec3::splat(2.0)).abs().max_element() < 1e-6);
    let s = spot();
    let q = Vec3::from_array(s.position) + Vec3::new(0.1, -1.0, 0.2) * 2.0;
    let inc = s.incident(q);
    let expected = s.emitted(-inc.wi) / (q - Vec3::from_array(s.position)).length_squared();
    assert!((inc.radiance - expected).abs().max_element() < 1e-6);
    let centre = Vec3::new(0.0, 1.0, 0.0);
    let sun =
        PunctualLight::directional(Vec3::new(0.0, -1.0, -1.0).normalize(), Vec3::splat(3.0), centre, 2.0);
    let inc = sun.incident(p);
    assert!((inc.wi - Vec3::new(0.0, 1.0, 1.0).normalize()).length() < 1e-6);
    assert_eq!(inc.radiance, Vec3::splat(3.0));
    assert!((inc.from - centre).length() > 2.0, "the shadow ray ends outside the bounding sphere");
}

/// A directional light's subpaths start uniformly on the disk of radius r whose centre lies r
/// before the bounding sphere's centre along the light's direction, perpendicular to it: every
/// ray of the light through the sphere starts on it, with density 1 / (π r²).
#[test]
fn directional_origins_cover_the_bounding_sphere() {
    let centre = Vec3::new(1.0, 2.0, 3.0);
    let d = Vec3::new(0.3, -1.0, 0.2).normalize();
    let sun = PunctualLight::directional(d, Vec3::ONE, centre, 2.0);
    let n = 100_000;
    let mut inner_quarter = 0;
    for i in 0..n {
        let (o, pdf) = sun.sample_origin(u2(i, 14));
        assert!((pdf - 1.0 / (PI * 4.0)).abs() < 1e-6);
        let rel = o - (centre - d * 2.0);
        assert!(rel.dot(d).abs() < 1e-4, "on the plane perpendicular to the light");
        assert!(rel.length() <= 2.0 + 1e-4, "within the radius");
        if rel.length() < 1.0 {
            inner_quarter += 1;
        }
    }
    let share = inner_quarter as f64 / n as f64;
    assert!((share - 0.25).abs() < 0.005, "uniform in area: {share}");
    let point = PunctualLight::point(centre, Vec3::ONE);
    assert_eq!(point.sample_origin(u2(0, 1)), (centre, 1.0), "a point light's origin is a delta");
}
