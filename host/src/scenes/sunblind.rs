//! `sunblind`: a closed room lit only through a window covered by a closed Venetian blind. The
//! light (a panel outside, above the window, shining down and in) falls on the slats' upper
//! faces; the slats descend outwards and overlap, so no straight line joins the room to the
//! light, and light enters only after bouncing off a slat's upper face and the underside of the
//! slat above — the camera sees it after at least two bounces.

use glam::Vec3;

use super::GltfBuilder;

/// The room with every quad split `tessellation` × `tessellation` times (58 quads: 116 ×
/// tessellation² triangles; 26 gives 78 416, 53 gives 325 844).
pub fn sunblind(tessellation: u32) -> String {
    let mut b = GltfBuilder::tessellated(tessellation);
    let wall = b.material("wall", [0.75, 0.73, 0.7], [0.0; 3], 1.0, None);
    let floor = b.material("floor", [0.45, 0.35, 0.25], [0.0; 3], 1.0, None);
    let slat = b.material("slat", [0.85, 0.85, 0.85], [0.0; 3], 1.0, None);
    let table = b.material("table", [0.5, 0.4, 0.3], [0.0; 3], 1.0, None);
    let sun = b.material("sun", [0.0; 3], [1.0, 0.92, 0.8], 40.0, None);
    let v = Vec3::new;
    let (r, h) = (3.0, 3.0);
    let (z0, z1, y0, y1) = (-1.5f32, 1.5f32, 0.8f32, 2.4f32); // the window in the wall x = r
    b.quad(floor, [v(-r, 0., r), v(r, 0., r), v(r, 0., -r), v(-r, 0., -r)]);
    b.quad(wall, [v(-r, h, -r), v(r, h, -r), v(r, h, r), v(-r, h, r)]);
    b.quad(wall, [v(-r, 0., -r), v(r, 0., -r), v(r, h, -r), v(-r, h, -r)]);
    b.quad(wall, [v(r, 0., r), v(-r, 0., r), v(-r, h, r), v(r, h, r)]);
    b.quad(wall, [v(-r, 0., r), v(-r, 0., -r), v(-r, h, -r), v(-r, h, r)]);
    let window_wall = |b: &mut GltfBuilder, za: f32, zb: f32, ya: f32, yb: f32| {
        b.quad(wall, [v(r, ya, -za), v(r, ya, -zb), v(r, yb, -zb), v(r, yb, -za)]);
    };
    window_wall(&mut b, -r, r, 0.0, y0);
    window_wall(&mut b, -r, r, y1, h);
    window_wall(&mut b, -r, z0, y0, y1);
    window_wall(&mut b, z1, r, y0, y1);
    // Slats just outside the opening, descending outwards at 45°. A line from the room to the
    // panel rises outwards with slope s ≥ 0.65 (the panel's nearest edge); slats of length L at
    // pitch p block every such line when L > p·√2/(1 + s) — here L = 0.099 > 0.069.
    let (depth, pitch) = (0.035f32, 0.08f32);
    // The stack reaches past the opening above and below and spans the whole wall, so no line
    // slips over the top slat or around the slat ends.
    let mut y = y0 - pitch;
    while y < y1 + 2.0 * pitch {
        let inner = v(r + 0.05, y + depth, 0.0);
        let outer = v(r + 0.05 + 2.0 * depth, y - depth, 0.0);
        b.quad(
            slat,
            [inner + v(0., 0., r), inner + v(0., 0., -r), outer + v(0., 0., -r), outer + v(0., 0., r)],
        );
        y += pitch;
    }
    // The light: a panel outside and above the window, facing down towards the slats.
    let panel = [v(r + 1.0, 5.0, r), v(r + 4.0, 5.0, r), v(r + 4.0, 5.0, -r), v(r + 1.0, 5.0, -r)];
    b.quad(sun, super::facing(panel, -Vec3::Y));
    // A table and two cabinets.
    b.cuboid(table, v(-0.5, 0.72, 0.0), v(1.0, 0.03, 0.6), 0.0);
    b.cuboid(table, v(-0.5, 0.35, 0.0), v(0.08, 0.35, 0.08), 0.0);
    b.cuboid(table, v(-2.6, 0.9, -2.0), v(0.35, 0.9, 0.8), 0.0);
    b.cuboid(table, v(-2.6, 0.9, 2.0), v(0.35, 0.9, 0.8), 0.0);
    b.camera(v(-1.6, 1.6, 2.7), v(1.5, 1.1, -0.8), Vec3::Y, 60f32.to_radians());
    b.to_json()
}
