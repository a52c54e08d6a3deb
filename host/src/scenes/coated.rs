//! `coated`: glTF's clear coat (`KHR_materials_clearcoat`) over each kind of base, on a floor
//! before a wall — a red paint ball (the glTF BRDF's dielectric over a red base, roughness 0.5)
//! under a smooth coat, a blue metallic paint ball (metal, roughness 0.45) under a glossy coat
//! (roughness 0.1), a white lacquered block (Lambert) under a rough coat (0.3), a black piano
//! slab (a black Lambert base: the coat alone reflects) under a smooth coat, and rough gold
//! under a half-strength smooth coat — in the `materials` scene's room (`super::materials::studio`: a
//! floor, a wall, a large area lamp and a small one): the scene of
//! the coat's check against Mitsuba 3 (`scripts/peers/check_clearcoat.sh`).

use glam::Vec3;

use super::GltfBuilder;

/// The scene, every quad split `tessellation` × `tessellation` times.
pub fn coated(tessellation: u32) -> String {
    let mut b = GltfBuilder::tessellated(tessellation);
    let floor = b.material("floor", [0.6, 0.6, 0.6], [0.0; 3], 1.0, None);
    let wall = b.material("wall", [0.7, 0.68, 0.62], [0.0; 3], 1.0, None);
    let red = b.pbr("red paint", [0.6, 0.05, 0.04], 0.0, 0.5);
    b.clearcoat(red, 1.0, 0.0);
    let blue = b.pbr("blue metallic paint", [0.1, 0.2, 0.6], 1.0, 0.45);
    b.clearcoat(blue, 1.0, 0.1);
    let white = b.material("white lacquer", [0.8, 0.8, 0.78], [0.0; 3], 1.0, None);
    b.clearcoat(white, 1.0, 0.3);
    let black = b.material("black piano", [0.0; 3], [0.0; 3], 1.0, None);
    b.clearcoat(black, 1.0, 0.0);
    let gold = b.pbr("coated gold", [1.0, 0.78, 0.34], 1.0, 0.4);
    b.clearcoat(gold, 0.5, 0.0);
    let lamp = b.material("lamp", [0.0; 3], [1.0, 0.95, 0.85], 6.0, None);
    let v = Vec3::new;
    b.sphere(red, v(-1.1, 0.45, -0.3), 0.45, 24);
    b.sphere(blue, v(1.3, 0.4, 0.1), 0.4, 24);
    b.cuboid(white, v(0.2, 0.3, -0.6), v(0.3, 0.3, 0.3), 0.5);
    b.cuboid(black, v(0.3, 0.7, -2.2), v(0.9, 0.7, 0.04), -0.25);
    b.cuboid(gold, v(-0.2, 0.2, 0.6), v(0.2, 0.2, 0.2), 0.3);
    super::materials::studio(&mut b, floor, wall, lamp);
    b.to_json()
}
