//! Cut-out decisions against opacities computed by hand, and the BLEND draw's statistics.

use super::*;
use crate::texture::{TextureRef, IDENTITY, WRAP_CLAMP};

fn rgba(r: u8, g: u8, b: u8, a: u8) -> u32 {
    u32::from_le_bytes([r, g, b, a])
}

/// One triangle in the z = 0 plane over [0, 1]², its texture coordinates its (x, y), and the
/// material `alpha_mode` with a base colour factor alpha of `alpha`, optionally textured by a
/// 2 × 1 NEAREST texture whose left texel has alpha 0.2 (51/255) and right texel 1.
struct Fixture {
    triangles: Vec<Triangle>,
    materials: Vec<Material>,
    material_textures: Vec<MaterialTextures>,
    texcoords: Vec<TriangleTexcoords>,
    textures: Vec<Texture>,
    texels: Vec<u32>,
}

impl Fixture {
    fn new(alpha_mode: u32, alpha: f32, textured: bool) -> Self {
        let tri = Triangle {
            v0: [0.0, 0.0, 0.0],
            v1: [1.0, 0.0, 0.0],
            v2: [0.0, 1.0, 0.0],
            material: 1,
            ..Default::default()
        };
        // Vertex order v0, v1, v2: (u, v) = (x, y).
        let uv = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        let base_color = if textured {
            TextureRef { texture: 0, tex_coord: 0, transform: IDENTITY }
        } else {
            TextureRef::NONE
        };
        Fixture {
            triangles: vec![tri],
            materials: vec![Material::default(), Material { textures: 1, ..Default::default() }],
            material_textures: vec![
                MaterialTextures::default(),
                MaterialTextures { base_color, alpha_mode, alpha_cutoff: 0.5, alpha, ..Default::default() },
            ],
            texcoords: vec![TriangleTexcoords { uv }],
            textures: vec![Texture {
                offset: 0,
                width: 2,
                height: 1,
                sampler: Texture::sampler(WRAP_CLAMP, WRAP_CLAMP, true),
            }],
            texels: vec![rgba(255, 255, 255, 51), rgba(10, 20, 30, 255)],
        }
    }

    fn cutouts(&self) -> Cutouts<'_> {
        Cutouts {
            triangles: &self.triangles,
            materials: &self.materials,
            material_textures: &self.material_textures,
            texcoords: &self.texcoords,
            textures: &self.textures,
            texels: &self.texels,
        }
    }
}

/// A ray straight down onto the point (x, y) of the triangle, hit at t = 1.
fn onto(x: f32, y: f32) -> (Vec3, Vec3) {
    (Vec3::new(x, y, 1.0), Vec3::NEG_Z)
}

#[test]
fn opacity_is_the_factor_times_the_textures_linear_alpha() {
    let f = Fixture::new(ALPHA_MASK, 0.8, true);
    let c = f.cutouts();
    let m = c.of(0);
    assert!(c.is_cutout(0), "a MASK material is a cut-out");
    // The left texel (u < 0.5): 0.8 × 51/255 = 0.16; the right one: 0.8 × 1. The colour is
    // sRGB, the alpha is not decoded.
    assert!((c.opacity(0, &m, Vec3::new(0.2, 0.3, 0.0)) - 0.8 * 51.0 / 255.0).abs() < 1e-6);
    assert!((c.opacity(0, &m, Vec3::new(0.7, 0.1, 0.0)) - 0.8).abs() < 1e-6);
    let plain = Fixture::new(ALPHA_BLEND, 0.35, false);
    let c = plain.cutouts();
    assert_eq!(c.opacity(0, &c.of(0), Vec3::new(0.2, 0.3, 0.0)), 0.35);
}

#[test]
fn mask_stops_where_the_opacity_reaches_the_cutoff() {
    let f = Fixture::new(ALPHA_MASK, 1.0, true);
    let c = f.cutouts();
    let (o, d) = onto(0.2, 0.3);
    assert!(!c.stops(0, o, d, 1.0, 0), "alpha 0.2 < cutoff 0.5: cut away");
    let (o, d) = onto(0.7, 0.1);
    assert!(c.stops(0, o, d, 1.0, 0), "alpha 1 ≥ 0.5: solid");
    // The cutoff is inclusive (the spec: rendered opaque if alpha ≥ cutoff).
    let mut exact = Fixture::new(ALPHA_MASK, 0.5, false);
    assert!(exact.cutouts().stops(0, o, d, 1.0, 0));
    exact.material_textures[1].alpha = 0.499;
    assert!(!exact.cutouts().stops(0, o, d, 1.0, 0));
}

