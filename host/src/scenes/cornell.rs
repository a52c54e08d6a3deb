//! The embedded default scene: a Cornell-style box — white, red and green diffuse walls, one
//! area light in the ceiling (emission given through `KHR_materials_emissive_strength`), a
//! glossy Phong block and a diffuse block, and a camera looking in through the open front.

use glam::Vec3;

use super::GltfBuilder;

/// The default scene as glTF JSON (also kept as `scenes/cornell.gltf`).
pub fn cornell() -> String {
    let mut b = GltfBuilder::new();
    let white = b.material("white", [0.73, 0.73, 0.73], [0.0; 3], 1.0, None);
    let red = b.material("red", [0.63, 0.065, 0.05], [0.0; 3], 1.0, None);
    let green = b.material("green", [0.14, 0.45, 0.091], [0.0; 3], 1.0, None);
    let light = b.material("light", [0.78, 0.78, 0.78], [1.0, 0.72, 0.32], 17.0, None);
    let glossy = b.material("glossy", [0.8, 0.8, 0.8], [0.0; 3], 1.0, Some(200.0));
    let v = Vec3::new;
    // The box spans x, z ∈ [−1, 1], y ∈ [0, 2]; walls face inwards, the front is open.
    b.quad(white, [v(-1., 0., 1.), v(1., 0., 1.), v(1., 0., -1.), v(-1., 0., -1.)]); // floor
    b.quad(white, [v(-1., 2., -1.), v(1., 2., -1.), v(1., 2., 1.), v(-1., 2., 1.)]); // ceiling
    b.quad(white, [v(-1., 0., -1.), v(1., 0., -1.), v(1., 2., -1.), v(-1., 2., -1.)]); // back
    b.quad(red, [v(-1., 0., 1.), v(-1., 0., -1.), v(-1., 2., -1.), v(-1., 2., 1.)]); // left
    b.quad(green, [v(1., 0., -1.), v(1., 0., 1.), v(1., 2., 1.), v(1., 2., -1.)]); // right
                                                                                   // The light, just below the ceiling, facing down.
    b.quad(light, [v(-0.25, 1.98, -0.25), v(0.25, 1.98, -0.25), v(0.25, 1.98, 0.25), v(-0.25, 1.98, 0.25)]);
    b.cuboid(glossy, v(-0.35, 0.6, -0.35), v(0.3, 0.6, 0.3), 0.3);
    b.cuboid(white, v(0.4, 0.3, 0.35), v(0.3, 0.3, 0.3), -0.3);
    b.camera(v(0.0, 1.0, 3.9), v(0.0, 1.0, 0.0), Vec3::Y, 40f32.to_radians());
    b.to_json()
}
