//! `textured`: a Lambertian room whose colours come from textures — a checker floor (NEAREST,
//! REPEAT, sRGB), a back wall of smooth colour bands (bilinear, MIRRORED_REPEAT across and
//! CLAMP_TO_EDGE up, through a `KHR_texture_transform` that scales, turns and offsets it), a
//! side wall with a linear-filtered stripe texture under a base colour factor, and a ceiling
//! lamp whose emission is an `emissiveTexture` (a bright frame around a dim centre, so that
//! light sampling meets emission that varies over a triangle) — the scene of the textures'
//! check against Mitsuba 3 and of every method's agreement on textures.

use glam::Vec3;
use serde_json::json;

use super::{png, GltfBuilder, Planar};

/// glTF's sampler enums.
const NEAREST: u32 = 9728;
const LINEAR: u32 = 9729;
const CLAMP_TO_EDGE: u32 = 33071;
const MIRRORED_REPEAT: u32 = 33648;

/// The scene, every quad split `tessellation` × `tessellation` times.
pub fn textured(tessellation: u32) -> String {
    let mut b = GltfBuilder::tessellated(tessellation);
    let floor = b.material("checker floor", [1.0; 3], [0.0; 3], 1.0, None);
    let back = b.material("banded wall", [1.0; 3], [0.0; 3], 1.0, None);
    let side = b.material("striped wall", [0.9, 0.8, 0.7], [0.0; 3], 1.0, None);
    let plain = b.material("plain", [0.6, 0.6, 0.6], [0.0; 3], 1.0, None);
    let block = b.material("block", [0.7, 0.3, 0.2], [0.0; 3], 1.0, None);
    let lamp = b.material("lamp", [0.0; 3], [1.0, 0.95, 0.85], 12.0, None);
    let checker = png(8, 8, |x, y| if (x + y) % 2 == 0 { [210, 205, 195, 255] } else { [40, 45, 60, 255] });
    b.texture(
        floor,
        "baseColorTexture",
        checker,
        json!({"magFilter": NEAREST, "minFilter": NEAREST}),
        None,
        Planar { u: Vec3::X * 0.5, v: Vec3::Z * 0.5 },
    );
    let bands = png(16, 4, |x, y| [(x * 15) as u8, 60 + (y * 40) as u8, 255 - (x * 15) as u8, 255]);
    b.texture(
        back,
        "baseColorTexture",
        bands,
        json!({"magFilter": LINEAR, "wrapS": MIRRORED_REPEAT, "wrapT": CLAMP_TO_EDGE}),
        Some(json!({"offset": [0.2, -0.1], "rotation": 0.3, "scale": [1.5, 1.0]})),
        Planar { u: Vec3::X * 0.4, v: -Vec3::Y * 0.4 },
    );
    let stripes = png(4, 1, |x, _| if x % 2 == 0 { [255, 255, 255, 255] } else { [90, 90, 90, 255] });
    b.texture(
        side,
        "baseColorTexture",
        stripes,
        json!({"magFilter": LINEAR}),
        None,
        Planar { u: Vec3::Z * 0.8, v: Vec3::Y * 0.8 },
    );
    // The lamp's emission: a bright frame around a dim centre, nearest-filtered.
    let frame =
        png(4, 4, |x, y| if x == 0 || y == 0 || x == 3 || y == 3 { [255; 4] } else { [60, 60, 60, 255] });
    // The lamp spans x ∈ [−0.8, 0.8], z ∈ [−1.2, 0.4]: offset to texture coordinates [0, 1]².
    b.texture(
        lamp,
        "emissiveTexture",
        frame,
        json!({"magFilter": NEAREST, "wrapS": CLAMP_TO_EDGE, "wrapT": CLAMP_TO_EDGE}),
        Some(json!({"offset": [0.5, 0.75]})),
        Planar { u: Vec3::X * (1.0 / 1.6), v: Vec3::Z * (1.0 / 1.6) },
    );
    let v = Vec3::new;
    let (w, h) = (2.0f32, 2.4f32);
    b.quad(floor, [v(-w, 0., w), v(w, 0., w), v(w, 0., -w), v(-w, 0., -w)]);
    b.quad(back, [v(-w, 0., -w), v(w, 0., -w), v(w, h, -w), v(-w, h, -w)]);
    b.quad(side, [v(-w, 0., w), v(-w, 0., -w), v(-w, h, -w), v(-w, h, w)]);
    b.quad(plain, [v(w, 0., -w), v(w, 0., w), v(w, h, w), v(w, h, -w)]);
    b.quad(plain, [v(-w, h, -w), v(w, h, -w), v(w, h, w), v(-w, h, w)]);
    b.cuboid(block, v(0.5, 0.35, -0.6), v(0.35, 0.35, 0.35), 0.4);
    let l = [v(-0.8, h - 0.01, -1.2), v(0.8, h - 0.01, -1.2), v(0.8, h - 0.01, 0.4), v(-0.8, h - 0.01, 0.4)];
    b.quad(lamp, super::facing(l, -Vec3::Y));
    b.camera(v(0.0, 1.3, 4.0), v(-0.2, 0.9, -1.0), Vec3::Y, 50f32.to_radians());
    b.to_json()
}
