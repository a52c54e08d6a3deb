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

/// The glass scenes' stage: a 4 m square grey floor at y = 0 and a warm wall at its back
/// (z = −2) of `height`; their materials are the document's first two.
fn floor_and_wall(b: &mut GltfBuilder, height: f32) {
    let floor = b.material("floor", [0.6; 3], [0.0; 3], 1.0, None);
    let wall = b.material("wall", [0.5, 0.45, 0.4], [0.0; 3], 1.0, None);
    let v = Vec3::new;
    b.quad(floor, [v(-2., 0., 2.), v(2., 0., 2.), v(2., 0., -2.), v(-2., 0., -2.)]);
    b.quad(wall, [v(-2., 0., -2.), v(2., 0., -2.), v(2., height, -2.), v(-2., height, -2.)]);
}

/// A solid glass ball on a floor before a wall, lit from above by a point lamp (`area` false:
/// its caustic under the ball is light no path tracer can find, L S S D E from a delta) or by
/// an area lamp (`area` true: the path tracer's BSDF samples reach it through the glass; a
/// lamp 0.3 m wide made every method's replicas so heavy-tailed that 5 standard errors were
/// crossed by chance, 0.8 m wide does not).
#[allow(dead_code)]
pub fn glass_caustic(area: bool) -> SceneData {
    let mut b = GltfBuilder::new();
    floor_and_wall(&mut b, 2.0);
    let glass = b.glass("glass", [0.95, 0.97, 1.0], 1.5, true);
    let v = Vec3::new;
    b.sphere(glass, v(0.0, 0.5, -0.5), 0.5, 10);
    if area {
        let lamp = b.material("lamp", [0.0; 3], [1.0; 3], 8.0, None);
        let q = [v(-0.4, 2.0, -0.9), v(0.4, 2.0, -0.9), v(0.4, 2.0, -0.1), v(-0.4, 2.0, -0.1)];
        b.quad(lamp, smlt::scenes::facing(q, -Vec3::Y));
    } else {
        b.point_light(v(0.0, 2.0, -0.5), [1.0; 3], 2000.0);
    }
    // A solid block that is partly glass (transmissionFactor 0.5, the rest glTF's BRDF: a
    // smooth dielectric layer over diffuse): its vertices are left by a delta lobe or by the
    // diffuse one, and a connection evaluates the diffuse one at a vertex the walk left by glass
    // (the weights' mixed case).
    let mixed = b.glass("half glass", [0.9, 0.9, 0.8], 1.5, true);
    b.cuboid(mixed, v(0.9, 0.25, -0.2), v(0.25, 0.25, 0.25), 0.4);
    b.camera(v(0.0, 1.2, 2.5), v(0.0, 0.3, -0.5), Vec3::Y, 45f32.to_radians());
    let mut doc = b.to_value();
    doc["materials"][mixed]["extensions"]["KHR_materials_transmission"]["transmissionFactor"] = 0.5.into();
    SceneData::from_slice(doc.to_string().as_bytes(), "glass caustic").expect("glass caustic scene")
}

/// Shading normals far from the geometry's: a Lambertian floor whose `NORMAL`s all lean 40°
/// towards +x, before a wall, under an area lamp — light the floor scatters onto the wall is
/// importance scattered off a bent normal wherever a light subpath carries it, so the
/// bidirectional methods agree with the path tracer (radiance only) only through Veach's
/// adjoint cosine. (Coarse smooth spheres bend too little for that: their normals' errors are
/// second order near normal incidence.)
#[allow(dead_code)]
pub fn bent_floor() -> SceneData {
    let mut b = GltfBuilder::new();
    let floor = b.material("floor", [0.8; 3], [0.0; 3], 1.0, None);
    let wall = b.material("wall", [0.5, 0.45, 0.4], [0.0; 3], 1.0, None);
    let v = Vec3::new;
    let lean = 40f32.to_radians();
    b.bent_quad(
        floor,
        [v(-2., 0., 2.), v(2., 0., 2.), v(2., 0., -2.), v(-2., 0., -2.)],
        v(lean.sin(), lean.cos(), 0.0),
    );
    b.quad(wall, [v(-2., 0., -2.), v(2., 0., -2.), v(2., 2.0, -2.), v(-2., 2.0, -2.)]);
    let lamp = b.material("lamp", [0.0; 3], [1.0; 3], 8.0, None);
    let q = [v(-0.4, 1.5, -0.9), v(0.4, 1.5, -0.9), v(0.4, 1.5, -0.1), v(-0.4, 1.5, -0.1)];
    b.quad(lamp, smlt::scenes::facing(q, -Vec3::Y));
    b.camera(v(0.0, 1.2, 2.5), v(0.0, 0.6, -1.0), Vec3::Y, 45f32.to_radians());
    SceneData::from_slice(b.to_json().as_bytes(), "bent floor").expect("bent floor scene")
}

