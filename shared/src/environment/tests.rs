use super::*;
use crate::testing::u2;

/// A 16 × 8 sky: a smooth gradient, a black row, a bright sun texel and a coloured band.
fn sky(rotation: f32) -> EnvironmentMap {
    let (w, h) = (16u32, 8u32);
    let mut texels = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let base = 0.2 + 0.05 * i as f32 + 0.1 * j as f32;
            let rgb = match (i, j) {
                (_, 6) => [0.0, 0.0, 0.0],
                (11, 2) => [400.0, 380.0, 300.0],
                (_, 4) => [base * 3.0, base, 0.1],
                _ => [base, base * 1.1, base * 1.3],
            };
            texels.push(rgb);
        }
    }
    EnvironmentMap::new(w, h, &texels, rotation)
}

/// The (θ, φ) grid quadrature of `f` over the sphere, each texel split n × n.
fn quadrature(e: &Environment, n: u32, f: impl Fn(Vec3) -> f64) -> f64 {
    let (nu, nv) = (e.width * n, e.height * n);
    let mut sum = 0.0f64;
    for j in 0..nv {
        let (t0, t1) = (PI as f64 * j as f64 / nv as f64, PI as f64 * (j + 1) as f64 / nv as f64);
        // The exact solid angle of a cell: Δφ (cos θ0 − cos θ1).
        let omega = 2.0 * PI as f64 / nu as f64 * (t0.cos() - t1.cos());
        for i in 0..nu {
            let uv = Vec2::new((i as f32 + 0.5) / nu as f32, (j as f32 + 0.5) / nv as f32);
            sum += f(e.map_to_world(uv_to_direction(uv))) * omega;
        }
    }
    sum
}

/// Mitsuba 3's `envmap` coordinates: −Z at u = 0, +X at a quarter, +Z at the centre column,
/// the zenith on the top row; and the two maps invert each other.
#[test]
fn directions_map_as_mitsuba_s_envmap() {
    let close = |a: Vec2, b: Vec2| (a - b).abs().max_element() < 1e-6;
    assert!(close(direction_to_uv(-Vec3::Z), Vec2::new(0.0, 0.5)));
    assert!(close(direction_to_uv(Vec3::X), Vec2::new(0.25, 0.5)));
    assert!(close(direction_to_uv(Vec3::Z), Vec2::new(0.5, 0.5)));
    assert!(close(direction_to_uv(-Vec3::X), Vec2::new(0.75, 0.5)));
    assert!(direction_to_uv(Vec3::Y).y.abs() < 1e-6 && (direction_to_uv(-Vec3::Y).y - 1.0).abs() < 1e-6);
    for i in 0..1000 {
        let uv = u2(i, 3) * Vec2::new(1.0, 0.98) + Vec2::new(0.0, 0.01);
        let d = uv_to_direction(uv);
        assert!((d.length() - 1.0).abs() < 1e-5);
        assert!(close(direction_to_uv(d), uv) || (direction_to_uv(d).x - uv.x).abs() > 0.999, "{uv}");
    }
}

/// The rotation turns the map about +Y: the world direction R_y(ρ)·d sees what the map shows
/// at d; 90° brings the map's −Z to the world's −X.
#[test]
fn rotation_turns_the_map_about_up() {
    let plain = sky(0.0);
    let turned = sky(90f32.to_radians());
    for i in 0..500 {
        let d = crate::punctual::uniform_sphere(u2(i, 5));
        let w = turned.environment.map_to_world(d);
        assert!((turned.environment.world_to_map(w) - d).abs().max_element() < 1e-5);
        // Away from texel borders the two agree exactly.
        let uv = direction_to_uv(d) * Vec2::new(16.0, 8.0);
        if (uv - uv.round()).abs().min_element() > 1e-3 {
            assert_eq!(
                turned.environment.radiance(&turned.map, w),
                plain.environment.radiance(&plain.map, d)
            );
        }
    }
    assert!((turned.environment.map_to_world(-Vec3::Z) + Vec3::X).length() < 1e-6);
}

