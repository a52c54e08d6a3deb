//! Texture lookups against texels computed by hand.

use super::*;

/// RGBA8 packed, red in the low byte.
fn rgba(r: u8, g: u8, b: u8, a: u8) -> u32 {
    u32::from_le_bytes([r, g, b, a])
}

/// A 2 × 2 texture after `pad` unrelated texels: black, white / red, (0, 0, 255, 128).
fn two_by_two(pad: usize, sampler: u32) -> (Vec<u32>, Texture) {
    let mut texels = vec![rgba(9, 9, 9, 9); pad];
    texels.extend([rgba(0, 0, 0, 255), rgba(255, 255, 255, 255), rgba(255, 0, 0, 255), rgba(0, 0, 255, 128)]);
    (texels, Texture { offset: pad as u32, width: 2, height: 2, sampler })
}

fn close(a: Vec4, b: Vec4) -> bool {
    (a - b).abs().max_element() < 1e-5
}

#[test]
fn srgb_decoding_follows_iec_61966_2_1() {
    assert_eq!(srgb_to_linear(0.0), 0.0);
    assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
    // Both pieces meet at the threshold: 0.04045 / 12.92 = 0.0031308.
    assert!((srgb_to_linear(0.04045) - 0.0031308).abs() < 1e-7);
    assert!((srgb_to_linear(0.5) - 0.2140411).abs() < 1e-6);
    // 128 / 255 as decoders round it: 0.2158605.
    assert!((srgb_to_linear(128.0 / 255.0) - 0.2158605).abs() < 1e-6);
}

#[test]
fn texels_unpack_red_first_and_alpha_stays_linear() {
    let v = unpack(rgba(255, 128, 0, 128), true);
    assert!(close(v, Vec4::new(1.0, 0.2158605, 0.0, 128.0 / 255.0)), "{v}");
    let v = unpack(rgba(255, 128, 0, 128), false);
    assert!(close(v, Vec4::new(1.0, 128.0 / 255.0, 0.0, 128.0 / 255.0)), "{v}");
}

#[test]
fn wrap_modes_fold_indices_as_gl_does() {
    let n = 4;
    let repeat: Vec<i32> = (-4..8).map(|i| wrap(i, n, WRAP_REPEAT)).collect();
    assert_eq!(repeat, [0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3]);
    let clamp: Vec<i32> = (-2..6).map(|i| wrap(i, n, WRAP_CLAMP)).collect();
    assert_eq!(clamp, [0, 0, 0, 1, 2, 3, 3, 3]);
    let mirror: Vec<i32> = (-5..13).map(|i| wrap(i, n, WRAP_MIRROR)).collect();
    assert_eq!(mirror, [3, 3, 2, 1, 0, 0, 1, 2, 3, 3, 2, 1, 0, 0, 1, 2, 3, 3]);
    // Over the whole range each mode is documented for, GL's definitions (by division).
    for n in 1..6 {
        for i in -n..2 * n {
            assert_eq!(wrap(i, n, WRAP_REPEAT), i.rem_euclid(n), "repeat {i} of {n}");
        }
        for i in -2 * n..4 * n {
            let m = i.rem_euclid(2 * n);
            assert_eq!(wrap(i, n, WRAP_MIRROR), if m >= n { 2 * n - 1 - m } else { m }, "mirror {i} of {n}");
        }
    }
}

