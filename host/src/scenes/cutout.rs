//! `cutout`: glTF's cut-outs (`alphaMode`) in a Lambertian room under a ceiling lamp — a
//! perforated screen hung under the lamp (MASK, a NEAREST texture of square holes, so that the
//! floor is lit through the holes only), a leaf (MASK over a bilinear disc of alpha, its
//! silhouette where the filtered alpha crosses the cutoff, coloured by the same texture), and a
//! red pane whose coverage fades across it (BLEND: baseColorFactor's alpha 0.8 × a bilinear
//! alpha ramp from 1 to 0) — the scene of every caster's and every method's agreement on
//! cut-outs and of their check against Mitsuba 3.

use glam::Vec3;
use serde_json::json;

use super::{png, GltfBuilder, Planar};

/// glTF's sampler enums.
const NEAREST: u32 = 9728;
const LINEAR: u32 = 9729;
const CLAMP_TO_EDGE: u32 = 33071;

/// The scene, every quad split `tessellation` × `tessellation` times.
pub fn cutout(tessellation: u32) -> String {
    let mut b = GltfBuilder::tessellated(tessellation);
    let wall = b.material("wall", [0.7, 0.7, 0.7], [0.0; 3], 1.0, None);
    let blue = b.material("blue wall", [0.2, 0.3, 0.6], [0.0; 3], 1.0, None);
    let screen = b.material("perforated screen", [0.8, 0.75, 0.6], [0.0; 3], 1.0, None);
    let leaf = b.material("leaf", [1.0; 3], [0.0; 3], 1.0, None);
    let pane = b.material("fading pane", [0.8, 0.2, 0.15], [0.0; 3], 1.0, None);
    let block = b.material("block", [0.7, 0.6, 0.3], [0.0; 3], 1.0, None);
    let lamp = b.material("lamp", [0.0; 3], [1.0, 0.95, 0.85], 12.0, None);
    // The screen: holes where (x + y) is even, 25 cm squares (two texels a metre, repeated).
    let holes = png(2, 2, |x, y| if (x + y) % 2 == 0 { [200, 190, 160, 0] } else { [200, 190, 160, 255] });
    b.texture(
        screen,
        "baseColorTexture",
        holes,
        json!({"magFilter": NEAREST, "minFilter": NEAREST}),
        None,
        Planar { u: Vec3::X * 2.0, v: Vec3::Z * 2.0 },
    );
    b.alpha(screen, "MASK", None, 1.0);
    // The leaf: alpha 1 inside a disc, 0 outside, bilinear, cut at 0.4; its green varies.
    let disc = png(8, 8, |x, y| {
        let (dx, dy) = (x as f32 - 3.5, y as f32 - 3.5);
        let a = if dx * dx + dy * dy < 10.0 { 255 } else { 0 };
        [40 + 20 * x as u8, 160, 50 + 10 * y as u8, a]
    });
    b.texture(
        leaf,
        "baseColorTexture",
        disc,
        json!({"magFilter": LINEAR, "wrapS": CLAMP_TO_EDGE, "wrapT": CLAMP_TO_EDGE}),
        // The leaf spans x ∈ [−1.6, −0.6], y ∈ [0.2, 1.2]: texture coordinates [0, 1]².
        Some(json!({"offset": [1.6, 1.2]})),
        Planar { u: Vec3::X, v: -Vec3::Y },
    );
    b.alpha(leaf, "MASK", Some(0.4), 1.0);
    // The pane: coverage 0.8 × a ramp 1, 2/3, 1/3, 0 along z, bilinear.
    let ramp = png(4, 1, |x, _| [255, 255, 255, (255 - 85 * x) as u8]);
    b.texture(
        pane,
        "baseColorTexture",
        ramp,
        json!({"magFilter": LINEAR, "wrapS": CLAMP_TO_EDGE, "wrapT": CLAMP_TO_EDGE}),
        // The pane spans z ∈ [−1.2, 0.4]: u from 0 to 1 along it.
        Some(json!({"offset": [0.75, 0.0]})),
        Planar { u: Vec3::Z * (1.0 / 1.6), v: Vec3::Y },
    );
    b.alpha(pane, "BLEND", None, 0.8);
    let v = Vec3::new;
    let (w, h) = (2.0f32, 2.4f32);
    b.quad(wall, [v(-w, 0., w), v(w, 0., w), v(w, 0., -w), v(-w, 0., -w)]);
    b.quad(wall, [v(-w, 0., -w), v(w, 0., -w), v(w, h, -w), v(-w, h, -w)]);
    b.quad(blue, [v(-w, 0., w), v(-w, 0., -w), v(-w, h, -w), v(-w, h, w)]);
    b.quad(wall, [v(w, 0., -w), v(w, 0., w), v(w, h, w), v(w, h, -w)]);
    b.quad(wall, [v(-w, h, -w), v(w, h, -w), v(w, h, w), v(-w, h, w)]);
    b.quad(screen, [v(-1.0, 1.9, 0.5), v(1.0, 1.9, 0.5), v(1.0, 1.9, -1.5), v(-1.0, 1.9, -1.5)]);
    b.quad(leaf, [v(-1.6, 0.2, -0.8), v(-0.6, 0.2, -0.8), v(-0.6, 1.2, -0.8), v(-1.6, 1.2, -0.8)]);
    b.quad(pane, [v(0.8, 0.0, 0.4), v(0.8, 0.0, -1.2), v(0.8, 1.6, -1.2), v(0.8, 1.6, 0.4)]);
    b.cuboid(block, v(0.1, 0.3, -1.0), v(0.3, 0.3, 0.3), 0.4);
    let l = [v(-0.7, h - 0.01, -1.1), v(0.7, h - 0.01, -1.1), v(0.7, h - 0.01, 0.3), v(-0.7, h - 0.01, 0.3)];
    b.quad(lamp, super::facing(l, -Vec3::Y));
    b.camera(v(0.0, 1.3, 4.0), v(-0.1, 0.9, -1.0), Vec3::Y, 50f32.to_radians());
    b.to_json()
}