/// A frosted glass ball (a rough dielectric, roughness `roughness`, α its square) on a floor
/// before a wall and a frosted thin pane of the same roughness (a thin wall, tinted) held level
/// beside it, lit by a point lamp above them: their caustics, light through rough glass onto
/// the floor, every method renders, the path tracer by light sampling at the glass.
#[allow(dead_code)]
pub fn rough_glass_caustic(roughness: f32) -> SceneData {
    let mut b = GltfBuilder::new();
    floor_and_wall(&mut b, 2.0);
    let glass = b.glass("frosted", [0.95, 0.97, 1.0], 1.5, true);
    b.roughness(glass, roughness);
    let v = Vec3::new;
    b.sphere(glass, v(0.0, 0.5, -0.5), 0.5, 10);
    let pane = b.glass("frosted pane", [0.9, 0.8, 0.6], 1.5, false);
    b.roughness(pane, roughness);
    let q = [v(-1.3, 0.9, -1.0), v(-0.6, 0.9, -1.0), v(-0.6, 0.9, -0.2), v(-1.3, 0.9, -0.2)];
    b.quad(pane, smlt::scenes::facing(q, Vec3::Y));
    b.point_light(v(0.3, 2.0, -0.5), [1.0; 3], 2000.0);
    b.camera(v(0.0, 1.2, 2.5), v(0.0, 0.3, -0.5), Vec3::Y, 45f32.to_radians());
    SceneData::from_slice(b.to_json().as_bytes(), "rough glass caustic").expect("rough glass caustic")
}

/// A 32 × 16 sky for the environment tests: a blue gradient from the zenith, a dark ground
/// below the horizon, a warm band, and a small bright sun (2 × 1 texels) that holds about a
/// third of its power.
#[allow(dead_code)]
pub fn sky_map(rotation_degrees: f32) -> shared::environment::EnvironmentMap {
    let (w, h) = (32u32, 16u32);
    let mut texels = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let rgb = if j >= h / 2 {
                [0.05, 0.04, 0.03]
            } else if (i == 9 || i == 10) && j == 4 {
                [60.0, 55.0, 45.0]
            } else if j == h / 2 - 1 {
                [0.9, 0.6, 0.3]
            } else {
                let t = j as f32 / (h / 2) as f32;
                [0.2 + 0.4 * t, 0.35 + 0.4 * t, 0.8 + 0.1 * t]
            };
            texels.push(rgb);
        }
    }
    shared::environment::EnvironmentMap::new(w, h, &texels, rotation_degrees.to_radians())
}

/// A constant environment of radiance `l` (what `--environment l,l,l` builds).
#[allow(dead_code)]
pub fn uniform_sky(l: f32) -> shared::environment::EnvironmentMap {
    smlt::scene::EnvironmentSpec { source: format!("{l}"), strength: 1.0, rotation_degrees: 0.0 }
        .read()
        .expect("a constant environment")
}

