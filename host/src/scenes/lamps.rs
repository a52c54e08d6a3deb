//! `lamps`: a corner of a room open to the sky, lit only by glTF's punctual lights — a point
//! lamp by the red wall, a spot aimed at the blue block, and a sun (a directional light)
//! slanting in over the walls — with no emissive triangle. The scene of the lamps' tests:
//! every light type, each lighting its own part of the image, with the one-bounce light
//! between the walls, the floor and the blocks.

use glam::Vec3;

use super::GltfBuilder;

/// The scene, every quad split `tessellation` × `tessellation` times.
pub fn lamps(tessellation: u32) -> String {
    let mut b = GltfBuilder::tessellated(tessellation);
    let floor = b.material("floor", [0.6, 0.6, 0.6], [0.0; 3], 1.0, None);
    let back = b.material("back wall", [0.7, 0.68, 0.62], [0.0; 3], 1.0, None);
    let red = b.material("red wall", [0.65, 0.18, 0.15], [0.0; 3], 1.0, None);
    let blue = b.material("blue block", [0.15, 0.3, 0.65], [0.0; 3], 1.0, None);
    let white = b.material("white block", [0.75, 0.75, 0.75], [0.0; 3], 1.0, None);
    let v = Vec3::new;
    let (w, h) = (3.0f32, 2.5f32); // floor x, z ∈ [−w, w]; walls up to h
    b.quad(floor, [v(-w, 0., w), v(w, 0., w), v(w, 0., -w), v(-w, 0., -w)]);
    b.quad(back, [v(-w, 0., -w), v(w, 0., -w), v(w, h, -w), v(-w, h, -w)]);
    b.quad(red, [v(-w, 0., w), v(-w, 0., -w), v(-w, h, -w), v(-w, h, w)]);
    b.cuboid(blue, v(1.0, 0.5, -0.6), v(0.5, 0.5, 0.5), 0.4);
    b.cuboid(white, v(-0.9, 0.9, -1.6), v(0.4, 0.9, 0.4), -0.3);
    b.point_light(v(-2.2, 1.6, 0.4), [1.0, 0.85, 0.7], 1500.0);
    // A nearly hard cone: Mitsuba's spot ramps linearly in angle, glTF's as the square of a
    // ramp in cos θ, and over 0.2° the two differ by < 0.3 % of the spot's light.
    b.spot_light(
        v(2.4, 2.6, 1.8),
        v(1.0, 0.5, -0.6),
        [0.8, 0.9, 1.0],
        6000.0,
        (25.8f32.to_radians(), 26f32.to_radians()),
    );
    b.directional_light(v(0.5, -1.0, -0.6), [1.0, 0.97, 0.9], 400.0);
    b.camera(v(0.4, 1.7, 5.6), v(-0.1, 0.7, -0.8), Vec3::Y, 50f32.to_radians());
    b.to_json()
}
