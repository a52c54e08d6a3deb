//! `atrium`: a courtyard open to the sky, lit only through its roof opening — a large sky
//! panel above and a small bright sun hung under it (`super::sun_below_sky`) — with columns
//! along two sides and a highly specular banner (Phong exponent 1e5) on the back wall that
//! throws a caustic onto the floor. View 1 looks across the sunlit court (mostly direct light);
//! view 2 looks into the banner, which shows the court and its caustic by reflection (the hard,
//! reflected-caustic case).

use glam::Vec3;

use super::GltfBuilder;

/// The atrium with every quad split `tessellation` × `tessellation` times (60 quads: 120 ×
/// tessellation² triangles; 25 gives 75 000, 52 gives 324 480).
pub fn atrium(tessellation: u32) -> String {
    let mut b = GltfBuilder::tessellated(tessellation);
    let stone = b.material("stone", [0.6, 0.57, 0.52], [0.0; 3], 1.0, None);
    let plaster = b.material("plaster", [0.7, 0.68, 0.64], [0.0; 3], 1.0, None);
    let column = b.material("column", [0.55, 0.5, 0.45], [0.0; 3], 1.0, None);
    let sky = b.material("sky", [0.0; 3], [0.55, 0.7, 1.0], 2.0, None);
    let sun = b.material("sun", [0.0; 3], [1.0, 0.9, 0.75], 4000.0, None);
    let banner = b.material("banner", [0.9, 0.85, 0.6], [0.0; 3], 1.0, Some(1e5));
    let v = Vec3::new;
    let (h, r, o) = (8.0, 5.0, 3.0); // wall height, half width, half opening
    b.quad(stone, [v(-r, 0., r), v(r, 0., r), v(r, 0., -r), v(-r, 0., -r)]); // floor, up
    b.quad(plaster, [v(-r, 0., -r), v(r, 0., -r), v(r, h, -r), v(-r, h, -r)]); // back, +z
    b.quad(plaster, [v(r, 0., r), v(-r, 0., r), v(-r, h, r), v(r, h, r)]); // front, -z
    b.quad(plaster, [v(-r, 0., r), v(-r, 0., -r), v(-r, h, -r), v(-r, h, r)]); // left, +x
    b.quad(plaster, [v(r, 0., -r), v(r, 0., r), v(r, h, r), v(r, h, -r)]); // right, -x
                                                                           // The roof around the opening, facing down into the court.
    b.quad(plaster, [v(-r, h, -r), v(r, h, -r), v(r, h, -o), v(-r, h, -o)]);
    b.quad(plaster, [v(-r, h, o), v(r, h, o), v(r, h, r), v(-r, h, r)]);
    b.quad(plaster, [v(-r, h, -o), v(-o, h, -o), v(-o, h, o), v(-r, h, o)]);
    b.quad(plaster, [v(o, h, -o), v(r, h, -o), v(r, h, o), v(o, h, o)]);
    // Sky panel above the opening, facing down.
    b.quad(sky, [v(-8., 12., -8.), v(8., 12., -8.), v(8., 12., 8.), v(-8., 12., 8.)]);
    // The sun as one of half-size 1 m at (3, 40, 32) would be seen from the banner, hung under the
    // sky panel (which would shadow it); its rays cross the roof plane at z ≈ −1.
    b.quad(sun, super::sun_below_sky(v(3.0, 40.0, 32.0), 1.0, v(0.0, 4.5, -4.6), 11.0));
    // Columns along the left and right walls.
    for x in [-4.2f32, 4.2] {
        for z in [-3.0f32, -1.0, 1.0, 3.0] {
            b.cuboid(column, v(x, h / 2.0, z), v(0.2, h / 2.0, 0.2), 0.0);
        }
    }
    // The banner: 3 × 3 m on the back wall, tilted forward so the sun's reflection falls on the floor.
    let (bx, by, bz) = (1.5f32, 1.5f32, -4.6f32);
    let tilt = 0.35f32;
    let top = v(0.0, 4.5 + by * tilt.cos(), bz - by * tilt.sin());
    let bottom = v(0.0, 4.5 - by * tilt.cos(), bz + by * tilt.sin());
    b.quad(
        banner,
        [bottom + v(-bx, 0., 0.), bottom + v(bx, 0., 0.), top + v(bx, 0., 0.), top + v(-bx, 0., 0.)],
    );
    b.camera(v(4.3, 1.7, 4.6), v(-1.5, 2.2, -2.5), Vec3::Y, 60f32.to_radians()); // view 1
                                                                                 // View 2: high in the court, looking down into the banner, which mirrors the front wall
                                                                                 // where the sun's reflection (the caustic) lands.
    b.camera(v(0.0, 7.0, -1.9), v(0.0, 4.5, -4.6), Vec3::Y, 45f32.to_radians());
    b.to_json()
}