#[test]
fn nearest_reads_the_texel_under_the_point() {
    let (texels, tex) = two_by_two(3, Texture::sampler(WRAP_REPEAT, WRAP_REPEAT, true));
    let at = |u: f32, v: f32| sample(&texels, tex, Vec2::new(u, v), false);
    assert!(close(at(0.25, 0.25), Vec4::new(0.0, 0.0, 0.0, 1.0)));
    assert!(close(at(0.75, 0.25), Vec4::ONE), "u to the right");
    assert!(close(at(0.25, 0.75), Vec4::new(1.0, 0.0, 0.0, 1.0)), "v down");
    assert!(close(at(0.99, 0.51), Vec4::new(0.0, 0.0, 1.0, 128.0 / 255.0)));
    // REPEAT: whole periods away (and negative ones) read the same texel.
    assert!(close(at(-2.25, 3.75), at(0.75, 0.75)));
    let (texels, tex) = two_by_two(0, Texture::sampler(WRAP_CLAMP, WRAP_MIRROR, true));
    let at = |u: f32, v: f32| sample(&texels, tex, Vec2::new(u, v), false);
    // CLAMP_TO_EDGE in u; MIRRORED_REPEAT in v: v = 1.25 mirrors to 0.75.
    assert!(close(at(7.0, 0.25), at(0.75, 0.25)));
    assert!(close(at(-7.0, 1.25), at(0.25, 0.75)));
    assert!(close(at(0.25, 1.75), at(0.25, 0.25)));
    // Coordinates that are not finite read as 0.
    assert!(close(at(f32::NAN, f32::INFINITY), at(0.0, 0.0)));
}

#[test]
fn bilinear_weighs_the_four_texel_centres_around_the_point() {
    let (texels, tex) = two_by_two(1, Texture::sampler(WRAP_REPEAT, WRAP_REPEAT, false));
    let at = |u: f32, v: f32, srgb: bool| sample(&texels, tex, Vec2::new(u, v), srgb);
    // At a texel's centre, that texel.
    assert!(close(at(0.75, 0.25, false), Vec4::ONE));
    // Between the four centres: their mean.
    let mean = Vec4::new(2.0 / 4.0, 1.0 / 4.0, 2.0 / 4.0, (3.0 + 128.0 / 255.0) / 4.0);
    assert!(close(at(0.5, 0.5, false), mean), "{}", at(0.5, 0.5, false));
    // At the corner (0, 0) with REPEAT the four centres around it are the same four.
    assert!(close(at(0.0, 0.0, false), mean));
    // A quarter of the way from black's centre to white's: 0.25 white.
    assert!(close(at(0.375, 0.25, false), Vec4::new(0.25, 0.25, 0.25, 1.0)));
    // sRGB is decoded before filtering: black and white average to linear 0.5 (white and
    // black decode to themselves).
    assert!(close(at(0.5, 0.25, true), Vec4::new(0.5, 0.5, 0.5, 1.0)));
    // CLAMP_TO_EDGE: at the corner, the corner texel alone.
    let (texels, tex) = two_by_two(0, Texture::sampler(WRAP_CLAMP, WRAP_CLAMP, false));
    assert!(close(sample(&texels, tex, Vec2::ZERO, false), Vec4::new(0.0, 0.0, 0.0, 1.0)));
}

#[test]
fn texture_transform_is_translation_rotation_scale_as_the_extension_writes_it() {
    let r = TextureRef {
        texture: 0,
        tex_coord: 1,
        transform: texture_transform([0.5, -1.0], core::f32::consts::FRAC_PI_2, [2.0, 3.0]),
    };
    // S(1, 0) = (2, 0); R(π/2) turns (x, y) to (y, −x) (counter-clockwise with v down):
    // (2, 0) → (0, −2); T adds (0.5, −1).
    let uv = r.coordinates(Vec2::new(9.0, 9.0), Vec2::new(1.0, 0.0));
    assert!((uv - Vec2::new(0.5, -3.0)).abs().max_element() < 1e-6, "{uv}");
    // (0, 1) → S (0, 3) → R (3, 0) → T (3.5, −1).
    let uv = r.coordinates(Vec2::ZERO, Vec2::new(0.0, 1.0));
    assert!((uv - Vec2::new(3.5, -1.0)).abs().max_element() < 1e-6, "{uv}");
    // texCoord 0 and the identity.
    let plain = TextureRef { texture: 0, tex_coord: 0, transform: IDENTITY };
    assert_eq!(plain.coordinates(Vec2::new(0.3, 0.7), Vec2::ZERO), Vec2::new(0.3, 0.7));
    assert!(!TextureRef::NONE.is_some() && plain.is_some());
}
