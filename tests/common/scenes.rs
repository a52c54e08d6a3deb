//! Small scenes for the tests, built with the project's glTF builder.

use glam::Vec3;
use smlt::scene::SceneData;
use smlt::scenes::GltfBuilder;

/// The furnace: a closed cube whose inward faces all emit `e` and reflect with Lambertian
/// albedo `rho`, the camera inside. Every pixel's radiance with paths of up to `k` bounces is
/// `e · Σ_{i=0..k} rho^i` exactly.
pub fn furnace(e: f32, rho: f32) -> SceneData {
    let mut b = GltfBuilder::new();
    let m = b.material("furnace", [rho; 3], [e, e, e], 1.0, None);
    let v = Vec3::new;
    // The faces of the cube [-1, 1]^3 (the labels name the inward normal after reversal).
    let faces = [
        [v(-1., -1., -1.), v(1., -1., -1.), v(1., -1., 1.), v(-1., -1., 1.)], // floor, normal +y
        [v(-1., 1., 1.), v(1., 1., 1.), v(1., 1., -1.), v(-1., 1., -1.)],     // ceiling, -y
        [v(-1., -1., 1.), v(1., -1., 1.), v(1., 1., 1.), v(-1., 1., 1.)],     // front, -z
        [v(1., -1., -1.), v(-1., -1., -1.), v(-1., 1., -1.), v(1., 1., -1.)], // back, +z
        [v(-1., -1., -1.), v(-1., -1., 1.), v(-1., 1., 1.), v(-1., 1., -1.)], // left, +x
        [v(1., -1., 1.), v(1., -1., -1.), v(1., 1., -1.), v(1., 1., 1.)],     // right, -x
    ];
    for [a, b0, c, d] in faces {
        // Reversed: the corners above run clockwise seen from inside.
        b.quad(m, [d, c, b0, a]);
    }
    b.camera(v(0.1, 0.2, 0.3), v(0.5, 0.1, -1.0), Vec3::Y, 60f32.to_radians());
    SceneData::from_slice(b.to_json().as_bytes(), "furnace").expect("furnace scene")
}

/// Expected furnace radiance: e · Σ_{i=0..k} rho^i.
pub fn furnace_radiance(e: f32, rho: f32, k: u32) -> f64 {
    (0..=k).map(|i| e as f64 * (rho as f64).powi(i as i32)).sum()
}