/// The environment furnace: one convex object under a uniform environment of radiance 1 and
/// nothing else. A convex object sees only the environment, so a Lambertian cube of albedo
/// `rho` sends exactly `rho` wherever it is seen (one bounce), and a lossless glass cube sends
/// exactly 1 (less what its internal reflections push past the depth limit). With `fill`, the
/// camera is close enough for the object to fill the view; otherwise it sees the object and the
/// environment around it (radiance 1 there), so with `rho` = 1 every pixel is 1.
#[allow(dead_code)]
pub fn environment_furnace(rho: f32, glass: bool, fill: bool) -> SceneData {
    let mut b = GltfBuilder::new();
    let m = if glass {
        b.glass("glass", [1.0; 3], 1.5, true)
    } else {
        b.material("cube", [rho; 3], [0.0; 3], 1.0, None)
    };
    let v = Vec3::new;
    b.cuboid(m, v(0.0, 0.0, 0.0), v(0.5, 0.5, 0.5), 0.5);
    let eye = if fill { v(0.0, 0.15, 0.95) } else { v(0.4, 0.9, 2.2) };
    b.camera(eye, v(0.0, 0.0, 0.0), Vec3::Y, if fill { 30f32 } else { 50f32 }.to_radians());
    SceneData::from_slice_with_environment(
        b.to_json().as_bytes(),
        "environment furnace",
        Some(uniform_sky(1.0)),
    )
    .expect("environment furnace")
}

/// Under the sky (`sky_map`, turned 30°) and a small area lamp: a floor, a wall, a diffuse
/// block, a solid glass ball and a frosted (rough, α 0.25) glass cube — the environment
/// reached by camera paths and by light sampling, left by light subpaths, seen through smooth
/// and rough glass and mixed with a triangle light.
#[allow(dead_code)]
pub fn sky_scene() -> SceneData {
    let mut b = GltfBuilder::new();
    floor_and_wall(&mut b, 1.2);
    let block = b.material("block", [0.3, 0.5, 0.7], [0.0; 3], 1.0, None);
    let glass = b.glass("glass", [0.95, 0.97, 1.0], 1.5, true);
    let lamp = b.material("lamp", [0.0; 3], [1.0; 3], 6.0, None);
    let v = Vec3::new;
    b.cuboid(block, v(0.9, 0.3, -0.6), v(0.3, 0.3, 0.3), 0.4);
    b.sphere(glass, v(-0.4, 0.45, -0.2), 0.45, 10);
    let frosted = b.glass("frosted", [0.9, 0.95, 1.0], 1.5, true);
    b.roughness(frosted, 0.5);
    // Clear of the floor: a face on the floor's plane would make the hit a toss-up.
    b.cuboid(frosted, v(0.35, 0.25, 0.5), v(0.2, 0.2, 0.2), 0.3);
    let q = [v(-1.6, 1.0, -1.9), v(-1.0, 1.0, -1.9), v(-1.0, 1.0, -1.3), v(-1.6, 1.0, -1.3)];
    b.quad(lamp, smlt::scenes::facing(q, -Vec3::Y));
    b.camera(v(0.0, 1.3, 2.6), v(0.0, 0.4, -0.5), Vec3::Y, 50f32.to_radians());
    SceneData::from_slice_with_environment(b.to_json().as_bytes(), "sky scene", Some(sky_map(30.0)))
        .expect("sky scene")
}

/// The lighting and view of the material scenes (`brdf_scene`, `coated_scene`): an area lamp
/// above them, or with `point` a point lamp, and the camera.
fn lamp_and_camera(b: &mut GltfBuilder, point: bool) {
    let v = Vec3::new;
    if point {
        b.point_light(v(0.4, 2.0, 0.2), [1.0; 3], 2000.0);
    } else {
        let lamp = b.material("lamp", [0.0; 3], [1.0; 3], 8.0, None);
        let q = [v(-0.4, 2.0, -0.6), v(0.4, 2.0, -0.6), v(0.4, 2.0, 0.2), v(-0.4, 2.0, 0.2)];
        b.quad(lamp, smlt::scenes::facing(q, -Vec3::Y));
    }
    b.camera(v(0.0, 1.2, 2.5), v(0.0, 0.35, -0.5), Vec3::Y, 50f32.to_radians());
}

