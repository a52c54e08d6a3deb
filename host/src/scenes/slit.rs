//! `slit`: two closed rooms side by side, joined only by a narrow vertical slit in the wall
//! between them. The light is a ceiling panel in the first room; the camera stands in the
//! second, which is lit only through the slit (a beam on its floor and far wall, and what
//! bounces from there). Few of the paths that the bootstrap and the large steps draw carry
//! light, so b is hard to estimate: the scene for the normalisation's convergence.

use glam::Vec3;

use super::GltfBuilder;

/// The two rooms, every quad split `tessellation` × `tessellation` times.
pub fn slit(tessellation: u32) -> String {
    let mut b = GltfBuilder::tessellated(tessellation);
    let wall = b.material("wall", [0.75, 0.74, 0.72], [0.0; 3], 1.0, None);
    let floor = b.material("floor", [0.55, 0.45, 0.35], [0.0; 3], 1.0, None);
    let block = b.material("block", [0.3, 0.45, 0.6], [0.0; 3], 1.0, None);
    let lamp = b.material("lamp", [0.0; 3], [1.0, 0.95, 0.85], 12.0, None);
    let v = Vec3::new;
    let (w, h, d) = (4.0f32, 3.0f32, 2.0f32); // each room: x ∈ [−w, 0] or [0, w], y ∈ [0, h], z ∈ [−d, d]
    for (x0, x1) in [(-w, 0.0), (0.0, w)] {
        b.quad(floor, [v(x0, 0., d), v(x1, 0., d), v(x1, 0., -d), v(x0, 0., -d)]);
        b.quad(wall, [v(x0, h, -d), v(x1, h, -d), v(x1, h, d), v(x0, h, d)]);
        b.quad(wall, [v(x0, 0., -d), v(x1, 0., -d), v(x1, h, -d), v(x0, h, -d)]);
        b.quad(wall, [v(x1, 0., d), v(x0, 0., d), v(x0, h, d), v(x1, h, d)]);
    }
    b.quad(wall, [v(-w, 0., d), v(-w, 0., -d), v(-w, h, -d), v(-w, h, d)]);
    b.quad(wall, [v(w, 0., -d), v(w, 0., d), v(w, h, d), v(w, h, -d)]);
    // The wall x = 0 with the slit z ∈ [−s, s], y ∈ [y0, y1].
    let (s, y0, y1) = (0.04f32, 0.4f32, 2.6f32);
    let part = |b: &mut GltfBuilder, za: f32, zb: f32, ya: f32, yb: f32| {
        b.quad(wall, [v(0., ya, za), v(0., ya, zb), v(0., yb, zb), v(0., yb, za)]);
    };
    part(&mut b, -d, d, 0.0, y0);
    part(&mut b, -d, d, y1, h);
    part(&mut b, -d, -s, y0, y1);
    part(&mut b, s, d, y0, y1);
    // The lamp: a panel under the first room's ceiling, shining down.
    let panel =
        [v(-3.0, h - 0.01, -1.0), v(-1.5, h - 0.01, -1.0), v(-1.5, h - 0.01, 1.0), v(-3.0, h - 0.01, 1.0)];
    b.quad(lamp, super::facing(panel, -Vec3::Y));
    // A block in the second room, in the beam's way.
    b.cuboid(block, v(2.2, 0.4, 0.3), v(0.4, 0.4, 0.4), 0.5);
    // The camera in the second room, looking back towards the slit and the lit floor.
    b.camera(v(3.8, 2.2, 1.8), v(0.8, 0.5, -0.4), Vec3::Y, 65f32.to_radians());
    b.to_json()
}