/// The density integrates to 1 over the sphere, and what `sample` reports is what `pdf` gives
/// for the direction it returns (but where rounding moves it onto a neighbouring texel).
#[test]
fn density_is_normalised_and_matches_the_samples() {
    for rotation in [0.0f32, 1.0] {
        let sky = sky(rotation);
        let e = &sky.environment;
        let integral = quadrature(e, 4, |w| e.pdf(&sky.map, w) as f64);
        assert!((integral - 1.0).abs() < 2e-3, "∫ p dω = {integral}");
        let mut mismatched = 0;
        for i in 0..20_000 {
            let s = e.sample(&sky.map, u2(i, 7));
            assert!(s.pdf > 0.0 && (s.wi.length() - 1.0).abs() < 1e-5);
            if (s.pdf - e.pdf(&sky.map, s.wi)).abs() > 1e-4 * s.pdf {
                mismatched += 1;
            }
            assert_ne!(s.radiance, Vec3::ZERO, "a black texel is never sampled");
        }
        assert!(mismatched < 20, "{mismatched} of 20000 samples disagree with pdf()");
    }
}

/// χ² of sampled texels against their probabilities (weight / Σ weights), and the sampling
/// estimate of ∫ L dω against the quadrature's.
#[test]
fn sampling_follows_the_texel_weights() {
    let sky = sky(0.3);
    let e = &sky.environment;
    let (w, h) = (e.width as usize, e.height as usize);
    let n = 400_000u32;
    let mut counts = vec![0u32; w * h];
    let mut estimate = 0.0f64;
    for i in 0..n {
        let s = e.sample(&sky.map, u2(i, 9));
        assert!(s.pdf > 0.0, "{i}: {s:?} {}", u2(i, 9));
        let uv = direction_to_uv(e.world_to_map(s.wi));
        let (ti, tj) = e.texel_at(uv);
        counts[tj as usize * w + ti as usize] += 1;
        estimate += luminance(s.radiance) as f64 / s.pdf as f64;
    }
    let weight =
        |i: usize, j: usize| texel_weight(e.texel(&sky.map, i as u32, j as u32), j as u32, h as u32) as f64;
    let total: f64 = (0..h).flat_map(|j| (0..w).map(move |i| (i, j))).map(|(i, j)| weight(i, j)).sum();
    let (mut chi2, mut bins) = (0.0f64, 0u32);
    for j in 0..h {
        for i in 0..w {
            let expected = n as f64 * weight(i, j) / total;
            if expected > 0.0 {
                chi2 += (counts[j * w + i] as f64 - expected).powi(2) / expected;
                bins += 1;
            } else {
                assert_eq!(counts[j * w + i], 0, "texel ({i}, {j}) has no weight");
            }
        }
    }
    let dof = (bins - 1) as f64;
    assert!(chi2 < dof + 5.0 * (2.0 * dof).sqrt(), "χ² = {chi2} over {dof} degrees of freedom");
    let estimate = estimate / n as f64;
    let exact = quadrature(e, 4, |d| luminance(e.radiance(&sky.map, d)) as f64);
    assert!((estimate / exact - 1.0).abs() < 0.01, "E[L/p] = {estimate}, ∫ L dω = {exact}");
    // The selection power's integral (row centres' sin θ) is within a few per cent of it.
    assert!((sky.luminance_integral() / exact - 1.0).abs() < 0.03, "{}", sky.luminance_integral());
}

/// A constant environment (one texel wide, rows following sin θ) sends the same radiance from
/// every direction, and its density is close to uniform.
#[test]
fn a_constant_environment_is_the_same_everywhere() {
    let c = [0.5f32, 0.6, 0.8];
    let env = EnvironmentMap::new(1, 64, &[c; 64], 0.0);
    let e = &env.environment;
    for i in 0..200 {
        let d = crate::punctual::uniform_sphere(u2(i, 13));
        assert_eq!(e.radiance(&env.map, d), Vec3::from_array(c));
        let p = e.pdf(&env.map, d) * 4.0 * PI;
        assert!((0.9..1.1).contains(&p) || d.y.abs() > 0.9, "{p} at {d}");
    }
    let exact = 4.0 * PI as f64 * luminance(Vec3::from_array(c)) as f64;
    assert!((env.luminance_integral() / exact - 1.0).abs() < 1e-3);
}
