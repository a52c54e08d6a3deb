//! `nave`: a long hall with a solid ceiling, lit only through five windows in its right wall
//! (emitting panels outside each opening), with two rows of columns: most light reaching the
//! camera has bounced inside the hall.

use glam::Vec3;

use super::GltfBuilder;

/// The nave with every quad split `tessellation` × `tessellation` times (90 quads: 180 ×
/// tessellation² triangles; 21 gives 79 380, 43 gives 332 820).
pub fn nave(tessellation: u32) -> String {
    let mut b = GltfBuilder::tessellated(tessellation);
    let stone = b.material("stone", [0.55, 0.52, 0.48], [0.0; 3], 1.0, None);
    let plaster = b.material("plaster", [0.72, 0.7, 0.66], [0.0; 3], 1.0, None);
    let column = b.material("column", [0.5, 0.47, 0.44], [0.0; 3], 1.0, None);
    let window = b.material("window", [0.0; 3], [1.0, 0.95, 0.85], 12.0, None);
    let v = Vec3::new;
    let (w, l, h) = (4.0, 15.0, 10.0);
    let (sill, head) = (3.0, 6.5);
    let windows = [-12.0f32, -6.0, 0.0, 6.0, 12.0];
    let half = 0.8;
    b.quad(stone, [v(-w, 0., l), v(w, 0., l), v(w, 0., -l), v(-w, 0., -l)]); // floor
    b.quad(plaster, [v(-w, h, -l), v(w, h, -l), v(w, h, l), v(-w, h, l)]); // ceiling, down
    b.quad(plaster, [v(-w, 0., -l), v(w, 0., -l), v(w, h, -l), v(-w, h, -l)]); // far end, +z
    b.quad(plaster, [v(w, 0., l), v(-w, 0., l), v(-w, h, l), v(w, h, l)]); // near end, -z
    b.quad(plaster, [v(-w, 0., l), v(-w, 0., -l), v(-w, h, -l), v(-w, h, l)]); // left, +x
                                                                               // The right wall (x = w, facing −x) around five openings.
    let right = |b: &mut GltfBuilder, z0: f32, z1: f32, y0: f32, y1: f32| {
        b.quad(plaster, [v(w, y0, -z0), v(w, y0, -z1), v(w, y1, -z1), v(w, y1, -z0)]);
    };
    right(&mut b, -l, l, 0.0, sill);
    right(&mut b, -l, l, head, h);
    let mut z = -l;
    for c in windows {
        right(&mut b, z, c - half, sill, head);
        z = c + half;
    }
    right(&mut b, z, l, sill, head);
    // A bright panel outside each opening, facing in.
    for c in windows {
        let panel = [
            v(w + 2.0, sill - 1.0, c + 1.5),
            v(w + 2.0, sill - 1.0, c - 1.5),
            v(w + 2.0, head + 1.0, c - 1.5),
            v(w + 2.0, head + 1.0, c + 1.5),
        ];
        b.quad(window, super::facing(panel, -Vec3::X));
    }
    for x in [-2.2f32, 2.2] {
        for z in [-10.0f32, -6.0, -2.0, 2.0, 6.0, 10.0] {
            b.cuboid(column, v(x, h / 2.0, z), v(0.35, h / 2.0, 0.35), 0.0);
        }
    }
    b.camera(v(-0.5, 1.7, 14.0), v(0.6, 3.5, -15.0), Vec3::Y, 55f32.to_radians());
    b.to_json()
}