#[test]
fn opaque_and_untextured_materials_always_stop() {
    let (o, d) = onto(0.2, 0.3);
    let f = Fixture::new(ALPHA_OPAQUE, 0.0, true);
    assert!(!f.cutouts().is_cutout(0));
    assert!(f.cutouts().stops(0, o, d, 1.0, 0), "OPAQUE ignores alpha");
    let mut bare = Fixture::new(ALPHA_BLEND, 0.0, false);
    bare.materials[1].textures = 0;
    assert!(bare.cutouts().stops(0, o, d, 1.0, 0), "no textures entry: opaque");
    assert!(Cutouts::NONE.stops(0, o, d, 1.0, 0));
    assert!(!Cutouts::NONE.any());
}

/// BLEND stops a ray with probability α: over 10^5 rays onto random points, the share stopped
/// is α within four binomial standard deviations, for a constant α and for the texture's two
/// halves.
#[test]
fn blend_stops_with_probability_the_opacity() {
    let mut state = 0x1234_5678u32;
    let mut uniform = || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        unit_f32(state)
    };
    for (alpha, textured) in [(0.3, false), (0.9, false), (1.0, true)] {
        let f = Fixture::new(ALPHA_BLEND, alpha, textured);
        let c = f.cutouts();
        let n = 100_000;
        let (mut stopped, mut expected) = (0u32, 0.0f64);
        for _ in 0..n {
            let (x, y) = (uniform() * 0.5, uniform() * 0.5);
            let (mut o, d) = onto(x + 0.5 * (uniform() < 0.5) as u32 as f32, y);
            o.z = 1.0 + uniform(); // rays from different heights
            let p = o + d * (o.z);
            let a = c.opacity(0, &c.of(0), p) as f64;
            expected += a;
            let key = blend_key(Vec2::new(uniform(), uniform()));
            stopped += c.stops(0, o, d, o.z, key) as u32;
        }
        let mean = expected / n as f64;
        let sigma = (mean * (1.0 - mean) / n as f64).sqrt().max(1e-9);
        let share = stopped as f64 / n as f64;
        assert!((share - mean).abs() < 4.0 * sigma, "α {alpha}: stopped {share}, expected {mean}");
    }
}

/// The draw is a function of the ray's key and the triangle: the same query decides the same
/// way (a re-traced path meets the same surfaces), and two triangles along one ray draw
/// independently — the share of rays through two layers of α 0.5 is 1/4, not 1/2 (pbrt-v4's
/// hash of the ray alone would give 1/2). Keys from neighbouring uniforms (a small Metropolis
/// step) draw independently too.
#[test]
fn draws_repeat_per_query_and_are_independent_across_triangles() {
    let key = blend_key(Vec2::new(0.25, 0.75));
    assert_eq!(blend_draw(key, 7), blend_draw(key, 7));
    assert_eq!(key, blend_key(Vec2::new(0.25, 0.75)));
    let n = 100_000;
    let (mut both_pass, mut neighbours_pass) = (0, 0);
    let mut sum = 0.0f64;
    for i in 0..n {
        let u = Vec2::new(i as f32 / n as f32, 0.5);
        let key = blend_key(u);
        let (a, b) = (blend_draw(key, 3), blend_draw(key, 4));
        sum += a as f64;
        both_pass += (a >= 0.5 && b >= 0.5) as u32;
        let next = blend_draw(blend_key(Vec2::new(f32::from_bits(u.x.to_bits() + 1), 0.5)), 3);
        neighbours_pass += (a >= 0.5 && next >= 0.5) as u32;
    }
    let mean = sum / n as f64;
    assert!((mean - 0.5).abs() < 4.0 * (1.0 / 12.0 / n as f64).sqrt(), "mean draw {mean}");
    for (what, count) in [("two layers", both_pass), ("neighbouring keys", neighbours_pass)] {
        let share = count as f64 / n as f64;
        assert!((share - 0.25).abs() < 4.0 * (0.25 * 0.75 / n as f64).sqrt(), "{what}: both pass {share}");
    }
}
