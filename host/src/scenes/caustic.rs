//! `caustic`: glass on a floor before a wall — a clear solid ball, an amber block that
//! absorbs by Beer–Lambert (`KHR_materials_volume`) and a thin-walled pane — under a spot lamp
//! aimed through the ball and a small area lamp. The spot's caustic under the ball (light
//! L S S D E from a delta light) is light no path tracer finds; the area lamp's is light a
//! path tracer finds only by BSDF sampling through the glass. The showcase of the glass and
//! the scene of its tests against Mitsuba (with the spot removed, where Mitsuba's path tracer
//! renders every path).

use glam::Vec3;

use super::GltfBuilder;

/// The scene, every quad split `tessellation` × `tessellation` times.
pub fn caustic(tessellation: u32) -> String {
    let mut b = GltfBuilder::tessellated(tessellation);
    let floor = b.material("floor", [0.6, 0.6, 0.6], [0.0; 3], 1.0, None);
    let wall = b.material("wall", [0.7, 0.68, 0.62], [0.0; 3], 1.0, None);
    let clear = b.glass("clear glass", [1.0; 3], 1.5, true);
    let amber = b.glass("amber glass", [1.0; 3], 1.5, true);
    b.attenuation(amber, [0.9, 0.55, 0.2], 0.6);
    let pane = b.glass("thin pane", [0.85, 0.95, 0.9], 1.5, false);
    let lamp = b.material("lamp", [0.0; 3], [1.0, 0.95, 0.85], 25.0, None);
    let v = Vec3::new;
    let (w, h) = (3.0f32, 2.5f32);
    b.quad(floor, [v(-w, 0., w), v(w, 0., w), v(w, 0., -w), v(-w, 0., -w)]);
    b.quad(wall, [v(-w, 0., -w), v(w, 0., -w), v(w, h, -w), v(-w, h, -w)]);
    b.sphere(clear, v(-0.6, 0.5, -0.4), 0.5, 24);
    b.cuboid(amber, v(0.9, 0.3, -0.9), v(0.3, 0.3, 0.3), 0.5);
    // The pane stands upright, its faces towards the camera.
    b.quad(pane, [v(1.2, 0., 0.5), v(2.0, 0., 0.2), v(2.0, 1.0, 0.2), v(1.2, 1.0, 0.5)]);
    let q = [v(0.6, 2.4, 0.4), v(1.0, 2.4, 0.4), v(1.0, 2.4, 0.8), v(0.6, 2.4, 0.8)];
    b.quad(lamp, super::facing(q, -Vec3::Y));
    b.spot_light(
        v(-0.6, 2.4, -0.4),
        v(-0.6, 0.0, -0.4),
        [1.0, 0.97, 0.9],
        2000.0,
        (19.8f32.to_radians(), 20f32.to_radians()),
    );
    b.camera(v(0.3, 1.6, 4.2), v(0.0, 0.4, -0.5), Vec3::Y, 45f32.to_radians());
    b.to_json()
}
