//! `smooth`: coarse spheres with smooth vertex normals (`NORMAL`) in a Lambertian room under a
//! ceiling lamp and a point light — a white Lambertian sphere, a rough gold one (glTF's BRDF)
//! and a solid glass one, five latitude bands each, so that their shading normals bend up to
//! ~20° from the facets' — beside a flat box. The scene of the shading normals' check against
//! Mitsuba 3 and of every method's agreement with them.

use glam::Vec3;

use super::GltfBuilder;

/// Latitude bands of each sphere: coarse, so that the normals bend far.
const RINGS: u32 = 5;

/// The scene, every quad split `tessellation` × `tessellation` times.
pub fn smooth(tessellation: u32) -> String {
    let mut b = GltfBuilder::tessellated(tessellation);
    let wall = b.material("wall", [0.7, 0.7, 0.7], [0.0; 3], 1.0, None);
    let red = b.material("red wall", [0.7, 0.2, 0.15], [0.0; 3], 1.0, None);
    let white = b.material("white ball", [0.8, 0.8, 0.8], [0.0; 3], 1.0, None);
    let gold = b.pbr("gold ball", [1.0, 0.78, 0.34], 1.0, 0.35);
    let glass = b.glass("glass ball", [1.0; 3], 1.5, true);
    let block = b.material("block", [0.3, 0.4, 0.7], [0.0; 3], 1.0, None);
    let lamp = b.material("lamp", [0.0; 3], [1.0, 0.95, 0.85], 10.0, None);
    let v = Vec3::new;
    let (w, h) = (2.0f32, 2.4f32);
    b.quad(wall, [v(-w, 0., w), v(w, 0., w), v(w, 0., -w), v(-w, 0., -w)]);
    b.quad(wall, [v(-w, 0., -w), v(w, 0., -w), v(w, h, -w), v(-w, h, -w)]);
    b.quad(red, [v(-w, 0., w), v(-w, 0., -w), v(-w, h, -w), v(-w, h, w)]);
    b.quad(wall, [v(w, 0., -w), v(w, 0., w), v(w, h, w), v(w, h, -w)]);
    b.quad(wall, [v(-w, h, -w), v(w, h, -w), v(w, h, w), v(-w, h, w)]);
    b.smooth_sphere(white, v(-1.1, 0.55, -0.6), 0.55, RINGS);
    b.smooth_sphere(gold, v(0.1, 0.55, -0.9), 0.55, RINGS);
    b.smooth_sphere(glass, v(1.05, 0.5, -0.1), 0.5, RINGS);
    b.cuboid(block, v(0.9, 0.3, -1.3), v(0.3, 0.3, 0.3), 0.5);
    let l = [v(-0.7, h - 0.01, -1.1), v(0.7, h - 0.01, -1.1), v(0.7, h - 0.01, 0.3), v(-0.7, h - 0.01, 0.3)];
    b.quad(lamp, super::facing(l, -Vec3::Y));
    b.point_light(v(-1.2, 1.9, 1.2), [1.0, 0.9, 0.8], 3.0);
    b.camera(v(0.0, 1.3, 4.0), v(0.0, 0.7, -0.6), Vec3::Y, 45f32.to_radians());
    b.to_json()
}
