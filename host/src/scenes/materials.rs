//! `materials`: glTF's metallic-roughness BRDF on a floor before a wall, each lobe it has — a
//! rough gold ball (metal, roughness 0.35), a red plastic block (the dielectric layer over a
//! diffuse base, roughness 0.3), a smooth mirror slab (metal, roughness 0: a delta lobe), a
//! satin-white ball (the layer at roughness 0.6) and a cube with glTF's defaults (a rough metal)
//! — under a large area lamp and a small one, so that a path tracer renders every path: the
//! scene of the BRDF's check against Mitsuba 3 (`scripts/peers/check_materials.sh`).

use glam::Vec3;

use super::GltfBuilder;

/// The scene, every quad split `tessellation` × `tessellation` times.
pub fn materials(tessellation: u32) -> String {
    let mut b = GltfBuilder::tessellated(tessellation);
    let floor = b.material("floor", [0.6, 0.6, 0.6], [0.0; 3], 1.0, None);
    let wall = b.material("wall", [0.7, 0.68, 0.62], [0.0; 3], 1.0, None);
    let gold = b.pbr("gold", [1.0, 0.78, 0.34], 1.0, 0.35);
    let plastic = b.pbr("red plastic", [0.7, 0.1, 0.08], 0.0, 0.3);
    let mirror = b.pbr("mirror", [0.95, 0.95, 0.95], 1.0, 0.0);
    let satin = b.pbr("satin white", [0.8, 0.8, 0.78], 0.0, 0.6);
    let defaults = b.pbr("glTF defaults", [0.6, 0.6, 0.6], 1.0, 1.0);
    let lamp = b.material("lamp", [0.0; 3], [1.0, 0.95, 0.85], 6.0, None);
    let v = Vec3::new;
    b.sphere(gold, v(-1.1, 0.45, -0.3), 0.45, 24);
    b.cuboid(plastic, v(0.2, 0.3, -0.6), v(0.3, 0.3, 0.3), 0.5);
    b.cuboid(mirror, v(0.3, 0.7, -2.2), v(0.9, 0.7, 0.04), -0.25);
    b.sphere(satin, v(1.3, 0.4, 0.1), 0.4, 24);
    b.cuboid(defaults, v(-0.2, 0.2, 0.6), v(0.2, 0.2, 0.2), 0.3);
    studio(&mut b, floor, wall, lamp);
    b.to_json()
}

/// The room the material scenes stand in (`materials`, `coated`): a floor of `floor` and a
/// wall of `wall`, a large area lamp and a small one of `lamp`, and the camera.
pub fn studio(b: &mut GltfBuilder, floor: usize, wall: usize, lamp: usize) {
    let v = Vec3::new;
    let (w, h) = (3.0f32, 2.5f32);
    b.quad(floor, [v(-w, 0., w), v(w, 0., w), v(w, 0., -w), v(-w, 0., -w)]);
    b.quad(wall, [v(-w, 0., -w), v(w, 0., -w), v(w, h, -w), v(-w, h, -w)]);
    let big = [v(-1.2, 2.4, -1.2), v(0.4, 2.4, -1.2), v(0.4, 2.4, 0.2), v(-1.2, 2.4, 0.2)];
    b.quad(lamp, super::facing(big, -Vec3::Y));
    let small = [v(1.4, 1.8, 0.8), v(1.7, 1.8, 0.8), v(1.7, 1.8, 1.1), v(1.4, 1.8, 1.1)];
    b.quad(lamp, super::facing(small, -Vec3::Y));
    b.camera(v(0.3, 1.5, 4.2), v(0.0, 0.45, -0.6), Vec3::Y, 45f32.to_radians());
}