/// glTF's metallic-roughness BRDF on every kind of lobe, on a Lambert floor before a wall: a
/// rough gold ball (metal, roughness 0.35), a red plastic block (the dielectric layer over a
/// diffuse base, roughness 0.3), a smooth mirror slab (metal, roughness 0: a delta lobe) and a
/// rough grey block with glTF's defaults (metal, roughness 1); lit by an area lamp, or with
/// `point` by a point lamp (whose light off the mirror no path tracer renders).
#[allow(dead_code)]
pub fn brdf_scene(point: bool) -> SceneData {
    let mut b = GltfBuilder::new();
    floor_and_wall(&mut b, 2.0);
    let v = Vec3::new;
    let gold = b.pbr("gold", [1.0, 0.78, 0.34], 1.0, 0.35);
    b.sphere(gold, v(-0.6, 0.4, -0.6), 0.4, 10);
    let plastic = b.pbr("red plastic", [0.7, 0.1, 0.08], 0.0, 0.3);
    b.cuboid(plastic, v(0.5, 0.25, -0.3), v(0.25, 0.25, 0.25), 0.5);
    let mirror = b.pbr("mirror", [0.95, 0.95, 0.95], 1.0, 0.0);
    b.cuboid(mirror, v(0.2, 0.5, -1.5), v(0.5, 0.45, 0.03), 0.2);
    let rough = b.pbr("rough default", [0.6, 0.6, 0.6], 1.0, 1.0);
    b.cuboid(rough, v(-0.9, 0.2, 0.3), v(0.2, 0.2, 0.2), -0.3);
    lamp_and_camera(&mut b, point);
    SceneData::from_slice(b.to_json().as_bytes(), "brdf scene").expect("brdf scene")
}

/// glTF's clear coat (`KHR_materials_clearcoat`) over each kind of base, on a Lambert floor
/// before a wall: a smooth coat over a red plastic ball (the glTF BRDF) whose normal texture
/// ridges the base and not the coat, a glossy coat (0.1) whose own normal texture ridges it
/// over a smooth blue ball, a rough coat (0.3) over
/// a white Lambert block, a half-strength smooth coat over a satin sheen (`KHR_materials_sheen`)
/// over rough gold, and a rough coat (0.2) over a thin glass pane, and a rough coat (0.5) over
/// a black tile; and a sheen alone over a dark red velvet ball; lit by an area lamp, or with
/// `point` by a point lamp (whose light off the smooth coats no path tracer renders).
#[allow(dead_code)]
pub fn coated_scene(point: bool) -> SceneData {
    let mut b = GltfBuilder::new();
    floor_and_wall(&mut b, 2.0);
    let v = Vec3::new;
    // Smooth spheres with ridges: in the base's normal texture under a smooth coat, which keeps
    // the coat's normal unbent; in the coat's own normal texture over a smooth base.
    let ridges = || {
        smlt::scenes::png(6, 1, |x, _| {
            [[128, 128, 255, 255], [165, 128, 245, 255], [100, 140, 248, 255]][(x % 3) as usize]
        })
    };
    let along = smlt::scenes::Planar { u: Vec3::X * 1.5, v: Vec3::Y };
    let paint = b.pbr("red paint", [0.7, 0.1, 0.08], 0.0, 0.5);
    b.clearcoat(paint, 1.0, 0.0);
    b.texture(paint, "normalTexture", ridges(), serde_json::json!({"magFilter": 9729}), None, along);
    b.smooth_sphere(paint, v(-0.6, 0.4, -0.6), 0.4, 10);
    let rippled = b.pbr("rippled coat", [0.2, 0.3, 0.7], 0.0, 0.6);
    b.clearcoat(rippled, 1.0, 0.1);
    b.texture(
        rippled,
        "clearcoatNormalTexture",
        ridges(),
        serde_json::json!({"magFilter": 9729}),
        None,
        along,
    );
    b.smooth_sphere(rippled, v(-1.0, 0.3, -1.4), 0.3, 10);
    let white = b.material("coated white", [0.8; 3], [0.0; 3], 1.0, None);
    b.clearcoat(white, 1.0, 0.3);
    b.cuboid(white, v(0.5, 0.25, -0.3), v(0.25, 0.25, 0.25), 0.5);
    let gold = b.pbr("coated gold", [1.0, 0.78, 0.34], 1.0, 0.4);
    b.clearcoat(gold, 0.5, 0.0);
    // A satin sheen between the coat and the metal.
    b.sheen(gold, [0.9, 0.9, 1.0], 0.3);
    b.cuboid(gold, v(-0.9, 0.2, 0.3), v(0.2, 0.2, 0.2), -0.3);
    let pane = b.glass("coated pane", [0.9, 0.95, 1.0], 1.5, false);
    b.clearcoat(pane, 1.0, 0.2);
    b.cuboid(pane, v(0.2, 0.5, -1.5), v(0.5, 0.45, 0.03), 0.2);
    // A black tile under a rough coat, standing before the camera and lit from above at
    // grazing angles: the coat alone reflects, its weight 4 % seen from the camera and ~20 %
    // seen from the lamp (a light subpath's weight taken at the wrong end shows here).
    let black = b.material("coated black", [0.0; 3], [0.0; 3], 1.0, None);
    b.clearcoat(black, 1.0, 0.5);
    b.cuboid(black, v(0.95, 0.6, -1.0), v(0.3, 0.3, 0.02), -0.3);
    let velvet = b.material("velvet", [0.25, 0.02, 0.04], [0.0; 3], 1.0, None);
    b.sheen(velvet, [0.9, 0.5, 0.7], 0.35);
    b.sphere(velvet, v(0.15, 0.25, 0.45), 0.25, 10);
    lamp_and_camera(&mut b, point);
    SceneData::from_slice(b.to_json().as_bytes(), "coated scene").expect("coated scene")
}

