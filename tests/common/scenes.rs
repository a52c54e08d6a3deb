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

/// The furnace ([`furnace`]) with a solid glass cube (index 1.5, lossless) in front of the
/// camera: lossless glass leaves the furnace's uniform radiance as it is, so every pixel is
/// still `e · Σ_{i=0..k} rho^i`, less the paths that the glass's bounces push past depth k —
/// few for a cube, whose internal reflections keep a direction's component along each axis
/// (a faceted ball traps light by total internal reflection: 2.3 % past depth 8, 0.4 % past 40).
#[allow(dead_code)]
pub fn glass_furnace(e: f32, rho: f32) -> SceneData {
    let mut b = GltfBuilder::new();
    let m = b.material("furnace", [rho; 3], [e, e, e], 1.0, None);
    let glass = b.glass("glass", [1.0; 3], 1.5, true);
    let v = Vec3::new;
    let faces = [
        [v(-1., -1., -1.), v(1., -1., -1.), v(1., -1., 1.), v(-1., -1., 1.)],
        [v(-1., 1., 1.), v(1., 1., 1.), v(1., 1., -1.), v(-1., 1., -1.)],
        [v(-1., -1., 1.), v(1., -1., 1.), v(1., 1., 1.), v(-1., 1., 1.)],
        [v(1., -1., -1.), v(-1., -1., -1.), v(-1., 1., -1.), v(1., 1., -1.)],
        [v(-1., -1., -1.), v(-1., -1., 1.), v(-1., 1., 1.), v(-1., 1., -1.)],
        [v(1., -1., 1.), v(1., -1., -1.), v(1., 1., -1.), v(1., 1., 1.)],
    ];
    for [a, b0, c, d] in faces {
        b.quad(m, [d, c, b0, a]);
    }
    b.cuboid(glass, v(0.0, 0.0, -0.3), v(0.35, 0.35, 0.35), 0.6);
    b.camera(v(0.0, 0.1, 0.85), v(0.0, 0.0, -0.3), Vec3::Y, 60f32.to_radians());
    SceneData::from_slice(b.to_json().as_bytes(), "glass furnace").expect("glass furnace scene")
}

/// A solid glass ball on a floor before a wall, lit from above by a point lamp (`area` false:
/// its caustic under the ball is light no path tracer can find, L S S D E from a delta) or by
/// an area lamp (`area` true: the path tracer's BSDF samples reach it through the glass; a
/// lamp 0.3 m wide made every method's replicas so heavy-tailed that 5 standard errors were
/// crossed by chance, 0.8 m wide does not).
#[allow(dead_code)]
pub fn glass_caustic(area: bool) -> SceneData {
    let mut b = GltfBuilder::new();
    let floor = b.material("floor", [0.6; 3], [0.0; 3], 1.0, None);
    let wall = b.material("wall", [0.5, 0.45, 0.4], [0.0; 3], 1.0, None);
    let glass = b.glass("glass", [0.95, 0.97, 1.0], 1.5, true);
    let v = Vec3::new;
    b.quad(floor, [v(-2., 0., 2.), v(2., 0., 2.), v(2., 0., -2.), v(-2., 0., -2.)]);
    b.quad(wall, [v(-2., 0., -2.), v(2., 0., -2.), v(2., 2., -2.), v(-2., 2., -2.)]);
    b.sphere(glass, v(0.0, 0.5, -0.5), 0.5, 10);
    if area {
        let lamp = b.material("lamp", [0.0; 3], [1.0; 3], 8.0, None);
        let q = [v(-0.4, 2.0, -0.9), v(0.4, 2.0, -0.9), v(0.4, 2.0, -0.1), v(-0.4, 2.0, -0.1)];
        b.quad(lamp, smlt::scenes::facing(q, -Vec3::Y));
    } else {
        b.point_light(v(0.0, 2.0, -0.5), [1.0; 3], 2000.0);
    }
    // A solid block that is partly glass (transmissionFactor 0.5, the rest Lambert): its
    // vertices are left by a delta lobe or by the diffuse one, and a connection evaluates the
    // diffuse one at a vertex the walk left by glass (the weights' mixed case).
    let mixed = b.glass("half glass", [0.9, 0.9, 0.8], 1.5, true);
    b.cuboid(mixed, v(0.9, 0.25, -0.2), v(0.25, 0.25, 0.25), 0.4);
    b.camera(v(0.0, 1.2, 2.5), v(0.0, 0.3, -0.5), Vec3::Y, 45f32.to_radians());
    let mut doc = b.to_value();
    doc["materials"][mixed]["extensions"]["KHR_materials_transmission"]["transmissionFactor"] = 0.5.into();
    SceneData::from_slice(doc.to_string().as_bytes(), "glass caustic").expect("glass caustic scene")
}