/// Every texture slot glTF has, each with a different sampler: a checker floor (base colour,
/// NEAREST) whose tiles lean four ways (normalTexture, NEAREST), a wall of colour bands (base colour, bilinear, MIRRORED_REPEAT, through a
/// `KHR_texture_transform`) under a sheen whose colour and roughness are a texture of fibres
/// (NEAREST), a smooth ball whose metallic-roughness texture stripes it into rough
/// dielectric, rough metal and a glossier half metal (bilinear), whose transmissionTexture (the
/// same image's red) makes much of the dielectric and some of the half metal a thin wall of
/// glass, and whose normal texture ridges it (bilinear, in MikkTSpace's vertex tangents), and
/// an area lamp whose emissiveTexture is a bright frame round a dim centre (NEAREST,
/// CLAMP_TO_EDGE).
#[allow(dead_code)]
pub fn textured_scene() -> SceneData {
    use serde_json::json;
    use smlt::scenes::{png, Planar};
    let mut b = GltfBuilder::new();
    let v = Vec3::new;
    let floor = b.material("checker", [0.9; 3], [0.0; 3], 1.0, None);
    let checker = png(4, 4, |x, y| if (x + y) % 2 == 0 { [220, 210, 190, 255] } else { [40, 60, 90, 255] });
    b.texture(
        floor,
        "baseColorTexture",
        checker,
        json!({"magFilter": 9728}),
        None,
        Planar { u: Vec3::X, v: Vec3::Z },
    );
    // Its tiles lean four ways (normalTexture, NEAREST, on the same coordinates).
    let lean = png(4, 4, |x, y| {
        [[128, 128, 255, 255], [220, 128, 220, 255], [128, 220, 220, 255], [60, 60, 230, 255]]
            [((x + 2 * y) % 4) as usize]
    });
    b.texture(
        floor,
        "normalTexture",
        lean,
        json!({"magFilter": 9728}),
        None,
        Planar { u: Vec3::X, v: Vec3::Z },
    );
    b.quad(floor, [v(-2., 0., 2.), v(2., 0., 2.), v(2., 0., -2.), v(-2., 0., -2.)]);
    let wall = b.material("bands", [1.0; 3], [0.0; 3], 1.0, None);
    let bands = png(8, 2, |x, y| [(x * 30) as u8, 90 + (y * 60) as u8, 240 - (x * 30) as u8, 255]);
    b.texture(
        wall,
        "baseColorTexture",
        bands,
        json!({"magFilter": 9729, "wrapS": 33648}),
        Some(json!({"rotation": 0.4, "scale": [1.3, 0.7], "offset": [0.1, 0.2]})),
        Planar { u: Vec3::X * 0.5, v: -Vec3::Y * 0.5 },
    );
    // A sheen over the bands, its colour (sRGB) and roughness (alpha) from one texture of
    // fibres (NEAREST).
    b.sheen(wall, [1.0, 0.9, 0.8], 0.9);
    let fibres = png(2, 2, |x, y| [[255, 240, 200, 60], [90, 160, 255, 255]][((x + y) % 2) as usize]);
    for slot in ["sheenColorTexture", "sheenRoughnessTexture"] {
        b.texture(
            wall,
            slot,
            fibres.clone(),
            json!({"magFilter": 9728}),
            None,
            // The bands' coordinates (one projection a material).
            Planar { u: Vec3::X * 0.5, v: -Vec3::Y * 0.5 },
        );
    }
    b.quad(wall, [v(-2., 0., -2.), v(2., 0., -2.), v(2., 2.5, -2.), v(-2., 2.5, -2.)]);
    let ball = b.pbr("striped metal", [0.95, 0.7, 0.4], 1.0, 1.0);
    let stripes =
        png(3, 1, |x, _| [[200, 255, 0, 255], [255, 200, 255, 255], [90, 110, 128, 255]][x as usize]);
    b.transmission(ball, 1.0);
    for slot in ["metallicRoughnessTexture", "transmissionTexture"] {
        b.texture(
            ball,
            slot,
            stripes.clone(),
            json!({"magFilter": 9729}),
            None,
            Planar { u: Vec3::X * 1.5, v: Vec3::Y },
        );
    }
    // Smooth, with a normal texture of ridges on the same coordinates: the curved mesh's
    // vertex tangents are MikkTSpace's (the mesh has no TANGENT).
    let ridges = png(6, 1, |x, _| {
        [[128, 128, 255, 255], [165, 128, 245, 255], [100, 140, 248, 255]][(x % 3) as usize]
    });
    b.texture(
        ball,
        "normalTexture",
        ridges,
        json!({"magFilter": 9729}),
        None,
        Planar { u: Vec3::X * 1.5, v: Vec3::Y },
    );
    b.smooth_sphere(ball, v(-0.3, 0.5, -0.6), 0.5, 10);
    let lamp = b.material("lamp", [0.0; 3], [1.0; 3], 10.0, None);
    let frame =
        png(4, 4, |x, y| if x == 0 || y == 0 || x == 3 || y == 3 { [255; 4] } else { [50, 50, 50, 255] });
    b.texture(
        lamp,
        "emissiveTexture",
        frame,
        json!({"magFilter": 9728, "wrapS": 33071, "wrapT": 33071}),
        Some(json!({"offset": [0.5, 0.5]})),
        Planar { u: Vec3::X * 1.25, v: Vec3::Z * 1.25 },
    );
    let q = [v(-0.4, 2.0, -0.4), v(0.4, 2.0, -0.4), v(0.4, 2.0, 0.4), v(-0.4, 2.0, 0.4)];
    b.quad(lamp, smlt::scenes::facing(q, -Vec3::Y));
    b.camera(v(0.0, 1.2, 2.5), v(0.0, 0.4, -0.5), Vec3::Y, 50f32.to_radians());
    SceneData::from_slice(b.to_json().as_bytes(), "textured scene").expect("textured scene")
}
