//! glTF loading and the BVH.

mod common;

use base64::Engine;
use glam::Vec3;
use serde_json::{json, Value};
use shared::bsdf::Material;
use shared::ray_caster::{Hit, RayCaster, NO_HIT};
use shared::triangle::intersect_triangle;
use smlt::scene::{SceneData, SceneError, TriangleSoup, View};
use smlt::scenes::GltfBuilder;

fn one_light_doc() -> Value {
    let mut b = GltfBuilder::new();
    let m = b.material("lamp", [0.5; 3], [1.0, 0.5, 0.25], 4.0, Some(1e5));
    b.quad(m, [Vec3::new(0., 0., 0.), Vec3::new(1., 0., 0.), Vec3::new(1., 1., 0.), Vec3::new(0., 1., 0.)]);
    b.camera(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 0.5);
    serde_json::from_str(&b.to_json()).unwrap()
}

fn load(doc: &Value) -> Result<SceneData, SceneError> {
    SceneData::from_slice(doc.to_string().as_bytes(), "test")
}

#[test]
fn the_committed_default_scene_is_what_the_generator_writes() {
    let committed = include_str!("../scenes/cornell.gltf");
    assert_eq!(
        committed,
        smlt::scenes::cornell::cornell(),
        "regenerate with `smlt scene cornell --out scenes/cornell.gltf`"
    );
}

#[test]
fn materials_read_emissive_strength_and_the_phong_extra() {
    let scene = load(&one_light_doc()).unwrap();
    let m: &Material = &scene.materials[1];
    assert_eq!(m.emission, [4.0, 2.0, 1.0]);
    assert_eq!(m.albedo, [0.5; 3]);
    assert_eq!(m.phong_exponent, 1e5);
    assert_eq!(scene.materials[0].albedo, [1.0; 3], "glTF's default material");
    assert_eq!(scene.lights.len(), 2);
    // Two equal triangles: each is picked half the time, area 0.5 → area density 1.
    for t in &scene.triangles {
        assert!((t.light_area_pdf - 1.0).abs() < 1e-6);
    }
    let mut doc = one_light_doc();
    doc["materials"][0]["extras"] = json!({"smlt_phong_exponent": "shiny"});
    assert!(matches!(load(&doc), Err(SceneError::Unsupported { .. })));
}

/// Node transforms compose parent × child, with TRS and matrix forms.
#[test]
fn node_transforms_and_the_camera() {
    let mut doc = one_light_doc();
    // Wrap the mesh node in a parent: translate (1, 2, 3), rotate 90° about +Y, scale 2; the
    // child itself is moved by (0, 1, 0) with a matrix.
    let s = std::f32::consts::FRAC_1_SQRT_2;
    doc["nodes"][0]["matrix"] = json!([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1]);
    let parent =
        json!({"children": [0], "translation": [1, 2, 3], "rotation": [0, s, 0, s], "scale": [2, 2, 2]});
    doc["nodes"].as_array_mut().unwrap().push(parent);
    doc["scenes"][0]["nodes"] = json!([2, 1]);
    let scene = load(&doc).unwrap();
    // Vertex (1, 0, 0) → child (1, 1, 0) → scale (2, 2, 0) → rotate about Y (0, 2, −2) → (1, 4, 1).
    let all: Vec<Vec3> =
        scene.triangles.iter().flat_map(|t| [t.v0, t.v1, t.v2]).map(Vec3::from_array).collect();
    assert!(all.iter().any(|v| (*v - Vec3::new(1.0, 4.0, 1.0)).length() < 1e-5), "{all:?}");
    assert!(all.iter().any(|v| (*v - Vec3::new(1.0, 4.0, 3.0)).length() < 1e-5), "origin → (1, 4, 3)");
    // The camera node: at (0, 0, 5) looking at the origin.
    let c = scene.camera;
    assert!((c.position - Vec3::new(0.0, 0.0, 5.0)).length() < 1e-5);
    assert!((c.forward - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-5);
    assert!((c.up - Vec3::Y).length() < 1e-5);
    assert_eq!(c.yfov, 0.5);
}

/// Morph targets (Blender's shape keys) move the vertices by their weights: the node's, else the
/// mesh's; no weights, the base mesh. A displaced normal is normalised again; a weight count that
/// is not the targets' is refused by path.
#[test]
fn morph_targets_move_the_mesh_by_their_weights() {
    let mut doc = one_light_doc();
    let position = doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"].as_u64().unwrap() as usize;
    let n = doc["accessors"][position]["count"].as_u64().unwrap() as usize;
    // One target: every vertex up +z by 1, every normal tilted by +x; and the base normals
    // (the quad faces +z).
    let data: Vec<u8> = [[0f32, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
        .iter()
        .flat_map(|d| std::iter::repeat_n(*d, n))
        .flat_map(|d| d.map(f32::to_le_bytes))
        .flatten()
        .collect();
    let layout: Vec<_> = (0..3).map(|k| (12 * n * k, 12 * n, 5126, "VEC3", false, n)).collect();
    let accessors = push_accessors(&mut doc, &data, &layout);
    for (k, bound) in [[0, 0, 1], [1, 0, 0], [0, 0, 1]].into_iter().enumerate() {
        doc["accessors"][accessors + k]["min"] = json!(bound);
        doc["accessors"][accessors + k]["max"] = json!(bound);
    }
    doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = json!(accessors + 2);
    let base = load(&doc).unwrap();
    assert!(base.normals.iter().all(|n| n.n == [0.0; 9]), "flat: no bent normal stored");
    doc["meshes"][0]["primitives"][0]["targets"] = json!([{"POSITION": accessors, "NORMAL": accessors + 1}]);
    let unweighted = load(&doc).unwrap();
    assert_eq!(unweighted.triangles, base.triangles, "no weights: the base mesh");
    let moved = |scene: &SceneData| {
        let (t, b) = (&scene.triangles[0], &base.triangles[0]);
        Vec3::from_array(t.v0) - Vec3::from_array(b.v0)
    };
    doc["meshes"][0]["weights"] = json!([0.5]);
    let half = load(&doc).unwrap();
    let node = doc["nodes"].as_array().unwrap().iter().position(|n| n["mesh"] == json!(0)).unwrap();
    doc["nodes"][node]["weights"] = json!([1.0]);
    let full = load(&doc).unwrap();
    // The lamp quad's node transform is the identity (one_light_doc).
    assert!((moved(&half) - Vec3::new(0.0, 0.0, 0.5)).length() < 1e-6, "{}", moved(&half));
    assert!((moved(&full) - Vec3::Z).length() < 1e-6, "the node's weights win: {}", moved(&full));
    // The quad faces +z; its normals, given, tilt by +x once displaced: (0, 0, 1) + (1, 0, 0).
    let n = full.normals.iter().find(|n| n.n != [0.0; 9]).expect("bent normals");
    let expected = Vec3::new(1.0, 0.0, 1.0).normalize();
    assert!((Vec3::from_slice(&n.n[..3]) - expected).length() < 1e-6, "{:?}", n.n);
    doc["nodes"][node]["weights"] = json!([1.0, 0.0]);
    let err = load(&doc).unwrap_err().to_string();
    assert!(err.contains("meshes[0].primitives[0]: 2 morph weights for its 1 morph targets"), "{err}");
}

/// The largest difference in any coordinate between the corners of two scenes' triangles, taken
/// in order (scenes of the same triangles, in the same order).
fn largest_vertex_gap(a: &SceneData, b: &SceneData) -> f32 {
    assert_eq!(a.triangles.len(), b.triangles.len());
    let mut largest = 0f32;
    for (t, u) in a.triangles.iter().zip(&b.triangles) {
        for (p, q) in [(t.v0, u.v0), (t.v1, u.v1), (t.v2, u.v2)] {
            largest = largest.max((Vec3::from_array(p) - Vec3::from_array(q)).abs().max_element());
        }
    }
    largest
}

/// The .gltf at `path` (its buffer `round_trip.bin` beside it) loaded with its JSON changed by
/// `edit` (written to a folder of its own, with the buffer).
fn load_edited(path: &std::path::Path, edit: impl FnOnce(&mut Value)) -> SceneData {
    let mut doc: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    edit(&mut doc);
    let dir = std::env::temp_dir().join(format!(
        "smlt-edited-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(path.with_file_name("round_trip.bin"), dir.join("round_trip.bin")).unwrap();
    std::fs::write(dir.join("edited.gltf"), doc.to_string()).unwrap();
    let scene = SceneData::load(&dir.join("edited.gltf")).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    scene
}

/// The widest angle, in degrees, between a smooth triangle's vertex normals and its face's normal.
fn widest_normal_lean(scene: &SceneData) -> f32 {
    let mut widest = 0f32;
    for (t, n) in scene.triangles.iter().zip(&scene.normals) {
        if n.n == [0.0; 9] {
            continue;
        }
        let [a, b, c] = [t.v0, t.v1, t.v2].map(Vec3::from_array);
        let face = (b - a).cross(c - a).normalize();
        for k in 0..3 {
            widest = widest.max(Vec3::from_slice(&n.n[3 * k..3 * k + 3]).angle_between(face).to_degrees());
        }
    }
    widest
}

/// Blender's shape keys as its exporter writes them (`tests/morph/targets`: the round-trip
/// scene's white ball with "squash" at 0.7 and "lift" at 0, two morph targets with those
/// weights) load to the geometry of Blender's own evaluation of the same keys
/// (`tests/morph/baked`: the ball's mesh made from the mix, no keys; `tests/morph/PROVENANCE.md`).
#[test]
fn blender_s_shape_keys_load_as_blender_evaluates_them() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/morph");
    let targets = SceneData::load(&root.join("targets/round_trip.gltf")).unwrap();
    let baked = SceneData::load(&root.join("baked/round_trip.gltf")).unwrap();
    assert!(targets.warnings.is_empty(), "{:?}", targets.warnings);
    assert_eq!(targets.triangles.len(), baked.triangles.len());
    let largest = largest_vertex_gap(&targets, &baked);
    assert!(largest < 1e-5, "vertices {largest} m apart");
    // And not the base sphere: without its weights the file loads the keys' basis.
    let base = load_edited(&root.join("targets/round_trip.gltf"), |doc| {
        for mesh in doc["meshes"].as_array_mut().unwrap() {
            mesh.as_object_mut().unwrap().remove("weights");
        }
    });
    let moved = largest_vertex_gap(&targets, &base);
    assert!(moved > 0.1, "the squash moves the ball's vertices by {moved} m");
    // The ball is flat-shaded: Blender's normals are its faces'. Its targets' NORMAL
    // displacements, added and normalised again as the spec says, lean off the squashed faces'
    // normals a little (a blend of unit normals is not the blended face's normal).
    let widest = widest_normal_lean(&targets);
    assert!(widest < 5.0, "normals {widest}° off their faces");
    println!("the displaced normals lie within {widest:.2}° of their faces");
}

/// Appends `data` to `doc` as a buffer (a data URI) with one view and one accessor for each
/// `(byte offset, byte length, componentType, type, normalized, count)` of `layout`: the first
/// accessor's index.
fn push_accessors(doc: &mut Value, data: &[u8], layout: &[(usize, usize, u32, &str, bool, usize)]) -> usize {
    let buffer = doc["buffers"].as_array().unwrap().len();
    doc["buffers"].as_array_mut().unwrap().push(json!({
        "byteLength": data.len(),
        "uri": format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(data))
    }));
    let (views, accessors) =
        (doc["bufferViews"].as_array().unwrap().len(), doc["accessors"].as_array().unwrap().len());
    for (k, &(offset, length, component, kind, normalized, count)) in layout.iter().enumerate() {
        doc["bufferViews"]
            .as_array_mut()
            .unwrap()
            .push(json!({"buffer": buffer, "byteOffset": offset, "byteLength": length}));
        doc["accessors"].as_array_mut().unwrap().push(json!({
            "bufferView": views + k, "componentType": component, "count": count, "type": kind, "normalized": normalized
        }));
    }
    accessors
}

/// A skinned mesh is drawn where its joints put it (glTF 2.0, "Skins"): each vertex by its
/// joints' world matrices times their inverse bind matrices, blended by its weights (here
/// normalised bytes, 64/255 and 191/255), the skinned node's own transform not applied. A joint
/// outside the scene, a vertex without weight, a weighted joint the skin lacks, a primitive
/// without joints, and a skin on an instanced node are refused by path.
#[test]
fn skinned_meshes_take_their_joints_pose() {
    let base = one_light_doc();
    let node = base["nodes"].as_array().unwrap().iter().position(|n| n["mesh"] == json!(0)).unwrap();
    let position = base["meshes"][0]["primitives"][0]["attributes"]["POSITION"].as_u64().unwrap() as usize;
    let n = base["accessors"][position]["count"].as_u64().unwrap() as usize;
    let s = std::f32::consts::FRAC_1_SQRT_2;
    // Joint "a" at (0, 0, 2); joint "b", its child, turned 90° about z, bound at (1, 0, 0)
    // (its inverse bind matrix moves by −x).
    let mut doc = base.clone();
    let (a, b) = (doc["nodes"].as_array().unwrap().len(), doc["nodes"].as_array().unwrap().len() + 1);
    doc["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!({"name": "a", "translation": [0, 0, 2], "children": [b]}));
    doc["nodes"].as_array_mut().unwrap().push(json!({"name": "b", "rotation": [0, 0, s, s]}));
    doc["scenes"][0]["nodes"].as_array_mut().unwrap().push(json!(a));
    let mut data: Vec<u8> = std::iter::repeat_n([0u8, 1, 0, 0], n).flatten().collect();
    data.extend(std::iter::repeat_n([64u8, 191, 0, 0], n).flatten());
    let binds = [glam::Mat4::IDENTITY, glam::Mat4::from_translation(-Vec3::X)];
    data.extend(binds.iter().flat_map(|m| m.to_cols_array()).flat_map(f32::to_le_bytes));
    let layout = [
        (0, 4 * n, 5121, "VEC4", false, n),
        (4 * n, 4 * n, 5121, "VEC4", true, n),
        (8 * n, 128, 5126, "MAT4", false, 2),
    ];
    let first = push_accessors(&mut doc, &data, &layout);
    doc["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = json!(first);
    doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] = json!(first + 1);
    doc["skins"] = json!([{"joints": [a, b], "inverseBindMatrices": first + 2}]);
    doc["nodes"][node]["skin"] = json!(0);
    doc["nodes"][node]["translation"] = json!([5, 5, 5]); // not applied to a skinned mesh
    let skinned = load(&doc).unwrap();
    assert!(skinned.warnings.is_empty(), "{:?}", skinned.warnings);
    let unskinned = load(&base).unwrap();
    let joint_a = glam::Mat4::from_translation(Vec3::new(0.0, 0.0, 2.0));
    let joint_b = joint_a * glam::Mat4::from_rotation_z(std::f32::consts::FRAC_PI_2) * binds[1];
    let blend = joint_a * (64.0 / 255.0) + joint_b * (191.0 / 255.0);
    assert_eq!(skinned.triangles.len(), unskinned.triangles.len());
    for (t, u) in skinned.triangles.iter().zip(&unskinned.triangles) {
        for (p, q) in [(t.v0, u.v0), (t.v1, u.v1), (t.v2, u.v2)] {
            let expected = blend.transform_point3(Vec3::from_array(q));
            assert!((Vec3::from_array(p) - expected).length() < 1e-5, "{p:?} against {expected}");
        }
    }
    let refused = |doc: &Value| load(doc).unwrap_err().to_string();
    let mut broken = doc.clone();
    broken["scenes"][0]["nodes"].as_array_mut().unwrap().pop();
    let err = refused(&broken);
    assert!(err.contains(&format!("skins[0].joints[0]: nodes[{a}] is not in the scene rendered")), "{err}");
    let mut broken = doc.clone();
    // Weights without a view or sparse values: zeros, as the spec says.
    broken["accessors"][first + 1].as_object_mut().unwrap().remove("bufferView");
    let err = refused(&broken);
    assert!(err.contains("meshes[0].primitives[0]: vertex 0: no joint weighs on it"), "{err}");
    let mut broken = doc.clone();
    broken["skins"][0]["joints"] = json!([a]);
    broken["accessors"][first + 2]["count"] = json!(1);
    let err = refused(&broken);
    assert!(err.contains("vertex 0: joint 1 is weighted, and its skin has 1 joints"), "{err}");
    let mut broken = doc.clone();
    broken["meshes"][0]["primitives"][0]["attributes"].as_object_mut().unwrap().remove("JOINTS_0");
    broken["meshes"][0]["primitives"][0]["attributes"].as_object_mut().unwrap().remove("WEIGHTS_0");
    let err = refused(&broken);
    assert!(err.contains("its node has a skin, but it has no JOINTS_0 and WEIGHTS_0"), "{err}");
    let mut broken = doc.clone();
    broken["nodes"][node]["extensions"] =
        json!({"EXT_mesh_gpu_instancing": {"attributes": {"TRANSLATION": first + 2}}});
    let err = refused(&broken);
    assert!(err.contains(&format!("nodes[{node}]: a skinned mesh with EXT_mesh_gpu_instancing")), "{err}");
}

/// Blender's armature as its exporter writes it with the pose (`tests/skin/posed`: the
/// round-trip scene's white ball bent by two bones, "upper" turned 35°, "lower" moved; a skin of
/// two joints) loads to the geometry of Blender's own evaluation of the pose (`tests/skin/baked`:
/// the ball's mesh made from the posed armature, no skin; `tests/skin/PROVENANCE.md`).
#[test]
fn blender_s_posed_armature_loads_as_blender_poses_it() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/skin");
    let posed = SceneData::load(&root.join("posed/round_trip.gltf")).unwrap();
    let baked = SceneData::load(&root.join("baked/round_trip.gltf")).unwrap();
    assert!(posed.warnings.is_empty(), "{:?}", posed.warnings);
    assert_eq!(posed.triangles.len(), baked.triangles.len());
    let largest = largest_vertex_gap(&posed, &baked);
    println!("the posed ball's vertices lie within {largest:e} m of Blender's");
    assert!(largest < 1e-5, "vertices {largest} m apart");
    // And not the bind pose: the file's joints without their pose move the ball back.
    let unposed = load_edited(&root.join("posed/round_trip.gltf"), |doc| {
        for joint in ["upper", "lower"] {
            let nodes = doc["nodes"].as_array_mut().unwrap();
            let node = nodes.iter_mut().find(|n| n["name"] == json!(joint)).unwrap();
            node.as_object_mut().unwrap().remove("rotation");
        }
    });
    let moved = largest_vertex_gap(&posed, &unposed);
    assert!(moved > 0.2, "the pose moves the ball's top by {moved} m");
    // The skinned normals (the flat faces' normals by each vertex's blended matrix, as the spec
    // says) lean off the bent faces where the blend shears them (measured 10.4°).
    let widest = widest_normal_lean(&posed);
    println!("the skinned normals lie within {widest:.2}° of their faces");
    assert!(widest < 12.0, "normals {widest}° off their faces");
}

/// The positions of `doc`'s first primitive, decoded from its data URI buffer.
fn first_positions(doc: &Value) -> Vec<Vec3> {
    let accessor = &doc["accessors"]
        [doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"].as_u64().unwrap() as usize];
    let view = &doc["bufferViews"][accessor["bufferView"].as_u64().unwrap() as usize];
    let uri = doc["buffers"][view["buffer"].as_u64().unwrap() as usize]["uri"].as_str().unwrap();
    let bytes = base64::engine::general_purpose::STANDARD.decode(uri.split_once(',').unwrap().1).unwrap();
    let offset = view["byteOffset"].as_u64().unwrap_or(0) + accessor["byteOffset"].as_u64().unwrap_or(0);
    let floats: Vec<f32> = bytes[offset as usize..]
        .as_chunks::<4>()
        .0
        .iter()
        .take(3 * accessor["count"].as_u64().unwrap() as usize)
        .map(|b| f32::from_le_bytes(*b))
        .collect();
    floats.as_chunks::<3>().0.iter().map(|p| Vec3::from_array(*p)).collect()
}

/// `COLOR_0` (Blender's colour attribute where its material reads it): its triangles draw a copy
/// of their material that reads the colours, carried at their corners (normalised shorts, read
/// to 1/65535); a primitive of the same material without colours keeps the material. An alpha
/// below 1 on a cut-out material is named in a warning (not applied); a colour beyond [0, 1] is
/// refused by path.
#[test]
fn vertex_colors_ride_on_a_copy_of_the_material() {
    let mut doc = one_light_doc();
    let positions = first_positions(&doc);
    // The colour of a vertex at (x, y, 0): (x, y, 0.25); one vertex's alpha 0.5.
    let rgba: Vec<[u16; 4]> = positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let c = [p.x, p.y, 0.25, if i == 0 { 0.5 } else { 1.0 }];
            c.map(|x| (x * 65535.0).round() as u16)
        })
        .collect();
    let data: Vec<u8> = rgba.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    let n = positions.len();
    let colors = push_accessors(&mut doc, &data, &[(0, data.len(), 5123, "VEC4", true, n)]);
    let plain = doc["meshes"][0]["primitives"][0].clone();
    doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = json!(colors);
    doc["meshes"][0]["primitives"].as_array_mut().unwrap().push(plain); // the same triangles, uncoloured
    let scene = load(&doc).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let original = scene.materials[1];
    assert_eq!(scene.materials.len(), 3, "the default, the lamp, its coloured copy");
    let copy = scene.materials[2];
    assert_eq!(Material { textures: original.textures, ..copy }, original);
    assert_eq!(scene.material_textures[copy.textures as usize].vertex_colors, 1);
    let (mut coloured, mut uncoloured) = (0, 0);
    for (t, c) in scene.triangles.iter().zip(&scene.colors) {
        if t.material == 1 {
            uncoloured += 1;
            continue;
        }
        coloured += 1;
        for (k, v) in [t.v0, t.v1, t.v2].into_iter().enumerate() {
            let expected = Vec3::new(v[0], v[1], 0.25);
            let got = Vec3::from_slice(&c.rgb[3 * k..3 * k + 3]);
            assert!((got - expected).abs().max_element() < 1e-4, "{got} at {v:?}");
        }
    }
    assert_eq!((coloured, uncoloured), (n / 3, n / 3));
    // On a cut-out material the alpha is named, not applied.
    let mut blend = doc.clone();
    blend["materials"].as_array_mut().unwrap().push(json!({"alphaMode": "BLEND"}));
    blend["meshes"][0]["primitives"][0]["material"] = json!(1);
    let scene = load(&blend).unwrap();
    assert!(
        scene.warnings.iter().any(|w| w.contains("meshes[0].primitives[0]: COLOR_0's alpha is not applied")),
        "{:?}",
        scene.warnings
    );
    // Floats beyond [0, 1] are refused by path.
    let mut bright = doc.clone();
    let data: Vec<u8> = (0..n).flat_map(|_| [2.0f32, 0.5, 0.5]).flat_map(f32::to_le_bytes).collect();
    let floats = push_accessors(&mut bright, &data, &[(0, data.len(), 5126, "VEC3", false, n)]);
    bright["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = json!(floats);
    let err = load(&bright).unwrap_err().to_string();
    assert!(
        err.contains("meshes[0].primitives[0]: COLOR_0 0: [2.0, 0.5, 0.5, 1.0] lies outside [0, 1]"),
        "{err}"
    );
}

/// Blender's colour attribute as its exporter writes it (`tests/colors/attribute`: the round-trip
/// scene's ball with its faces in four colours, a float `COLOR_0` its material reads) shades as
/// Blender's four materials of those base colours (`tests/colors/baked`, one a face;
/// `tests/colors/PROVENANCE.md`): every face of the ball has the base colour of its twin.
#[test]
fn blender_s_colour_attribute_shades_as_its_colours_materials() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/colors");
    let coloured = SceneData::load(&root.join("attribute/round_trip.gltf")).unwrap();
    let baked = SceneData::load(&root.join("baked/round_trip.gltf")).unwrap();
    assert!(coloured.warnings.is_empty(), "{:?}", coloured.warnings);
    assert_eq!(coloured.triangles.len(), baked.triangles.len());
    let key = |t: &shared::triangle::Triangle| {
        let c = (Vec3::from_array(t.v0) + Vec3::from_array(t.v1) + Vec3::from_array(t.v2)) / 3.0;
        (c * 1e4).round().to_array().map(|x| x as i64)
    };
    let twins: std::collections::HashMap<_, _> =
        baked.triangles.iter().map(|t| (key(t), baked.materials[t.material as usize].albedo)).collect();
    let scene = coloured.with_caster(());
    let mut faces = 0;
    for (i, t) in coloured.triangles.iter().enumerate() {
        if coloured.material_textures[coloured.materials[t.material as usize].textures as usize].vertex_colors
            == 0
        {
            continue;
        }
        faces += 1;
        let twin = twins[&key(t)];
        for b in [glam::Vec2::new(1.0 / 3.0, 1.0 / 3.0), glam::Vec2::new(0.8, 0.1)] {
            let albedo = shared::surface::material_at_barycentrics(&scene, i as u32, b).albedo;
            assert!(
                (Vec3::from_array(albedo) - Vec3::from_array(twin)).abs().max_element() < 1e-6,
                "{albedo:?} against {twin:?}"
            );
        }
    }
    assert_eq!(faces, 320, "the ball's faces");
}

/// `EXT_mesh_gpu_instancing` (glTF-Transform's `instance`, run by its `optimize` by default,
/// which does not mark it required): a node's mesh is drawn once an instance, at the node's
/// matrix times the instance's TRS — the triangles of the same mesh on one plain node per
/// instance, the rotation read from normalised shorts. Counts that differ and an accessor that
/// does not exist are refused by path.
#[test]
fn instanced_meshes_load_as_copies_at_their_instances() {
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let instances: [([f32; 3], [f32; 4], [f32; 3]); 3] = [
        ([1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0], [1.0, 1.0, 1.0]),
        ([0.0, 2.0, 0.0], [0.0, s, 0.0, s], [2.0, 2.0, 2.0]),
        ([0.0, 0.0, -3.0], [s, 0.0, 0.0, s], [1.0, 0.5, 1.0]),
    ];
    let base = one_light_doc();
    let node = base["nodes"].as_array().unwrap().iter().position(|n| n["mesh"] == json!(0)).unwrap();
    // The copies: one plain node an instance, each a child of the mesh node's place.
    let mut copies = base.clone();
    copies["nodes"][node]["translation"] = json!([0.0, 0.0, 1.0]);
    let mesh = copies["nodes"][node].as_object_mut().unwrap().remove("mesh").unwrap();
    let children: Vec<usize> = (0..3).map(|k| copies["nodes"].as_array().unwrap().len() + k).collect();
    for (t, r, sc) in instances {
        copies["nodes"]
            .as_array_mut()
            .unwrap()
            .push(json!({"mesh": mesh, "translation": t, "rotation": r, "scale": sc}));
    }
    copies["nodes"][node]["children"] = json!(children);
    // The instanced node: translations and scales as floats, rotations as normalised shorts.
    let mut doc = base.clone();
    doc["nodes"][node]["translation"] = json!([0.0, 0.0, 1.0]);
    let mut data: Vec<u8> = instances.iter().flat_map(|i| i.0).flat_map(f32::to_le_bytes).collect();
    data.extend(
        instances.iter().flat_map(|i| i.1).flat_map(|q| ((q * 32767.0).round() as i16).to_le_bytes()),
    );
    data.extend(instances.iter().flat_map(|i| i.2).flat_map(f32::to_le_bytes));
    let layout =
        [(0, 36, 5126, "VEC3", false, 3), (36, 24, 5122, "VEC4", true, 3), (60, 36, 5126, "VEC3", false, 3)];
    let accessors = push_accessors(&mut doc, &data, &layout);
    let attributes = json!({"TRANSLATION": accessors, "ROTATION": accessors + 1, "SCALE": accessors + 2});
    doc["nodes"][node]["extensions"] = json!({"EXT_mesh_gpu_instancing": {"attributes": attributes}});
    doc["extensionsUsed"] = json!(["EXT_mesh_gpu_instancing"]);
    let (instanced, copied) = (load(&doc).unwrap(), load(&copies).unwrap());
    assert!(instanced.warnings.is_empty(), "{:?}", instanced.warnings);
    assert_eq!(instanced.triangles.len(), copied.triangles.len());
    assert_eq!(instanced.triangles.len(), load(&base).unwrap().triangles.len() + 2 * 2, "three lamp quads");
    for (a, b) in instanced.triangles.iter().zip(&copied.triangles) {
        for (p, q) in [(a.v0, b.v0), (a.v1, b.v1), (a.v2, b.v2)] {
            assert!((Vec3::from_array(p) - Vec3::from_array(q)).length() < 1e-4, "{p:?} against {q:?}");
        }
    }
    let mut broken = doc.clone();
    broken["nodes"][node]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"] = json!(99);
    let err = load(&broken).unwrap_err().to_string();
    assert!(
        err.contains(&format!(
            "nodes[{node}].extensions.EXT_mesh_gpu_instancing.attributes.TRANSLATION: 99 names no accessor"
        )),
        "{err}"
    );
    let mut broken = doc.clone();
    broken["accessors"][accessors + 2]["count"] = json!(2);
    let view = doc["accessors"][accessors + 2]["bufferView"].as_u64().unwrap() as usize;
    broken["bufferViews"][view]["byteLength"] = json!(24);
    let err = load(&broken).unwrap_err().to_string();
    assert!(err.contains("hold [3, 3, 2] instances"), "{err}");
}

/// An orthographic camera (Blender's exporter writes every camera of the scene) does not refuse
/// the file: it is named in a warning and refused as a view, the render without `--view` sees
/// the first perspective camera, and a file whose cameras are all orthographic the default
/// framing. A broken one is still refused by path.
#[test]
fn orthographic_cameras_are_views_smlt_refuses_not_files() {
    let mut doc = one_light_doc();
    let ortho =
        json!({"type": "orthographic", "orthographic": {"xmag": 2, "ymag": 1.5, "znear": 0, "zfar": 100}});
    doc["cameras"].as_array_mut().unwrap().insert(0, ortho.clone());
    // The perspective camera is cameras[1] now, and the orthographic one's node comes first.
    for node in doc["nodes"].as_array_mut().unwrap() {
        if node.get("camera").is_some() {
            node["camera"] = json!(1);
        }
    }
    doc["nodes"].as_array_mut().unwrap().push(json!({"camera": 0, "translation": [0, 0, 9]}));
    let last = doc["nodes"].as_array().unwrap().len() - 1;
    doc["scenes"][0]["nodes"].as_array_mut().unwrap().insert(0, json!(last));
    let mut scene = load(&doc).unwrap();
    assert_eq!(scene.views.len(), 2);
    assert!(matches!(scene.views[0], View::Orthographic { camera: 0 }), "{:?}", scene.views);
    let warned: Vec<_> = scene.warnings.iter().filter(|w| w.contains("orthographic")).collect();
    assert!(warned.len() == 1 && warned[0].contains("cameras[0] (view 1"), "{:?}", scene.warnings);
    assert_eq!(scene.default_view(), 2);
    assert!((scene.camera.position - Vec3::new(0.0, 0.0, 5.0)).length() < 1e-5, "the perspective camera");
    let err = scene.select_view(1).unwrap_err().to_string();
    assert!(err.contains("view 1 is cameras[0], an orthographic camera"), "{err}");
    scene.select_view(2).unwrap();

    // Only the orthographic camera: the default framing, looking down −Z.
    let mut only = doc.clone();
    only["cameras"] = json!([ortho]);
    only["nodes"].as_array_mut().unwrap().retain(|n| n.get("camera") != Some(&json!(1)));
    only["scenes"][0]["nodes"] = json!((0..only["nodes"].as_array().unwrap().len()).collect::<Vec<_>>());
    let scene = load(&only).unwrap();
    assert_eq!(scene.default_view(), 0);
    assert!((scene.camera.forward - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);

    for (key, value, said) in
        [("xmag", json!(0), "neither may be zero"), ("zfar", json!(-1), "0 ≤ znear < zfar")]
    {
        let mut broken = doc.clone();
        broken["cameras"][0]["orthographic"][key] = value;
        let err = load(&broken).unwrap_err().to_string();
        assert!(err.contains("cameras[0].orthographic") && err.contains(said), "{err}");
    }
}

/// Triangle strips and fans load as the triangles the spec makes of them (the lamp quad's two,
/// wound the same way); points and lines draw no surface and are skipped with a warning; a mode
/// glTF does not define is refused by path.
#[test]
fn strips_and_fans_are_triangles_and_lines_are_skipped() {
    let base = one_light_doc();
    // The quad's corners c0..c3 are vertices 0, 1, 2 and 5 of its two triangles (c0 c1 c2,
    // c0 c2 c3): the strip c1 c2 c0 c3 and the fan c0 c1 c2 c3 make the same two.
    let canonical = |scene: &SceneData| {
        let mut triangles: Vec<[[i64; 3]; 3]> = scene
            .triangles
            .iter()
            .map(|t| {
                let mut v = [t.v0, t.v1, t.v2].map(|p| p.map(|x| (x * 1e4).round() as i64));
                let first = (0..3).min_by_key(|&k| v[k]).unwrap();
                v.rotate_left(first);
                v
            })
            .collect();
        triangles.sort();
        triangles
    };
    let expected = canonical(&load(&base).unwrap());
    for (mode, order) in [(5, [1u8, 2, 0, 5]), (6, [0, 1, 2, 5])] {
        let mut doc = base.clone();
        let indices = push_accessors(&mut doc, &order, &[(0, 4, 5121, "SCALAR", false, 4)]);
        doc["meshes"][0]["primitives"][0]["indices"] = json!(indices);
        doc["meshes"][0]["primitives"][0]["mode"] = json!(mode);
        let scene = load(&doc).unwrap();
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        assert_eq!(canonical(&scene), expected, "mode {mode}");
    }
    let mut doc = base.clone();
    let mut lines = doc["meshes"][0]["primitives"][0].clone();
    lines["mode"] = json!(1); // LINES
    doc["meshes"][0]["primitives"].as_array_mut().unwrap().push(lines);
    let scene = load(&doc).unwrap();
    assert_eq!(canonical(&scene), expected);
    assert_eq!(scene.warnings, ["meshes[0].primitives[1]: mode Lines draws no surface: not rendered"]);
    doc["meshes"][0]["primitives"][1]["mode"] = json!(7);
    let err = load(&doc).unwrap_err().to_string();
    assert!(err.contains("meshes[0].primitives[1]") && err.contains("mode"), "{err}");
}

#[test]
fn unsupported_content_is_an_error_or_a_warning() {
    let mut doc = one_light_doc();
    doc["materials"][0]["emissiveFactor"] = json!([0, 0, 0]);
    let err = load(&doc).unwrap_err().to_string();
    assert!(err.contains("nothing emits light"), "{err}");

    // A texture (a real 1×1 PNG beside the file) read with texture coordinates the mesh lacks
    // is refused by name; an occlusion map is named in a warning; an image in an encoding smlt
    // does not read is left out with a warning.
    let dir = std::env::temp_dir().join(format!("smlt-texture-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    image::RgbImage::from_pixel(1, 1, image::Rgb([200, 10, 10])).save(dir.join("red.png")).unwrap();
    // A GIF's identifier: an encoding smlt does not read.
    std::fs::write(dir.join("image.gif"), b"GIF89a").unwrap();
    let mut doc = one_light_doc();
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
    doc["textures"] = json!([{"source": 0}, {"source": 1}]);
    doc["images"] = json!([{"uri": "red.png"}, {"uri": "image.gif"}]);
    std::fs::write(dir.join("textured.gltf"), doc.to_string()).unwrap();
    let err = SceneData::load(&dir.join("textured.gltf")).unwrap_err().to_string();
    assert!(err.contains("meshes[0].primitives[0]") && err.contains("TEXCOORD_0"), "{err}");
    doc["materials"][0]["pbrMetallicRoughness"].as_object_mut().unwrap().remove("baseColorTexture");
    doc["materials"][0]["occlusionTexture"] = json!({"index": 0});
    doc["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = json!({"index": 1});
    std::fs::write(dir.join("textured.gltf"), doc.to_string()).unwrap();
    let scene = SceneData::load(&dir.join("textured.gltf")).unwrap();
    for said in ["occlusionTexture is ignored on material", "images[1]"] {
        assert!(scene.warnings.iter().any(|w| w.contains(said)), "{said}: {:?}", scene.warnings);
    }
    // Said once for every material that has one, not once a material.
    let mut many = doc.clone();
    let materials = many["materials"].as_array().unwrap().clone();
    let copies: Vec<_> = (0..6)
        .map(|i| {
            let mut m = materials[0].clone();
            m["name"] = json!(format!("m{i}"));
            m
        })
        .collect();
    many["materials"] = json!(copies);
    std::fs::write(dir.join("many.gltf"), many.to_string()).unwrap();
    let scene = SceneData::load(&dir.join("many.gltf")).unwrap();
    let occlusion: Vec<_> = scene.warnings.iter().filter(|w| w.contains("occlusionTexture")).collect();
    assert_eq!(occlusion.len(), 1, "{:?}", scene.warnings);
    assert!(occlusion[0].contains("on 6 materials ('m0', 'm1', 'm2', …)"), "{}", occlusion[0]);
    assert_eq!(scene.material_textures.len(), 1, "the unreadable texture leaves the material untextured");
    // A buffer URI that does not exist, a missing file, a directory.
    doc["buffers"][0]["uri"] = json!("missing.bin");
    std::fs::write(dir.join("missing-buffer.gltf"), doc.to_string()).unwrap();
    let err = SceneData::load(&dir.join("missing-buffer.gltf")).unwrap_err().to_string();
    assert!(err.contains("missing-buffer.gltf") && err.contains("'missing.bin', does not exist"), "{err}");
    let err = SceneData::load(&dir.join("nope.gltf")).unwrap_err().to_string();
    assert!(err.contains("nope.gltf"), "{err}");
    let err = SceneData::load(&dir).unwrap_err().to_string();
    assert!(err.contains("is a directory"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();

    let err =
        SceneData::from_slice(b"{\"asset\": {\"version\": \"2.0\"", "truncated").unwrap_err().to_string();
    assert!(err.contains("cannot load glTF scene truncated"), "{err}");
    let err = SceneData::from_slice(&[0x67, 0x6c, 0x54, 0x46, 7, 7, 7, 7, 1, 2, 3], "random.glb")
        .unwrap_err()
        .to_string();
    assert!(err.contains("cannot load glTF scene random.glb"), "{err}");
}

/// The ray casters — the device's wide-BVH traversal (shared, run on the host) and obvhs's,
/// exactly; Embree (the CPU backend's where installed) within its rounding — against brute
/// force over every triangle: 40 000 rays, a third of them axis-parallel (one or two zero
/// direction components, of both signs), degenerate triangles in the mix, closest-hit and
/// occlusion queries with finite intervals.
#[test]
fn ray_casters_match_brute_force() {
    let mut rng = 0x1234_5678u64;
    let mut next = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut soup = TriangleSoup {
        materials: vec![Material { albedo: [0.5; 3], emission: [1.0; 3], ..Default::default() }],
        ..Default::default()
    };
    for i in 0..2000 {
        let c = Vec3::new(next(), next(), next()) * 10.0 - 5.0;
        let tri = if i % 50 == 0 {
            [c, c + Vec3::X, c + Vec3::X * 2.0] // zero area
        } else {
            [c, c + Vec3::new(next(), next(), next()) - 0.5, c + Vec3::new(next(), next(), next()) - 0.5]
        };
        soup.triangles.push(tri);
        soup.material_of.push(0);
    }
    let scene = SceneData::from_soup(soup, "random").unwrap();
    let brute = |o: Vec3, d: Vec3, tmin: f32, tmax: f32| {
        let mut best = Hit::NONE;
        for (i, tri) in scene.triangles.iter().enumerate() {
            let t = intersect_triangle(tri, o, d, tmin, best.t.min(tmax));
            if t < best.t.min(tmax) {
                best = Hit { t, triangle: i as u32 };
            }
        }
        best
    };
    let (device, obvhs, host) =
        (scene.device_view().caster, scene.obvhs_view().caster, scene.shared().caster);
    let embree = matches!(host, smlt::caster::HostCaster::Embree(_));
    assert!(embree || std::env::var("CI").as_deref() != Ok("true"), "CI=true and no Embree");
    let (mut hits, mut axis, mut blocked, mut embree_differ) = (0, 0, 0, 0);
    for i in 0..40_000 {
        let o = Vec3::new(next(), next(), next()) * 14.0 - 7.0;
        let mut d = Vec3::new(next(), next(), next()) * 2.0 - 1.0;
        if i % 3 == 0 {
            axis += 1;
            d.x = 0.0;
            if i % 2 == 0 {
                d.y = if i % 4 == 0 { 0.0 } else { -0.0 };
            }
        }
        if d.length() < 1e-3 {
            continue;
        }
        let d = d.normalize();
        let (tmin, tmax) = if i % 5 == 0 { (0.5 * next(), 2.0 + 8.0 * next()) } else { (0.0, NO_HIT) };
        let truth = brute(o, d, tmin, tmax);
        for (name, hit) in [
            ("device", device.closest_hit(o, d, tmin, tmax, 0)),
            ("obvhs", obvhs.closest_hit(o, d, tmin, tmax, 0)),
        ] {
            assert_eq!(hit.found(), truth.found(), "{name} ray {i}: o {o} d {d}: {hit:?} vs {truth:?}");
            // The same triangle test gives the same t; two triangles at one t are a tie.
            assert_eq!(hit.t, truth.t, "{name} ray {i}: o {o} d {d}");
        }
        let occluded = truth.found();
        assert_eq!(device.occluded(o, d, tmin, tmax, 0), occluded, "device ray {i}");
        assert_eq!(obvhs.occluded(o, d, tmin, tmax, 0), occluded, "obvhs ray {i}");
        if embree {
            // Embree's own triangle test: t within 1e-5 relative; a ray through an edge or a
            // degenerate triangle's line may differ.
            let hit = host.closest_hit(o, d, tmin, tmax, 0);
            let same =
                hit.found() == truth.found() && (!hit.found() || (hit.t - truth.t).abs() <= 1e-5 * truth.t);
            let blocked_alike = host.occluded(o, d, tmin, tmax, 0) == occluded;
            embree_differ += (!same || !blocked_alike) as u32;
        }
        hits += truth.found() as u32;
        blocked += (occluded && tmax < NO_HIT) as u32;
    }
    println!(
        "{hits} hits of 40000 rays ({axis} axis-parallel, {blocked} blocked finite intervals); \
         Embree differs on {embree_differ}"
    );
    assert!(hits > 4_000 && blocked > 100);
    assert!(embree_differ <= 20, "{embree_differ} Embree answers differ from brute force");
}

/// Zero-area emitting triangles are never chosen as lights (they would have an infinite area
/// density); a scene whose only emitters have zero area has nothing that emits.
#[test]
fn zero_area_emitters_are_not_lights() {
    let lamp = Material { albedo: [0.5; 3], emission: [1.0; 3], ..Default::default() };
    let mut soup = TriangleSoup { materials: vec![lamp], ..Default::default() };
    soup.triangles.push([Vec3::ZERO, Vec3::X, Vec3::X * 2.0]); // zero area
    soup.triangles.push([Vec3::ZERO, Vec3::X, Vec3::Y]);
    soup.material_of = vec![0, 0];
    let scene = SceneData::from_soup(soup.clone(), "lamps").unwrap();
    assert_eq!(scene.lights.len(), 1);
    let light = scene.triangles[scene.lights[0].light as usize];
    assert!(light.area > 0.0 && (light.light_area_pdf - 2.0).abs() < 1e-6);
    soup.triangles.pop();
    soup.material_of.pop();
    assert!(matches!(SceneData::from_soup(soup, "degenerate"), Err(SceneError::NoEmitter(_))));
}

/// A document lit by one `KHR_lights_punctual` light (the JSON of the light, on a node with
/// `node` fields), marked required as Blender's exporter marks it: a floor quad and a camera.
fn lamp_doc(light: Value, node: Value) -> Value {
    let mut b = GltfBuilder::new();
    let m = b.material("floor", [0.5; 3], [0.0; 3], 1.0, None);
    b.quad(
        m,
        [Vec3::new(-1., 0., 1.), Vec3::new(1., 0., 1.), Vec3::new(1., 0., -1.), Vec3::new(-1., 0., -1.)],
    );
    b.camera(Vec3::new(0.0, 2.0, 3.0), Vec3::ZERO, Vec3::Y, 0.8);
    let mut doc: Value = serde_json::from_str(&b.to_json()).unwrap();
    let mut node = node;
    node["extensions"] = json!({"KHR_lights_punctual": {"light": 0}});
    doc["nodes"].as_array_mut().unwrap().push(node);
    let n = doc["nodes"].as_array().unwrap().len() - 1;
    doc["scenes"][0]["nodes"].as_array_mut().unwrap().push(json!(n));
    doc["extensions"] = json!({"KHR_lights_punctual": {"lights": [light]}});
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc["extensionsRequired"] = json!(["KHR_lights_punctual"]);
    doc
}

/// Blender marks `KHR_lights_punctual` required whenever a lamp exists: such a file loads,
/// its lights on their nodes' world transforms (shining down the node's −Z) in Blender's
/// units (candela / 683 W/sr, lux / 683 W/m²), and a scene lit only by them needs no emitter.
#[test]
fn punctual_lights_load_on_their_nodes_in_blender_s_units() {
    use shared::punctual::{DIRECTIONAL, POINT, SPOT};
    let down = json!([-std::f32::consts::FRAC_1_SQRT_2, 0.0, 0.0, std::f32::consts::FRAC_1_SQRT_2]);
    let point = lamp_doc(
        json!({"type": "point", "color": [1.0, 0.5, 0.25], "intensity": 683.0}),
        json!({"translation": [0.5, 2.0, -0.5]}),
    );
    let scene = load(&point).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.punctual.len(), 1);
    let l = scene.punctual[0];
    assert_eq!((l.kind, l.position, l.intensity), (POINT, [0.5, 2.0, -0.5], [1.0, 0.5, 0.25]));
    assert_eq!(scene.lights.len(), 1, "the point light is the one entry of the light CDF");
    assert!(shared::light::is_punctual(scene.lights[0].light));
    // A spot on a parent rotated to look down: its axis is the parent's −Z in world space.
    let mut spot = lamp_doc(
        json!({"type": "spot", "intensity": 1366.0, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}),
        json!({"translation": [0.0, 0.0, 0.0]}),
    );
    let light_node = spot["nodes"].as_array().unwrap().len() - 1;
    spot["nodes"].as_array_mut().unwrap().push(json!({"translation": [0.0, 2.0, 0.0], "rotation": down, "scale": [3.0, 3.0, 3.0], "children": [light_node]}));
    let parent = spot["nodes"].as_array().unwrap().len() - 1;
    let roots = spot["scenes"][0]["nodes"].as_array_mut().unwrap();
    roots.retain(|n| n.as_u64() != Some(light_node as u64));
    roots.push(json!(parent));
    let scene = load(&spot).unwrap();
    let l = scene.punctual[0];
    assert_eq!(l.kind, SPOT);
    assert!((glam::Vec3::from_array(l.position) - Vec3::new(0.0, 2.0, 0.0)).length() < 1e-5);
    assert!((glam::Vec3::from_array(l.direction) - Vec3::NEG_Y).length() < 1e-5, "{:?}", l.direction);
    assert_eq!(l.intensity, [2.0; 3], "scale changes no brightness");
    assert!((l.cos_inner - 0.2f32.cos()).abs() < 1e-6 && (l.cos_outer - 0.5f32.cos()).abs() < 1e-6);
    // A sun: lux / 683, its disk the bounding sphere of the floor.
    let sun = lamp_doc(json!({"type": "directional", "intensity": 341.5}), json!({"rotation": down}));
    let scene = load(&sun).unwrap();
    let l = scene.punctual[0];
    assert_eq!((l.kind, l.intensity), (DIRECTIONAL, [0.5; 3]));
    assert!((glam::Vec3::from_array(l.direction) - Vec3::NEG_Y).length() < 1e-5);
    assert!((l.radius - 2f32.sqrt()).abs() < 1e-4 && l.position == [0.0; 3], "{l:?}");
}

/// Lights outside the spec's ranges are refused in one line naming the light by its glTF path;
/// `range` is ignored with a warning; a zero-intensity light is no light.
#[test]
fn punctual_lights_outside_the_spec_are_refused_by_path() {
    let cases = [
        (json!({"type": "point", "intensity": -1.0}), "lights[0].intensity"),
        (json!({"type": "point", "color": [1.5, 1.0, 1.0]}), "lights[0].color"),
        (
            json!({"type": "spot", "spot": {"innerConeAngle": 0.6, "outerConeAngle": 0.5}}),
            "spot.innerConeAngle",
        ),
        (json!({"type": "spot", "spot": {"outerConeAngle": 2.0}}), "spot.outerConeAngle"),
    ];
    for (light, what) in cases {
        let err = load(&lamp_doc(light.clone(), json!({}))).err().unwrap_or_else(|| panic!("{light} loaded"));
        let line = err.to_string();
        assert!(matches!(err, SceneError::Malformed { .. }) && line.contains(what), "{light}: {line}");
        assert!(!line.contains('\n'), "{line}");
    }
    let unknown = load(&lamp_doc(json!({"type": "spherical"}), json!({}))).unwrap_err().to_string();
    assert!(unknown.contains("unsupported") && unknown.contains("lights[0].type: 'spherical'"), "{unknown}");
    let ranged = load(&lamp_doc(json!({"type": "point", "range": 3.0}), json!({}))).unwrap();
    assert!(ranged.warnings.iter().any(|w| w.contains("range is ignored")), "{:?}", ranged.warnings);
    let dark = load(&lamp_doc(json!({"type": "point", "intensity": 0.0}), json!({})));
    assert!(matches!(dark, Err(SceneError::NoEmitter(_))), "{dark:?}");
}

/// A document lit by `one_light_doc`'s lamp with one more material, `glass` (its
/// `extensions`), on a second quad.
fn glass_doc(extensions: Value) -> Value {
    let mut b = GltfBuilder::new();
    let lamp = b.material("lamp", [0.5; 3], [1.0; 3], 1.0, None);
    let glass = b.glass("glass", [0.9, 0.8, 0.7], 1.5, false);
    let v = Vec3::new;
    b.quad(lamp, [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)]);
    b.quad(glass, [v(0., 0., 1.), v(1., 0., 1.), v(1., 1., 1.), v(0., 1., 1.)]);
    b.camera(v(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 0.5);
    let mut doc: Value = serde_json::from_str(&b.to_json()).unwrap();
    doc["materials"][1]["extensions"] = extensions;
    doc["extensionsUsed"] =
        json!(["KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume"]);
    doc
}

/// Glass reads as the spec defines it: the transmission share, the ior (1.5 by default),
/// thin-walled without a volume or with thicknessFactor 0, solid with a thickness (rough with
/// α = roughness²), and the
/// Beer–Lambert coefficient −ln(attenuationColor) / attenuationDistance. Values outside the
/// spec's ranges are refused in one line by their glTF path; the special ior 0 is refused as
/// not modelled.
#[test]
fn glass_reads_as_the_spec_defines_it_and_bad_values_are_refused() {
    let material = |ext: Value| {
        let scene = load(&glass_doc(ext)).unwrap();
        scene.materials.iter().copied().find(|m| m.albedo == [0.9, 0.8, 0.7]).expect("the glass")
    };
    let thin = material(json!({"KHR_materials_transmission": {"transmissionFactor": 0.75}}));
    assert_eq!((thin.transmission, thin.ior, thin.thin_walled, thin.attenuation), (0.75, 1.5, 1, [0.0; 3]));
    let solid = material(json!({
        "KHR_materials_transmission": {"transmissionFactor": 1.0},
        "KHR_materials_ior": {"ior": 1.33},
        "KHR_materials_volume": {"thicknessFactor": 0.1, "attenuationColor": [0.5, 1.0, 0.25], "attenuationDistance": 2.0}
    }));
    assert_eq!((solid.transmission, solid.ior, solid.thin_walled), (1.0, 1.33, 0));
    let expected = [0.5f32.ln() / -2.0, 0.0, 0.25f32.ln() / -2.0];
    for (a, e) in solid.attenuation.iter().zip(expected) {
        assert!((a - e).abs() < 1e-6, "{:?} vs {expected:?}", solid.attenuation);
    }
    // Rough: α is roughness², a solid's interface and a thin wall's alike.
    let rough = |ext: Value| {
        let mut doc = glass_doc(ext);
        doc["materials"][1]["pbrMetallicRoughness"]["roughnessFactor"] = json!(0.5);
        let scene = load(&doc).unwrap();
        let m = scene.materials.iter().copied().find(|m| m.albedo == [0.9, 0.8, 0.7]).expect("the glass");
        (m, scene.warnings)
    };
    let (rough_solid, warnings) = rough(json!({
        "KHR_materials_transmission": {"transmissionFactor": 1.0},
        "KHR_materials_volume": {"thicknessFactor": 1.0}
    }));
    assert!(
        rough_solid.alpha == 0.25 && rough_solid.is_rough_dielectric() && warnings.is_empty(),
        "{warnings:?}"
    );
    let (rough_thin, warnings) = rough(json!({"KHR_materials_transmission": {"transmissionFactor": 1.0}}));
    assert!(
        rough_thin.alpha == 0.25 && rough_thin.thin_walled == 1 && rough_thin.is_rough_dielectric(),
        "{rough_thin:?}"
    );
    assert!(warnings.is_empty(), "{warnings:?}");
    let zero_thickness = material(json!({
        "KHR_materials_transmission": {"transmissionFactor": 1.0},
        "KHR_materials_volume": {"thicknessFactor": 0.0}
    }));
    assert_eq!(zero_thickness.thin_walled, 1);
    let t = |f: f64| json!({"KHR_materials_transmission": {"transmissionFactor": f}});
    for (ext, what) in [
        (json!({"KHR_materials_ior": {"ior": 0.5}}), "KHR_materials_ior.ior"),
        (t(1.5), "KHR_materials_transmission.transmissionFactor"),
        (
            json!({"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_volume": {"thicknessFactor": 1.0, "attenuationDistance": 0.0}}),
            "KHR_materials_volume.attenuationDistance",
        ),
        (
            json!({"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_volume": {"thicknessFactor": 1.0, "attenuationColor": [2.0, 1.0, 1.0]}}),
            "KHR_materials_volume.attenuationColor",
        ),
    ] {
        let err = load(&glass_doc(ext.clone())).err().unwrap_or_else(|| panic!("{ext} loaded"));
        let line = err.to_string();
        assert!(matches!(err, SceneError::Malformed { .. }) && line.contains(what), "{ext}: {line}");
        assert!(line.contains("materials[1]") && !line.contains('\n'), "{line}");
    }
    let special = load(&glass_doc(json!({"KHR_materials_ior": {"ior": 0.0}}))).unwrap_err();
    assert!(matches!(special, SceneError::Unsupported { .. }), "{special}");
}

/// glTF's metallic-roughness BRDF reads as the spec defines it: metallicFactor and
/// roughnessFactor default to 1 (a file that omits them is a rough metal), α = roughness²,
/// `KHR_materials_specular`'s factors (1 and white without it), the ior of `KHR_materials_ior`;
/// a metal does not transmit; the default material of a primitive without one is the spec's
/// (white rough metal). Values outside the spec's ranges are refused in one line by their path.
#[test]
fn the_metallic_roughness_brdf_reads_as_the_spec_defines_it() {
    let doc_with = |pbr: Value, extensions: Value| {
        let mut b = GltfBuilder::new();
        let lamp = b.material("lamp", [0.5; 3], [1.0; 3], 1.0, None);
        let surface = b.pbr("surface", [0.9, 0.8, 0.7], 0.0, 0.0);
        let v = Vec3::new;
        b.quad(lamp, [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)]);
        b.quad(surface, [v(0., 0., 1.), v(1., 0., 1.), v(1., 1., 1.), v(0., 1., 1.)]);
        b.camera(v(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 0.5);
        let mut doc: Value = serde_json::from_str(&b.to_json()).unwrap();
        doc["materials"][1]["pbrMetallicRoughness"] = pbr;
        doc["materials"][1]["extensions"] = extensions;
        doc["extensionsUsed"] =
            json!(["KHR_materials_specular", "KHR_materials_transmission", "KHR_materials_ior"]);
        doc
    };
    let material = |pbr: Value, extensions: Value| {
        let scene = load(&doc_with(pbr, extensions)).unwrap();
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        scene.materials[2]
    };
    let defaults = material(json!({}), json!({}));
    assert_eq!(
        (
            defaults.albedo,
            defaults.metallic,
            defaults.alpha,
            defaults.specular,
            defaults.specular_color,
            defaults.ior
        ),
        ([1.0; 3], 1.0, 1.0, 1.0, [1.0; 3], 1.5)
    );
    let plastic = material(
        json!({"baseColorFactor": [0.9, 0.8, 0.7, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.5}),
        json!({"KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [1.0, 0.5, 0.0]}, "KHR_materials_ior": {"ior": 2.0}}),
    );
    assert_eq!(
        (plastic.metallic, plastic.alpha, plastic.specular, plastic.specular_color, plastic.ior),
        (0.0, 0.25, 0.5, [1.0, 0.5, 0.0], 2.0)
    );
    let brdf = plastic.brdf();
    let f0 = ((2.0f32 - 1.0) / 3.0).powi(2) * 0.5;
    assert!((brdf.f0 - Vec3::new(f0, f0 * 0.5, 0.0)).abs().max_element() < 1e-6, "{}", brdf.f0);
    // The project's Lambert materials: specularFactor 0, no metal.
    let lambert =
        material(json!({"metallicFactor": 0.0}), json!({"KHR_materials_specular": {"specularFactor": 0.0}}));
    assert!(lambert.brdf().is_lambertian() && !lambert.has_delta_lobe());
    // A metal does not transmit; a smooth one is a mirror.
    let metal_glass = material(
        json!({"metallicFactor": 0.75, "roughnessFactor": 0.0}),
        json!({"KHR_materials_transmission": {"transmissionFactor": 1.0}}),
    );
    // The spec's mix: metal 0.75, glass 0.25 × 1, no opaque dielectric left.
    assert_eq!((metal_glass.transmission, metal_glass.metallic), (0.25, 1.0));
    let half = material(
        json!({"metallicFactor": 0.5, "roughnessFactor": 0.0}),
        json!({"KHR_materials_transmission": {"transmissionFactor": 0.5}}),
    );
    // Glass 0.25; the rest 0.75: metal 0.5 of the whole, the opaque dielectric 0.25.
    assert!((half.transmission - 0.25).abs() < 1e-6 && (half.metallic - 2.0 / 3.0).abs() < 1e-6, "{half:?}");
    assert!(material(json!({"roughnessFactor": 0.0}), json!({})).has_delta_lobe());
    // The default material: a primitive without one.
    let mut doc = doc_with(json!({}), json!({}));
    doc["meshes"][1]["primitives"][0].as_object_mut().unwrap().remove("material");
    let scene = load(&doc).unwrap();
    let default = scene.materials[scene.triangles.last().unwrap().material as usize];
    assert_eq!((default.albedo, default.metallic, default.alpha), ([1.0; 3], 1.0, 1.0));
    for (pbr, ext, what) in [
        (json!({"metallicFactor": 1.5}), json!({}), "materials[1].pbrMetallicRoughness.metallicFactor"),
        (json!({"roughnessFactor": -0.1}), json!({}), "materials[1].pbrMetallicRoughness.roughnessFactor"),
        (
            json!({}),
            json!({"KHR_materials_specular": {"specularFactor": 2.0}}),
            "KHR_materials_specular.specularFactor",
        ),
        (
            json!({}),
            json!({"KHR_materials_specular": {"specularColorFactor": [1.0, -1.0, 0.0]}}),
            "KHR_materials_specular.specularColorFactor",
        ),
    ] {
        let err =
            load(&doc_with(pbr.clone(), ext.clone())).err().unwrap_or_else(|| panic!("{pbr} {ext} loaded"));
        let line = err.to_string();
        assert!(matches!(err, SceneError::Malformed { .. }) && line.contains(what), "{line}");
        assert!(!line.contains('\n'), "{line}");
    }
}

/// The `textured` scene's textures load as its builder wrote them: sRGB texels packed red
/// first, the samplers' filters and wraps, the texture transform, and per-triangle texture
/// coordinates that put the checker's squares where the projection puts them.
#[test]
fn textures_load_with_their_samplers_transforms_and_coordinates() {
    use shared::texture::{Texture, WRAP_CLAMP, WRAP_MIRROR, WRAP_REPEAT};
    let (_, scene, _) = smlt::scenes::open(Some("textured"), 1).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.textures.len(), 4);
    assert_eq!(scene.material_textures.len(), 5, "entry 0 and four textured materials");
    let samplers: Vec<u32> = scene.textures.iter().map(|t| t.sampler).collect();
    assert_eq!(
        samplers,
        [
            Texture::sampler(WRAP_REPEAT, WRAP_REPEAT, true),
            Texture::sampler(WRAP_MIRROR, WRAP_CLAMP, false),
            Texture::sampler(WRAP_REPEAT, WRAP_REPEAT, false),
            Texture::sampler(WRAP_CLAMP, WRAP_CLAMP, true),
        ]
    );
    let checker = scene.textures[0];
    assert_eq!((checker.width, checker.height, checker.offset), (8, 8, 0));
    assert_eq!(scene.texels[0], u32::from_le_bytes([210, 205, 195, 255]));
    assert_eq!(scene.texels[1], u32::from_le_bytes([40, 45, 60, 255]));
    // The banded wall's transform: scale (1.5, 1), rotation 0.3, offset (0.2, −0.1).
    let wall = scene.materials.iter().find(|m| m.textures == 2).expect("the banded wall");
    let r = scene.material_textures[wall.textures as usize].base_color;
    let expected = shared::texture::texture_transform([0.2, -0.1], 0.3, [1.5, 1.0]);
    assert!(r.transform.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-6), "{:?}", r.transform);
    // On the floor, TEXCOORD_0 = (x, z) / 2: the texel at (0.3, 0, 0.3) is (1, 1), light;
    // the one at (0.3, 0, 0.55) is (1, 2), dark (squares of 0.25 m).
    let shared_scene = scene.shared();
    let floor_at = |x: f32, z: f32| {
        let p = Vec3::new(x, 0.0, z);
        let hit = shared_scene.caster.closest_hit(p + Vec3::Y, -Vec3::Y, 0.0, NO_HIT, 0);
        shared::surface::material_at(&shared_scene, hit.triangle, p).albedo
    };
    let light = shared::texture::srgb_to_linear(210.0 / 255.0);
    let dark = shared::texture::srgb_to_linear(40.0 / 255.0);
    assert!((floor_at(0.3, 0.3)[0] - light).abs() < 1e-5, "{:?}", floor_at(0.3, 0.3));
    assert!((floor_at(0.3, 0.55)[0] - dark).abs() < 1e-5, "{:?}", floor_at(0.3, 0.55));
    assert!((floor_at(-0.3, 0.55)[0] - light).abs() < 1e-5, "REPEAT below 0: {:?}", floor_at(-0.3, 0.55));
    assert!(scene.describe_contents().contains("4 texture(s)"), "{}", scene.describe_contents());
}

/// A quad whose every `NORMAL` leans towards +x, on a node with transform `node`.
fn bent_doc(normal: Vec3, node: Value) -> Value {
    let mut b = GltfBuilder::new();
    let m = b.pbr("floor", [0.5; 3], 0.0, 1.0);
    b.bent_quad(
        m,
        [Vec3::new(0., 0., 0.), Vec3::new(1., 0., 0.), Vec3::new(1., 1., 0.), Vec3::new(0., 1., 0.)],
        normal,
    );
    b.camera(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 0.5);
    b.point_light(Vec3::new(0.5, 0.5, 2.0), [1.0; 3], 10.0);
    let mut doc: Value = serde_json::from_str(&b.to_json()).unwrap();
    let mesh_node = doc["nodes"].as_array().unwrap().iter().position(|n| n.get("mesh").is_some()).unwrap();
    for (k, v) in node.as_object().unwrap() {
        doc["nodes"][mesh_node][k] = v.clone();
    }
    doc
}

/// Every vertex normal of every triangle of `scene`.
fn vertex_normals(scene: &SceneData) -> Vec<Vec3> {
    scene
        .normals
        .iter()
        .flat_map(|t| t.n.chunks(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect::<Vec<_>>())
        .collect()
}

/// `NORMAL` follows the node's inverse-transpose (a non-uniform scale bends it, a mirror
/// turns it), a normal equal to its face's is stored flat, and one that is no unit vector is
/// refused by name.
#[test]
fn normals_follow_the_inverse_transpose_and_bad_ones_are_refused() {
    let lean = Vec3::new(1.0, 0.0, 1.0).normalize();
    let cases = [
        (json!({}), lean),
        (json!({"scale": [2, 1, 1]}), Vec3::new(0.5, 0.0, 1.0).normalize()),
        (json!({"scale": [-1, 1, 1]}), Vec3::new(-1.0, 0.0, 1.0).normalize()),
    ];
    for (node, expected) in cases {
        let scene = load(&bent_doc(lean, node.clone())).unwrap();
        assert_eq!(scene.normals.len(), scene.triangles.len(), "{node}: one entry a triangle");
        for n in vertex_normals(&scene) {
            assert!((n - expected).length() < 1e-5, "{node}: {n} against {expected}");
        }
    }
    // Normals equal to the face's: no per-triangle store.
    let flat = load(&bent_doc(Vec3::Z, json!({}))).unwrap();
    assert!(flat.normals.iter().all(|t| t.n == [0.0; 9]), "a flat mesh stores no normals");
    // A NORMAL shrunk to a tenth: refused, naming the attribute.
    let mut doc = bent_doc(lean, json!({}));
    let normal_accessor =
        doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"].as_u64().unwrap() as usize;
    let view =
        &doc["bufferViews"][doc["accessors"][normal_accessor]["bufferView"].as_u64().unwrap() as usize];
    let (offset, length) =
        (view["byteOffset"].as_u64().unwrap_or(0) as usize, view["byteLength"].as_u64().unwrap() as usize);
    let uri = doc["buffers"][0]["uri"].as_str().unwrap().to_string();
    let (head, data) = uri.split_once(',').unwrap();
    let engine = base64::engine::general_purpose::STANDARD;
    let mut bytes = engine.decode(data).unwrap();
    for f in bytes[offset..offset + length].chunks_mut(4) {
        let v = f32::from_le_bytes(f.try_into().unwrap()) * 0.1;
        f.copy_from_slice(&v.to_le_bytes());
    }
    doc["buffers"][0]["uri"] = json!(format!("{head},{}", engine.encode(&bytes)));
    let err = load(&doc).unwrap_err().to_string();
    assert!(err.contains("NORMAL 0 is not a unit vector"), "{err}");
}

/// `alphaMode` reads as the spec defines it: OPAQUE (the default) ignores alpha and needs no
/// texture entry; MASK keeps `alphaCutoff` (0.5 by default) and BLEND the factor's alpha; an
/// alpha outside [0, 1] or a negative cutoff is refused by its path; an emitter stays opaque,
/// said once.
#[test]
fn alpha_modes_read_as_the_spec_defines_them() {
    use shared::cutout::{ALPHA_BLEND, ALPHA_MASK, ALPHA_OPAQUE};
    let with = |material: Value| {
        let mut doc = glass_doc(json!({}));
        doc["extensionsUsed"] = json!([]);
        doc["materials"][1].as_object_mut().unwrap().remove("extensions");
        for (k, v) in material.as_object().unwrap() {
            doc["materials"][1][k] = v.clone();
        }
        doc["materials"][1]["pbrMetallicRoughness"]["baseColorFactor"] = json!([0.9, 0.8, 0.7, 0.3]);
        load(&doc)
    };
    let entry = |scene: &SceneData| {
        let m = scene.materials.iter().find(|m| m.albedo == [0.9, 0.8, 0.7]).expect("the material");
        scene.material_textures[m.textures as usize]
    };
    let opaque = with(json!({})).unwrap();
    assert_eq!(entry(&opaque).alpha_mode, ALPHA_OPAQUE);
    assert_eq!(opaque.material_textures.len(), 1, "an opaque untextured material needs no entry");
    let mask = with(json!({"alphaMode": "MASK"})).unwrap();
    assert_eq!(
        (entry(&mask).alpha_mode, entry(&mask).alpha_cutoff, entry(&mask).alpha),
        (ALPHA_MASK, 0.5, 0.3)
    );
    let mask = with(json!({"alphaMode": "MASK", "alphaCutoff": 0.25})).unwrap();
    assert_eq!(entry(&mask).alpha_cutoff, 0.25);
    let blend = with(json!({"alphaMode": "BLEND"})).unwrap();
    assert_eq!((entry(&blend).alpha_mode, entry(&blend).alpha), (ALPHA_BLEND, 0.3));
    assert!(blend.warnings.is_empty(), "{:?}", blend.warnings);
    let err = with(json!({"alphaMode": "MASK", "alphaCutoff": -1.0})).unwrap_err().to_string();
    assert!(err.contains("materials[1].alphaCutoff"), "{err}");
    let mut doc = one_light_doc();
    doc["materials"][0]["alphaMode"] = json!("BLEND");
    let lamp = load(&doc).unwrap();
    assert!(lamp.warnings.iter().any(|w| w.contains("on an emitter is not modelled")), "{:?}", lamp.warnings);
    assert_eq!(lamp.material_textures[lamp.materials[1].textures as usize].alpha_mode, ALPHA_OPAQUE);
}

/// A floor (y = 0, facing +y, TEXCOORD_0 = (x, z)) whose material has a 1 × 1 normal texture
/// leaning towards +x, with `scale` and a `KHR_texture_transform` offset; with `smooth` its
/// vertices have `NORMAL` (+y), so that its tangents are read or computed.
fn normal_mapped_doc(scale: f32, smooth: bool) -> Value {
    textured_floor_doc([218, 128, 218, 255], scale, smooth)
}

/// [`normal_mapped_doc`] with another texel.
fn textured_floor_doc(texel: [u8; 4], scale: f32, smooth: bool) -> Value {
    use smlt::scenes::{facing, png, Planar};
    let mut b = GltfBuilder::new();
    let floor = b.pbr("floor", [0.5; 3], 0.0, 1.0);
    b.texture(
        floor,
        "normalTexture",
        png(1, 1, |_, _| texel),
        json!({"magFilter": 9728}),
        Some(json!({"offset": [0.25, 0.5]})),
        Planar { u: Vec3::X, v: Vec3::Z },
    );
    let q = [Vec3::new(-1., 0., -1.), Vec3::new(1., 0., -1.), Vec3::new(1., 0., 1.), Vec3::new(-1., 0., 1.)];
    if smooth {
        b.bent_quad(floor, facing(q, Vec3::Y), Vec3::Y);
    } else {
        b.quad(floor, facing(q, Vec3::Y));
    }
    b.camera(Vec3::new(0.0, 3.0, 0.1), Vec3::ZERO, Vec3::Y, 0.8);
    b.point_light(Vec3::new(0.0, 2.0, 0.0), [1.0; 3], 10.0);
    let mut doc: Value = serde_json::from_str(&b.to_json()).unwrap();
    doc["materials"][0]["normalTexture"]["scale"] = json!(scale);
    doc
}

/// The floor's shading normal at (0.3, 0, −0.2), from above.
fn floor_normal(scene: &SceneData) -> shared::normals::Normals {
    let shared_scene = scene.shared();
    let p = Vec3::new(0.3, 0.0, -0.2);
    let hit = shared_scene.caster.closest_hit(p + Vec3::Y, -Vec3::Y, 0.0, NO_HIT, 0);
    shared::surface::normals_at(&shared_scene, hit.triangle, p)
}

/// The texel of [`normal_mapped_doc`], decoded: 2 c − 1.
fn texel(byte: f32) -> f32 {
    byte / 255.0 * 2.0 - 1.0
}

/// A normal texture loads with its transform (read from the extension on `normalTexture`) and
/// scale, its triangles get the texture coordinates it reads, and the floor's shading normal
/// leans as the spec's tangent frame says: x along dp/du (+x here), z the normal (+y), the texel
/// 2 c − 1 with x and y times the scale; the same whether the floor is flat (each triangle's own
/// frame) or has normals (MikkTSpace's tangents, which on a flat, evenly mapped floor are that
/// frame). A scale that is no number is refused.
#[test]
fn a_normal_texture_loads_and_bends_the_shading_normal() {
    for smooth in [false, true] {
        let scene = load(&normal_mapped_doc(0.5, smooth)).unwrap();
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        let t = scene.material_textures[scene.materials[1].textures as usize];
        assert!(t.normal.is_some() && !t.base_color.is_some());
        assert_eq!(t.normal_scale, 0.5);
        assert_eq!(t.normal.transform, shared::texture::texture_transform([0.25, 0.5], 0.0, [1.0, 1.0]));
        assert!(scene.texcoords.iter().any(|c| c.uv[..6].iter().any(|&u| u != 0.0)), "TEXCOORD_0 read");
        assert_eq!(scene.tangents.iter().any(|t| t.t != [0.0; 12]), smooth, "tangents computed where smooth");
        let contents = scene.describe_contents();
        assert_eq!(contents.contains("2 with vertex tangents"), smooth, "{contents}");
        let n = floor_normal(&scene);
        let expected = (Vec3::X * (0.5 * texel(218.0)) - Vec3::Z * (0.5 * texel(128.0))
            + Vec3::Y * texel(218.0))
        .normalize();
        assert_eq!(n.geometric, Vec3::Y);
        assert!((n.shading - expected).length() < 1e-5, "{smooth}: {} against {expected}", n.shading);
    }
    let mut doc = normal_mapped_doc(1.0, false);
    doc["materials"][0]["normalTexture"]["extensions"]["KHR_texture_transform"]["offset"] = json!("left");
    let err = load(&doc).unwrap_err().to_string();
    assert!(err.contains("normalTexture.extensions.KHR_texture_transform"), "{err}");
}

/// `doc` with a VEC4 float attribute `TANGENT` on its first primitive, one `tangent` a vertex.
fn with_tangents(mut doc: Value, tangent: [f32; 4]) -> Value {
    let prim = &doc["meshes"][0]["primitives"][0];
    let vertices = doc["accessors"][prim["attributes"]["POSITION"].as_u64().unwrap() as usize]["count"]
        .as_u64()
        .unwrap() as usize;
    let bytes: Vec<u8> = (0..vertices).flat_map(|_| tangent).flat_map(f32::to_le_bytes).collect();
    let accessors = push_accessors(&mut doc, &bytes, &[(0, bytes.len(), 5126, "VEC4", false, vertices)]);
    doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = json!(accessors);
    doc
}

/// A mesh's `TANGENT` sets the normal texture's frame (the spec's bitangent w (n × t)), through
/// the node's transform, a mirroring one included; a mesh without `NORMAL` is flat and its
/// `TANGENT` ignored, as the spec says; a tangent that is not finite is refused by name.
#[test]
fn a_mesh_tangent_sets_the_normal_textures_frame() {
    let (x, y) = (0.5 * texel(218.0), 0.5 * texel(128.0));
    // Tangents along +z, w = 1: the bitangent +y × +z = +x; the texel's x leans along +z.
    let scene = load(&with_tangents(normal_mapped_doc(0.5, true), [0.0, 0.0, 1.0, 1.0])).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let expected = (Vec3::Z * x + Vec3::X * y + Vec3::Y * texel(218.0)).normalize();
    let n = floor_normal(&scene);
    assert!((n.shading - expected).length() < 1e-5, "{} against {expected}", n.shading);
    // w = −1 turns the bitangent, and with it the texel's y.
    let scene = load(&with_tangents(normal_mapped_doc(0.5, true), [0.0, 0.0, 1.0, -1.0])).unwrap();
    let expected = (Vec3::Z * x - Vec3::X * y + Vec3::Y * texel(218.0)).normalize();
    let n = floor_normal(&scene);
    assert!((n.shading - expected).length() < 1e-5, "{} against {expected}", n.shading);
    // The node turns the floor's mesh a quarter about +y (+x to −z, +z to +x): the floor is
    // the same square, its mesh's +z tangents now +x, which is the mapping frame again.
    let mut doc = with_tangents(normal_mapped_doc(0.5, true), [0.0, 0.0, 1.0, 1.0]);
    let half = std::f32::consts::FRAC_PI_4;
    let mesh_node = doc["nodes"].as_array().unwrap().iter().position(|n| n.get("mesh").is_some()).unwrap();
    doc["nodes"][mesh_node]["rotation"] = json!([0.0, half.sin(), 0.0, half.cos()]);
    let turned = floor_normal(&load(&doc).unwrap());
    let expected = (Vec3::X * x + Vec3::Z * -y + Vec3::Y * texel(218.0)).normalize();
    assert!((turned.shading - expected).length() < 1e-4, "{} against {expected}", turned.shading);
    // A mirroring node (z to −z) takes the mesh's +z tangents to −z and flips w, so that the
    // bitangent, w (n × t) with the transformed normal +y, is the mirrored mesh's +x still.
    let mut doc = with_tangents(normal_mapped_doc(0.5, true), [0.0, 0.0, 1.0, 1.0]);
    doc["nodes"][mesh_node]["scale"] = json!([1.0, 1.0, -1.0]);
    let mirrored = floor_normal(&load(&doc).unwrap());
    let expected = (-Vec3::Z * x + Vec3::X * y + Vec3::Y * texel(218.0)).normalize();
    assert_eq!(mirrored.geometric, Vec3::Y);
    assert!((mirrored.shading - expected).length() < 1e-5, "{} against {expected}", mirrored.shading);
    // No NORMAL: flat, the TANGENT ignored (the mapping's frame, +x).
    let flat = load(&with_tangents(normal_mapped_doc(0.5, false), [0.0, 0.0, 1.0, 1.0])).unwrap();
    assert!(flat.tangents.iter().all(|t| t.t == [0.0; 12]));
    let expected = (Vec3::X * x - Vec3::Z * y + Vec3::Y * texel(218.0)).normalize();
    assert!((floor_normal(&flat).shading - expected).length() < 1e-5);
    let err = load(&with_tangents(normal_mapped_doc(0.5, true), [f32::NAN, 0.0, 1.0, 1.0]))
        .unwrap_err()
        .to_string();
    assert!(err.contains("meshes[0].primitives[0]: TANGENT 0 is not finite"), "{err}");
    let mut short = with_tangents(normal_mapped_doc(0.5, true), [0.0, 0.0, 1.0, 1.0]);
    let tangent = short["meshes"][0]["primitives"][0]["attributes"]["TANGENT"].as_u64().unwrap() as usize;
    short["accessors"][tangent]["count"] = json!(1);
    let err = load(&short).unwrap_err().to_string();
    assert!(err.contains("meshes[0].primitives[0]: TANGENT has 1 values for"), "{err}");
    let mut vec3 = with_tangents(normal_mapped_doc(0.5, true), [0.0, 0.0, 1.0, 1.0]);
    vec3["accessors"][tangent]["type"] = json!("VEC3");
    let err = load(&vec3).unwrap_err().to_string();
    assert!(err.contains("meshes[0].primitives[0]: TANGENT must be a VEC4 of floats"), "{err}");
    let mut ints = with_tangents(normal_mapped_doc(0.5, true), [0.0, 0.0, 1.0, 1.0]);
    ints["accessors"][tangent]["componentType"] = json!(5123);
    let err = load(&ints).unwrap_err().to_string();
    assert!(err.contains("meshes[0].primitives[0]: TANGENT must be a VEC4 of floats"), "{err}");
}

/// [`normal_mapped_doc`]'s floor without its normal texture, anisotropic by `extension`.
fn anisotropic_doc(smooth: bool, extension: Value) -> Value {
    anisotropic_textured_doc([218, 128, 218, 255], smooth, extension)
}

/// [`anisotropic_doc`] whose texture 0 (1 × 1, linear, nearest) is `texel`, for the extension's
/// anisotropyTexture.
fn anisotropic_textured_doc(texel: [u8; 4], smooth: bool, extension: Value) -> Value {
    let mut doc = textured_floor_doc(texel, 1.0, smooth);
    let material = &mut doc["materials"][0];
    material.as_object_mut().unwrap().remove("normalTexture");
    material["pbrMetallicRoughness"]["metallicFactor"] = json!(1.0);
    material["pbrMetallicRoughness"]["roughnessFactor"] = json!(0.4);
    material["extensions"] = json!({ "KHR_materials_anisotropy": extension });
    doc["extensionsUsed"] = json!(["KHR_materials_anisotropy", "KHR_lights_punctual"]);
    doc["extensionsRequired"] = json!(["KHR_materials_anisotropy"]);
    doc
}

/// `KHR_materials_anisotropy` reads as the spec defines it: the strength times the rotation's
/// direction, in the tangent frame of the mesh's `TANGENT` or else MikkTSpace's over
/// `TEXCOORD_0` (x along dp/du, +x here; the bitangent up the image, −dp/dv, as for a normal
/// texture: −z), which the floor's
/// `Normals::anisotropy` carries into the world; a flat mesh's triangles' own frames; a file
/// that requires the extension loads. A frame where the mesh gives none is said, and values
/// outside the spec's are refused in one line by path.
#[test]
fn anisotropy_reads_as_the_spec_defines_it_and_bad_values_are_refused() {
    let spec = json!({"anisotropyStrength": 0.6, "anisotropyRotation": 0.5});
    let scene = load(&anisotropic_doc(true, spec.clone())).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let m = scene.materials[1];
    let expected = [0.6 * 0.5f32.cos(), 0.6 * 0.5f32.sin()];
    assert!((m.anisotropy[0] - expected[0]).abs() < 1e-6 && (m.anisotropy[1] - expected[1]).abs() < 1e-6);
    assert!((m.alphas() - glam::Vec2::new(0.16 + 0.84 * 0.36, 0.16)).abs().max_element() < 1e-6);
    assert!(scene.tangents.iter().any(|t| t.t != [0.0; 12]), "MikkTSpace's tangents over TEXCOORD_0");
    let contents = scene.describe_contents();
    assert!(contents.contains("2 with vertex tangents, 2 anisotropic"), "{contents}");
    let direction = (Vec3::X * 0.5f32.cos() - Vec3::Z * 0.5f32.sin()).normalize();
    let n = floor_normal(&scene);
    assert!((n.anisotropy.normalize() - direction).length() < 1e-5, "{} against {direction}", n.anisotropy);
    // The mesh's TANGENT (+z, w = 1: the bitangent +y × +z = +x) turns the direction with it.
    let scene = load(&with_tangents(anisotropic_doc(true, spec.clone()), [0.0, 0.0, 1.0, 1.0])).unwrap();
    let direction = (Vec3::Z * 0.5f32.cos() + Vec3::X * 0.5f32.sin()).normalize();
    let n = floor_normal(&scene);
    assert!((n.anisotropy.normalize() - direction).length() < 1e-5, "{} against {direction}", n.anisotropy);
    // No strength, no direction: the isotropic lobe.
    let scene = load(&anisotropic_doc(true, json!({"anisotropyRotation": 1.0}))).unwrap();
    assert_eq!((scene.materials[1].anisotropy, floor_normal(&scene).anisotropy), ([0.0; 2], Vec3::ZERO));
    // A flat mesh (no NORMAL, so no vertex tangents): each triangle's own frame, dp/du and
    // −dp/dv, which on this floor is the same.
    let flat = load(&anisotropic_doc(false, spec.clone())).unwrap();
    assert!(
        flat.warnings.is_empty() && flat.tangents.iter().all(|t| t.t == [0.0; 12]),
        "{:?}",
        flat.warnings
    );
    let direction = (Vec3::X * 0.5f32.cos() - Vec3::Z * 0.5f32.sin()).normalize();
    let n = floor_normal(&flat);
    assert!((n.anisotropy.normalize() - direction).length() < 1e-5, "{} against {direction}", n.anisotropy);
    // Without TEXCOORD_0 the TANGENT alone gives the frame; without either, a warning.
    let mut bare = anisotropic_doc(true, spec.clone());
    bare["meshes"][0]["primitives"][0]["attributes"].as_object_mut().unwrap().remove("TEXCOORD_0");
    let tangent_only = load(&with_tangents(bare.clone(), [0.0, 0.0, 1.0, 1.0])).unwrap();
    assert!(tangent_only.warnings.is_empty(), "{:?}", tangent_only.warnings);
    let direction = (Vec3::Z * 0.5f32.cos() + Vec3::X * 0.5f32.sin()).normalize();
    assert!((floor_normal(&tangent_only).anisotropy.normalize() - direction).length() < 1e-5);
    let frameless = load(&bare).unwrap();
    let said = "meshes[0].primitives[0]: its material's KHR_materials_anisotropy has no tangent frame here";
    assert!(frameless.warnings.iter().any(|w| w.contains(said)), "{:?}", frameless.warnings);
    for (extension, said) in [
        (json!({"anisotropyStrength": 1.5}), "anisotropyStrength: 1.5: must lie in [0, 1]"),
        (json!({"anisotropyStrength": -0.1}), "anisotropyStrength: -0.1: must lie in [0, 1]"),
        (json!({"anisotropyRotation": "left"}), "anisotropyRotation: \"left\" is not a finite number"),
    ] {
        let err = load(&anisotropic_doc(true, extension)).unwrap_err().to_string();
        assert!(err.contains(&format!("materials[0].extensions.KHR_materials_anisotropy.{said}")), "{err}");
    }
    let err = load(&anisotropic_doc(true, json!(5))).unwrap_err().to_string();
    assert!(err.contains("materials[0].extensions.KHR_materials_anisotropy: 5 is not an object"), "{err}");
}

/// [`textured_floor_doc`]'s floor of one texel (192, 237, 100, 128), without its normal texture,
/// whose material has extension `name` of value `value`.
fn floor_with_extension(name: &str, value: Value) -> Value {
    let mut doc = textured_floor_doc([192, 237, 100, 128], 1.0, true);
    let material = &mut doc["materials"][0];
    material.as_object_mut().unwrap().remove("normalTexture");
    material["extensions"] = json!({ name: value });
    doc["extensionsUsed"] = json!([name, "KHR_lights_punctual"]);
    doc
}

/// The material of [`floor_with_extension`]'s floor at (0.3, 0, −0.2).
fn floor_material(scene: &SceneData) -> Material {
    let shared_scene = scene.shared();
    let p = Vec3::new(0.3, 0.0, -0.2);
    let hit = shared_scene.caster.closest_hit(p + Vec3::Y, -Vec3::Y, 0.0, NO_HIT, 0);
    shared::surface::material_at(&shared_scene, hit.triangle, p)
}

/// `KHR_materials_specular`'s textures read as the spec defines them: specularTexture's alpha
/// (linear) multiplies specularFactor, specularColorTexture's rgb (sRGB-decoded) multiplies
/// specularColorFactor, each at the point's own coordinates; a reference to no texture is
/// refused by its path.
#[test]
fn specular_textures_multiply_their_factors() {
    let doc = |specular: Value| floor_with_extension("KHR_materials_specular", specular);
    let spec = json!({"specularFactor": 0.5, "specularTexture": {"index": 0},
        "specularColorFactor": [1.0, 0.5, 0.25], "specularColorTexture": {"index": 0}});
    let scene = load(&doc(spec)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let t = scene.material_textures[scene.materials[1].textures as usize];
    assert!(t.specular.is_some() && t.specular_color.is_some());
    let m = floor_material(&scene);
    assert!((m.specular - 0.5 * 128.0 / 255.0).abs() < 1e-6, "{}", m.specular);
    let decoded = [192.0f32, 237.0, 100.0].map(|c| shared::texture::srgb_to_linear(c / 255.0));
    let expected = [decoded[0], 0.5 * decoded[1], 0.25 * decoded[2]];
    assert!(
        m.specular_color.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-6),
        "{:?}",
        m.specular_color
    );
    let err = load(&doc(json!({"specularTexture": {"index": 7}}))).unwrap_err().to_string();
    assert!(err.contains("specularTexture"), "{err}");
}

/// `KHR_materials_transmission`'s transmissionTexture reads as the spec defines it: its red
/// (linear) multiplies transmissionFactor point by point, and the point's transmission mixes with
/// the point's metallic (its metallicRoughnessTexture's blue × metallicFactor) as the untextured
/// material's does. Without a factor the texture is not read; a reference to no texture is
/// refused by its path.
#[test]
fn a_transmission_texture_scales_the_glass_share() {
    let doc = |transmission: Value| {
        let mut doc = floor_with_extension("KHR_materials_transmission", transmission);
        let pbr = &mut doc["materials"][0]["pbrMetallicRoughness"];
        pbr["metallicFactor"] = json!(0.6);
        pbr["metallicRoughnessTexture"] = json!({"index": 0});
        doc
    };
    let scene = load(&doc(json!({"transmissionFactor": 0.9, "transmissionTexture": {"index": 0}}))).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let m = floor_material(&scene);
    let (metallic, transmission) = (0.6 * 100.0 / 255.0, 0.9 * 192.0 / 255.0);
    let glass = transmission * (1.0 - metallic);
    assert!((m.transmission - glass).abs() < 1e-6, "{} against {glass}", m.transmission);
    assert!((m.metallic - metallic / (1.0 - glass)).abs() < 1e-6, "{}", m.metallic);
    // The same as the untextured material of the products.
    let mut products = doc(json!({ "transmissionFactor": transmission }));
    let pbr = &mut products["materials"][0]["pbrMetallicRoughness"];
    pbr.as_object_mut().unwrap().remove("metallicRoughnessTexture");
    pbr["metallicFactor"] = json!(metallic);
    let untextured = floor_material(&load(&products).unwrap());
    assert!(
        (m.transmission - untextured.transmission).abs() < 1e-6
            && (m.metallic - untextured.metallic).abs() < 1e-6
    );
    // No factor: nothing to multiply, the texture is not read.
    let off = load(&doc(json!({"transmissionFactor": 0.0, "transmissionTexture": {"index": 0}}))).unwrap();
    assert!(!off.material_textures[off.materials[1].textures as usize].transmission.is_some());
    assert_eq!(floor_material(&off).transmission, 0.0);
    let err = load(&doc(json!({"transmissionFactor": 0.5, "transmissionTexture": {"index": 7}})))
        .unwrap_err()
        .to_string();
    assert!(err.contains("transmissionTexture"), "{err}");
}

/// `KHR_materials_sheen` reads as the spec defines it: sheenColorFactor and
/// sheenRoughnessFactor into the material (`shared::sheen`), sheenColorTexture's rgb
/// (sRGB-decoded) multiplying the colour and sheenRoughnessTexture's alpha (linear) the
/// roughness, each at the point; black turns the layer off and leaves its textures unread;
/// the extension may be required, and values outside [0, 1] or a reference to no texture are
/// refused by their paths.
#[test]
fn the_sheen_reads_its_factors_and_textures() {
    let doc = |sheen: Value| floor_with_extension("KHR_materials_sheen", sheen);
    let plain =
        load(&doc(json!({"sheenColorFactor": [0.9, 0.5, 0.2], "sheenRoughnessFactor": 0.4}))).unwrap();
    assert!(plain.warnings.is_empty(), "{:?}", plain.warnings);
    let m = plain.materials[1];
    assert_eq!((m.sheen_color, m.sheen_roughness), ([0.9, 0.5, 0.2], 0.4));
    let textured = json!({"sheenColorFactor": [1.0, 0.5, 0.25], "sheenColorTexture": {"index": 0},
        "sheenRoughnessFactor": 0.8, "sheenRoughnessTexture": {"index": 0}});
    let scene = load(&doc(textured)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let m = floor_material(&scene);
    let decoded = [192.0f32, 237.0, 100.0].map(|c| shared::texture::srgb_to_linear(c / 255.0));
    let expected = [decoded[0], 0.5 * decoded[1], 0.25 * decoded[2]];
    assert!(m.sheen_color.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-6), "{:?}", m.sheen_color);
    assert!((m.sheen_roughness - 0.8 * 128.0 / 255.0).abs() < 1e-6, "{}", m.sheen_roughness);
    // Black: no layer, the textures unread.
    let off = load(&doc(json!({"sheenRoughnessFactor": 0.5, "sheenColorTexture": {"index": 0}}))).unwrap();
    assert!(!off.materials[1].has_sheen());
    assert!(!off.material_textures[off.materials[1].textures as usize].sheen_color.is_some());
    // Blender marks it required where a lamp is; smlt reads it.
    let mut required = doc(json!({"sheenColorFactor": [1.0, 1.0, 1.0]}));
    required["extensionsRequired"] = json!(["KHR_materials_sheen"]);
    assert!(load(&required).unwrap().materials[1].has_sheen());
    for (sheen, names) in [
        (json!({"sheenColorFactor": [1.2, 0.0, 0.0]}), "sheenColorFactor"),
        (json!({"sheenColorFactor": [1.0, 0.0]}), "sheenColorFactor"),
        (json!({"sheenRoughnessFactor": -0.1}), "sheenRoughnessFactor"),
        (
            json!({"sheenColorFactor": [1.0, 1.0, 1.0], "sheenRoughnessTexture": {"index": 7}}),
            "sheenRoughnessTexture",
        ),
    ] {
        let err = load(&doc(sheen)).unwrap_err().to_string();
        assert!(err.contains(names) && err.contains("KHR_materials_sheen"), "{err}");
    }
}

/// `KHR_materials_anisotropy`'s anisotropyTexture reads as the spec defines it: the texel's red
/// and green, 2 c − 1, are the direction in the tangent frame, turned by anisotropyRotation;
/// its blue multiplies anisotropyStrength (linear, no sRGB decoding). Without strength the
/// texture is not read; a reference to no texture is refused by its path.
#[test]
fn an_anisotropy_texture_turns_and_scales_the_lobe() {
    let (r, g, b) = (192.0f32, 237.0f32, 100.0f32);
    let spec =
        json!({"anisotropyStrength": 0.6, "anisotropyRotation": 0.5, "anisotropyTexture": {"index": 0}});
    let scene = load(&anisotropic_textured_doc([192, 237, 100, 255], true, spec)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let t = scene.material_textures[scene.materials[1].textures as usize];
    assert!(t.anisotropy.is_some() && t.anisotropic == 1);
    // The direction: the texel's angle plus the rotation, in the frame (+x, −z).
    let angle = texel(g).atan2(texel(r)) + 0.5;
    let direction = Vec3::X * angle.cos() - Vec3::Z * angle.sin();
    let n = floor_normal(&scene);
    assert!((n.anisotropy.normalize() - direction).length() < 1e-5, "{} against {direction}", n.anisotropy);
    // The strength: 0.6 × b / 255, which the material at the point carries.
    let shared_scene = scene.shared();
    let p = Vec3::new(0.3, 0.0, -0.2);
    let hit = shared_scene.caster.closest_hit(p + Vec3::Y, -Vec3::Y, 0.0, NO_HIT, 0);
    let m = shared::surface::material_at(&shared_scene, hit.triangle, p);
    let strength = glam::Vec2::from_array(m.anisotropy).length();
    assert!((strength - 0.6 * b / 255.0).abs() < 1e-6, "{strength}");
    let s2 = strength * strength;
    assert!((m.alphas() - glam::Vec2::new(0.16 + 0.84 * s2, 0.16)).abs().max_element() < 1e-6);
    // No strength: the texture is not read.
    let off = json!({"anisotropyStrength": 0.0, "anisotropyTexture": {"index": 0}});
    let scene = load(&anisotropic_textured_doc([192, 237, 100, 255], true, off)).unwrap();
    let t = scene.material_textures[scene.materials[1].textures as usize];
    assert!(!t.anisotropy.is_some() && t.anisotropic == 0);
    let bad = json!({"anisotropyStrength": 0.6, "anisotropyTexture": {"index": 7}});
    let err = load(&anisotropic_textured_doc([192, 237, 100, 255], true, bad)).unwrap_err().to_string();
    let said = "materials[0].extensions.KHR_materials_anisotropy.anisotropyTexture.index: 7 names no texture";
    assert!(err.contains(said), "{err}");
    let bad = json!({"anisotropyStrength": 0.6, "anisotropyTexture": {"texCoord": 0}});
    let err = load(&anisotropic_textured_doc([192, 237, 100, 255], true, bad)).unwrap_err().to_string();
    assert!(err.contains("anisotropyTexture: no texture index"), "{err}");
}

/// `KHR_materials_clearcoat` reads as the spec defines it: the intensity and roughness factors
/// (α = roughness²; 0 by default), their textures with their own texCoord and transform, the
/// coat's normal texture and its scale, the extension accepted where a file requires it; what
/// smlt does not model (the emission's darkening) is said, and values outside the spec's ranges
/// and references to no texture are refused in one line by their glTF path.
#[test]
fn clearcoat_reads_as_the_spec_defines_it_and_bad_values_are_refused() {
    let base: Value = serde_json::from_str(include_str!("../scenes/textured.gltf")).unwrap();
    // Material 0 of the document (the checker floor: Lambert, a base colour texture, TEXCOORD_0)
    // is the scene's 1.
    let coated = |coat: Value, edit: &dyn Fn(&mut Value)| {
        let mut doc = base.clone();
        doc["materials"][0]["extensions"]["KHR_materials_clearcoat"] = coat;
        doc["extensionsUsed"].as_array_mut().unwrap().push(json!("KHR_materials_clearcoat"));
        edit(&mut doc);
        load(&doc)
    };
    let scene = coated(json!({"clearcoatFactor": 0.8, "clearcoatRoughnessFactor": 0.5}), &|_| {}).unwrap();
    let m = scene.materials[1];
    assert_eq!((m.clearcoat, m.clearcoat_alpha), (0.8, 0.25));
    let t = scene.material_textures[m.textures as usize];
    assert!(!t.clearcoat.is_some() && !t.clearcoat_roughness.is_some());
    assert_eq!((t.clearcoat_factor, t.clearcoat_roughness_factor), (0.8, 0.5));
    assert!(scene.warnings.iter().all(|w| !w.contains("clear")), "{:?}", scene.warnings);
    let plain = coated(json!({}), &|_| {}).unwrap().materials[1];
    assert_eq!((plain.clearcoat, plain.clearcoat_alpha), (0.0, 0.0), "the spec's defaults: no coat");
    // Textures: the intensity from texture 1 on TEXCOORD_0 scaled by 2, the roughness from
    // texture 0; required by the file, which smlt reads.
    let scene = coated(
        json!({
            "clearcoatFactor": 1.0,
            "clearcoatTexture": {"index": 1, "extensions": {"KHR_texture_transform": {"scale": [2.0, 2.0]}}},
            "clearcoatRoughnessFactor": 0.4,
            "clearcoatRoughnessTexture": {"index": 0, "texCoord": 0},
        }),
        &|doc| doc["extensionsRequired"] = json!(["KHR_materials_clearcoat"]),
    )
    .unwrap();
    let t = scene.material_textures[scene.materials[1].textures as usize];
    assert!(t.clearcoat.is_some() && t.clearcoat_roughness.is_some());
    assert_ne!(t.clearcoat.texture, t.clearcoat_roughness.texture);
    assert_eq!(t.clearcoat_roughness.texture, t.base_color.texture, "the floor's own texture 0");
    assert_eq!((t.clearcoat.transform[0], t.clearcoat.transform[3]), (2.0, 2.0));
    assert_eq!((t.clearcoat_factor, t.clearcoat_roughness_factor), (1.0, 0.4));
    // A coat of intensity 0 is off, its textures unread.
    let off = coated(json!({"clearcoatFactor": 0.0, "clearcoatTexture": {"index": 1}}), &|_| {}).unwrap();
    assert!(!off.material_textures[off.materials[1].textures as usize].clearcoat.is_some());
    // A coat texture alone makes a material textured: on the untextured "plain" (document
    // material 3), whose meshes have no TEXCOORD_0, it is refused by name.
    let mut doc = base.clone();
    doc["materials"][3]["extensions"]["KHR_materials_clearcoat"] =
        json!({"clearcoatFactor": 1.0, "clearcoatTexture": {"index": 1}});
    let Err(text) = load(&doc).map_err(|e| e.to_string()) else { panic!("loaded without TEXCOORD_0") };
    assert!(text.contains("reads TEXCOORD_0, which the primitive does not have"), "{text}");
    // The coat's own normal texture, with its scale.
    let scene = coated(
        json!({"clearcoatFactor": 1.0, "clearcoatNormalTexture": {"index": 1, "scale": 0.5}}),
        &|_| {},
    )
    .unwrap();
    let t = scene.material_textures[scene.materials[1].textures as usize];
    assert!(t.clearcoat_normal.is_some() && !t.normal.is_some() && t.clearcoat_normal_scale == 0.5);
    // What is not modelled is said: an emission the coat does not darken.
    let warned = |coat: Value, edit: &dyn Fn(&mut Value), what: &str| {
        let scene = coated(coat, edit).unwrap();
        assert!(
            scene.warnings.iter().any(|w| w.contains("'checker floor'") && w.contains(what)),
            "{:?}",
            scene.warnings
        );
    };
    warned(
        json!({"clearcoatFactor": 1.0}),
        &|doc| doc["materials"][0]["emissiveFactor"] = json!([1.0, 1.0, 1.0]),
        "not darkened",
    );
    for (coat, what) in [
        (json!({"clearcoatFactor": 1.5}), "KHR_materials_clearcoat.clearcoatFactor: 1.5 is outside [0, 1]"),
        (json!({"clearcoatRoughnessFactor": -0.5}), "clearcoatRoughnessFactor: -0.5 is outside [0, 1]"),
        (json!({"clearcoatFactor": "glossy"}), "clearcoatFactor: \"glossy\" is not a finite number"),
        (
            json!({"clearcoatFactor": 1.0, "clearcoatTexture": {"index": 9}}),
            "clearcoatTexture.index: 9 names no texture",
        ),
        (
            json!({"clearcoatFactor": 1.0, "clearcoatRoughnessTexture": {}}),
            "clearcoatRoughnessTexture: no index",
        ),
        (
            json!({"clearcoatFactor": 1.0, "clearcoatNormalTexture": {"index": 0, "scale": "deep"}}),
            "clearcoatNormalTexture.scale: \"deep\" is not a finite number",
        ),
    ] {
        match coated(coat, &|_| {}) {
            Err(e @ SceneError::Malformed { .. }) => {
                let text = e.to_string();
                assert!(text.contains("materials[0].extensions.") && text.contains(what), "{text}");
                assert_eq!(text.lines().count(), 1, "{text}");
            }
            other => panic!("{what}: {:?}", other.map(|_| "loaded")),
        }
    }
}

/// The bytes of buffer `b` of `doc` (a `data:` URI).
fn buffer_bytes(doc: &Value, b: usize) -> Vec<u8> {
    buffer_of_uri(doc["buffers"][b]["uri"].as_str().unwrap())
}

/// The floats of accessor `k` of `doc` (float components, from a `data:` buffer).
fn accessor_floats(doc: &Value, k: usize) -> Vec<f32> {
    let a = &doc["accessors"][k];
    assert_eq!(a["componentType"], 5126);
    let view = &doc["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
    let bytes = buffer_bytes(doc, view["buffer"].as_u64().unwrap() as usize);
    let n: usize = match a["type"].as_str().unwrap() {
        "VEC2" => 2,
        "VEC3" => 3,
        _ => 4,
    };
    let stride = view["byteStride"].as_u64().map_or(4 * n, |s| s as usize);
    let start =
        view["byteOffset"].as_u64().unwrap_or(0) as usize + a["byteOffset"].as_u64().unwrap_or(0) as usize;
    (0..a["count"].as_u64().unwrap() as usize)
        .flat_map(|i| (0..n).map(move |c| start + i * stride + 4 * c))
        .map(|o| f32::from_le_bytes(bytes[o..o + 4].try_into().unwrap()))
        .collect()
}

/// `doc` (a builder's document, floats in `data:` buffers) as gltfpack writes it with
/// `KHR_mesh_quantization`, from the spec's text: positions as unsigned shorts, not normalised,
/// on a grid of `step` from `origin`, which a new child node of each mesh's node undoes (its
/// translation and scale); normals and tangents as normalised signed bytes, each element padded
/// to 4 bytes; TEXCOORD_0 as normalised signed shorts (the builder's planar ones lie in [−1, 1]).
fn quantized(doc: &Value, origin: Vec3, step: f32) -> Value {
    let mut out = doc.clone();
    let mut bytes: Vec<u8> = Vec::new();
    let buffer = out["buffers"].as_array().unwrap().len();
    let meshes = out["meshes"].as_array().unwrap().len();
    for m in 0..meshes {
        let primitives = out["meshes"][m]["primitives"].as_array().unwrap().len();
        for p in 0..primitives {
            let attributes: Vec<(String, usize)> = out["meshes"][m]["primitives"][p]["attributes"]
                .as_object()
                .unwrap()
                .iter()
                .map(|(k, v)| (k.clone(), v.as_u64().unwrap() as usize))
                .collect();
            for (name, k) in attributes {
                let floats = accessor_floats(doc, k);
                // (components, component type, normalised, element stride in bytes)
                let (n, component, normalized, stride) = match name.as_str() {
                    "POSITION" => (3, 5123, false, 8),
                    "NORMAL" => (3, 5120, true, 4),
                    "TANGENT" => (4, 5120, true, 4),
                    "TEXCOORD_0" => (2, 5122, true, 4),
                    _ => continue,
                };
                let encode = |c: usize, x: f32| -> Vec<u8> {
                    match component {
                        5123 => {
                            let q = ((x - origin[c]) / step).round();
                            assert!((0.0..65536.0).contains(&q), "{x} off the grid's range");
                            (q as u16).to_le_bytes().to_vec()
                        }
                        5120 => vec![(x * 127.0).round() as i8 as u8],
                        _ => {
                            assert!((-1.0..=1.0).contains(&x), "coordinate {x} outside [-1, 1]");
                            ((x * 32767.0).round() as i16).to_le_bytes().to_vec()
                        }
                    }
                };
                bytes.resize(bytes.len().next_multiple_of(4), 0);
                let offset = bytes.len();
                for element in floats.chunks(n) {
                    let mut e: Vec<u8> =
                        element.iter().enumerate().flat_map(|(c, &x)| encode(c, x)).collect();
                    e.resize(stride, 0);
                    bytes.extend(e);
                }
                let view = out["bufferViews"].as_array().unwrap().len();
                out["bufferViews"].as_array_mut().unwrap().push(json!({
                    "buffer": buffer, "byteOffset": offset, "byteLength": bytes.len() - offset, "byteStride": stride
                }));
                out["accessors"][k] = json!({
                    "bufferView": view, "componentType": component, "normalized": normalized,
                    "count": floats.len() / n, "type": format!("VEC{n}")
                });
                if name == "POSITION" {
                    // The spec's min and max, in the accessor's own (integer) values.
                    let q: Vec<u16> = bytes[offset..]
                        .chunks(8)
                        .flat_map(|e| e[..6].chunks(2).map(|c| u16::from_le_bytes([c[0], c[1]])))
                        .collect();
                    let axis = |c: usize, f: fn(u16, u16) -> u16| {
                        q.iter().skip(c).step_by(3).copied().reduce(f).unwrap()
                    };
                    out["accessors"][k]["min"] = json!([0, 1, 2].map(|c| axis(c, u16::min)));
                    out["accessors"][k]["max"] = json!([0, 1, 2].map(|c| axis(c, u16::max)));
                }
            }
        }
    }
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bytes)
    );
    out["buffers"].as_array_mut().unwrap().push(json!({"byteLength": bytes.len(), "uri": uri}));
    let nodes = out["nodes"].as_array().unwrap().len();
    for i in 0..nodes {
        if let Some(mesh) = out["nodes"][i].as_object_mut().unwrap().remove("mesh") {
            let child = out["nodes"].as_array().unwrap().len();
            out["nodes"].as_array_mut().unwrap().push(json!({
                "mesh": mesh, "translation": origin.to_array(), "scale": [step, step, step]
            }));
            out["nodes"][i]["children"] = json!([child]);
        }
    }
    out["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
    out["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
    out
}

/// `KHR_mesh_quantization` (positions as unsigned shorts under a dequantising node, normals and
/// tangents as normalised bytes, coordinates as normalised shorts) loads as the float file it
/// was made from: the same triangles, normals, coordinates, tangent frames and shading normal,
/// through a turned node; a file that uses the extension without requiring it, or integers
/// without the extension, is refused in one line.
#[test]
fn quantized_attributes_load_as_the_floats_they_encode() {
    let mut float = with_tangents(normal_mapped_doc(0.5, true), [0.0, 0.0, 1.0, 1.0]);
    let mesh_node = float["nodes"].as_array().unwrap().iter().position(|n| n.get("mesh").is_some()).unwrap();
    let half = std::f32::consts::FRAC_PI_4 / 2.0;
    float["nodes"][mesh_node]["rotation"] = json!([0.0, half.sin(), 0.0, half.cos()]);
    // The floor's corners (±1) lie on the grid: the positions decode exactly.
    let quantized = quantized(&float, Vec3::splat(-1.0), 1.0 / 1024.0);
    let (a, b) = (load(&float).unwrap(), load(&quantized).unwrap());
    assert!(b.warnings.is_empty(), "{:?}", b.warnings);
    assert_eq!(a.triangles.len(), b.triangles.len());
    for (s, t) in a.triangles.iter().zip(&b.triangles) {
        for (u, v) in [(s.v0, t.v0), (s.v1, t.v1), (s.v2, t.v2)] {
            assert!((Vec3::from_array(u) - Vec3::from_array(v)).length() < 1e-6, "{u:?} against {v:?}");
        }
    }
    let close =
        |x: &[f32], y: &[f32], tolerance: f32| x.iter().zip(y).all(|(p, q)| (p - q).abs() <= tolerance);
    for (s, t) in a.normals.iter().zip(&b.normals) {
        assert!(close(&s.n, &t.n, 1e-6), "{:?} against {:?}", s.n, t.n);
    }
    for (s, t) in a.texcoords.iter().zip(&b.texcoords) {
        assert!(close(&s.uv, &t.uv, 1e-6), "{:?} against {:?}", s.uv, t.uv);
    }
    assert!(a.tangents.iter().zip(&b.tangents).all(|(s, t)| close(&s.t, &t.t, 1e-6)));
    let (na, nb) = (floor_normal(&a), floor_normal(&b));
    assert!((na.shading - nb.shading).length() < 1e-6, "{} against {}", na.shading, nb.shading);
    assert!(na.shading.dot(Vec3::Y) < 0.99, "the normal texture bends the floor's normal");
    // The extension used but not required; integers without it.
    let mut optional = quantized.clone();
    optional["extensionsRequired"] = json!([]);
    let err = load(&optional).unwrap_err().to_string();
    assert!(err.contains("KHR_mesh_quantization is used but not required"), "{err}");
    let mut undeclared = quantized.clone();
    undeclared.as_object_mut().unwrap().remove("extensionsUsed");
    undeclared.as_object_mut().unwrap().remove("extensionsRequired");
    let err = load(&undeclared).unwrap_err().to_string();
    assert!(
        err.contains("must be a VEC3 of floats (integers need KHR_mesh_quantization, used and required)"),
        "{err}"
    );
    assert!(!err.contains('\n'));
}

/// A `data:` URI of `bytes` as `mime`.
fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!("data:{mime};base64,{}", base64::engine::general_purpose::STANDARD.encode(bytes))
}

/// `EXT_texture_webp`: a texture with the extension reads its WebP image (lossless, and lossy
/// from the Khronos validator's samples), not its fallback `source`, with or without that
/// fallback and with the extension required; a WebP source that names no image, or WebP data
/// that does not decode, is refused in one line.
#[test]
fn webp_textures_read_the_extensions_image() {
    let base: Value = serde_json::from_str(include_str!("../scenes/textured.gltf")).unwrap();
    let plain = load(&base).unwrap();
    // Texture 0 (image 0, the floor's checker) as a lossless WebP, image 4.
    let png = buffer_of_uri(base["images"][0]["uri"].as_str().unwrap());
    let rgba = image::load_from_memory(&png).unwrap().to_rgba8();
    let mut webp = Vec::new();
    image::codecs::webp::WebPEncoder::new_lossless(&mut webp)
        .encode(&rgba, rgba.width(), rgba.height(), image::ExtendedColorType::Rgba8)
        .unwrap();
    let with_webp = |webp: &[u8], fallback: bool, required: bool| {
        let mut doc = base.clone();
        doc["images"].as_array_mut().unwrap().push(json!({"uri": data_uri("image/webp", webp)}));
        doc["textures"][0]["extensions"] = json!({"EXT_texture_webp": {"source": 4}});
        if fallback {
            // A fallback of another colour, which a client with the extension does not read.
            let mut magenta = Vec::new();
            image::RgbaImage::from_pixel(1, 1, image::Rgba([255, 0, 255, 255]))
                .write_to(&mut std::io::Cursor::new(&mut magenta), image::ImageFormat::Png)
                .unwrap();
            doc["images"][0]["uri"] = json!(data_uri("image/png", &magenta));
        } else {
            doc["textures"][0].as_object_mut().unwrap().remove("source");
        }
        doc["extensionsUsed"].as_array_mut().unwrap().push(json!("EXT_texture_webp"));
        if required {
            doc["extensionsRequired"] = json!(["EXT_texture_webp"]);
        }
        doc
    };
    for (fallback, required) in [(true, false), (false, true), (true, true)] {
        let scene = load(&with_webp(&webp, fallback, required)).unwrap();
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        assert_eq!(scene.textures, plain.textures, "fallback {fallback}, required {required}");
        assert_eq!(scene.texels, plain.texels, "fallback {fallback}, required {required}");
    }
    // Lossy (VP8) and extended (VP8X, with alpha) WebP: the validator's red samples.
    for (file, alpha) in [("VP8_red.webp", 255), ("VP8X_red_transparent.webp", 128)] {
        let bytes = std::fs::read(format!("tests/khronos/ext/EXT_texture_webp/data/image/{file}")).unwrap();
        let scene = load(&with_webp(&bytes, true, false)).unwrap();
        let floor = scene.textures[0];
        let texel = scene.texels[floor.offset as usize].to_le_bytes();
        assert!(texel[0] > 240 && texel[1] < 16 && texel[2] < 16 && texel[3] == alpha, "{file}: {texel:?}");
    }
    let mut unresolved = with_webp(&webp, true, false);
    unresolved["textures"][0]["extensions"]["EXT_texture_webp"]["source"] = json!(9);
    let err = load(&unresolved).unwrap_err().to_string();
    assert!(err.contains("textures[0].extensions.EXT_texture_webp.source: 9 names no image"), "{err}");
    let err = load(&with_webp(&webp[..webp.len() / 2], true, false)).unwrap_err().to_string();
    assert!(err.contains("images[4]: its WebP data does not decode"), "{err}");
    assert!(!err.contains('\n'));
}

/// The bytes of a base64 `data:` URI.
fn buffer_of_uri(uri: &str) -> Vec<u8> {
    base64::engine::general_purpose::STANDARD.decode(uri.split_once(',').unwrap().1).unwrap()
}

/// `doc` (one of [`quantized`]'s, its data in `data:` buffers) as gltfpack `-c` writes it: every
/// view the accessors read compressed with meshoptimizer's encoders (`EXT_meshopt_compression`:
/// vertex attributes as ATTRIBUTES, indices as INDICES, which keeps their order) into one new
/// buffer, each view's own buffer a fallback with no data.
fn compressed(doc: &Value) -> Value {
    let mut out = doc.clone();
    let mut packed: Vec<u8> = Vec::new();
    let fallback = out["buffers"].as_array().unwrap().len();
    let data = fallback + 1;
    let mut fallback_length = 0;
    let accessors = out["accessors"].as_array().unwrap().clone();
    for a in &accessors {
        let v = a["bufferView"].as_u64().unwrap() as usize;
        if out["bufferViews"][v].get("extensions").is_some() {
            continue; // shared by another accessor, compressed already
        }
        let view = out["bufferViews"][v].clone();
        let bytes = buffer_bytes(doc, view["buffer"].as_u64().unwrap() as usize);
        let (offset, length) = (
            view["byteOffset"].as_u64().unwrap_or(0) as usize,
            view["byteLength"].as_u64().unwrap() as usize,
        );
        let raw = &bytes[offset..offset + length];
        let index = a["type"] == "SCALAR";
        let stride = match view["byteStride"].as_u64() {
            Some(s) => s as usize,
            None if index => {
                if a["componentType"] == 5125 {
                    4
                } else {
                    2
                }
            }
            None => panic!("an attribute view without a stride"),
        };
        let count = length / stride;
        let (encoded, mode) = if index {
            let indices: Vec<u32> = match stride {
                2 => raw.chunks(2).map(|b| u16::from_le_bytes([b[0], b[1]]) as u32).collect(),
                _ => raw.chunks(4).map(|b| u32::from_le_bytes(b.try_into().unwrap())).collect(),
            };
            let vertices = indices.iter().max().map_or(0, |&m| m as usize + 1);
            (meshopt::encoding::encode_index_sequence(&indices, vertices).unwrap(), "INDICES")
        } else {
            // One element a row of `stride` bytes, as a slice of u32 words (strides are multiples of 4).
            let words: Vec<u32> = raw.chunks(4).map(|b| u32::from_le_bytes(b.try_into().unwrap())).collect();
            let encoded = match stride {
                4 => meshopt::encoding::encode_vertex_buffer(&words).unwrap(),
                8 => meshopt::encoding::encode_vertex_buffer(words.as_chunks::<2>().0).unwrap(),
                12 => meshopt::encoding::encode_vertex_buffer(words.as_chunks::<3>().0).unwrap(),
                16 => meshopt::encoding::encode_vertex_buffer(words.as_chunks::<4>().0).unwrap(),
                s => panic!("stride {s}"),
            };
            (encoded, "ATTRIBUTES")
        };
        packed.resize(packed.len().next_multiple_of(4), 0);
        let at = packed.len();
        packed.extend(&encoded);
        out["bufferViews"][v] = json!({
            "buffer": fallback, "byteOffset": fallback_length, "byteLength": length,
            "extensions": {"EXT_meshopt_compression": {
                "buffer": data, "byteOffset": at, "byteLength": encoded.len(), "byteStride": stride,
                "count": count, "mode": mode
            }}
        });
        if !index {
            out["bufferViews"][v]["byteStride"] = json!(stride);
        }
        fallback_length += length.next_multiple_of(4);
    }
    out["buffers"].as_array_mut().unwrap().push(json!({
        "byteLength": fallback_length, "extensions": {"EXT_meshopt_compression": {"fallback": true}}
    }));
    out["buffers"]
        .as_array_mut()
        .unwrap()
        .push(json!({"byteLength": packed.len(), "uri": data_uri("application/octet-stream", &packed)}));
    for list in ["extensionsUsed", "extensionsRequired"] {
        out[list].as_array_mut().unwrap().push(json!("EXT_meshopt_compression"));
    }
    out
}

/// `EXT_meshopt_compression`: a file whose views are all compressed, its fallback buffer without
/// data, loads as the uncompressed file (the same triangles, normals, coordinates, tangent
/// frames); a compressed stream cut short, or a view that breaks the extension's rules, is
/// refused in one line by its path.
#[test]
fn meshopt_compressed_views_load_as_the_views_they_encode() {
    let float = with_tangents(normal_mapped_doc(0.5, true), [0.0, 0.0, 1.0, 1.0]);
    let plain = quantized(&float, Vec3::splat(-1.0), 1.0 / 1024.0);
    let packed = compressed(&plain);
    let (a, b) = (load(&plain).unwrap(), load(&packed).unwrap());
    assert!(b.warnings.is_empty(), "{:?}", b.warnings);
    assert_eq!(a.triangles, b.triangles);
    assert_eq!(a.normals, b.normals);
    assert_eq!(a.texcoords, b.texcoords);
    assert_eq!(a.tangents, b.tangents);
    // The view of the positions (accessor 0's): its stream cut short, its count wrong.
    let v = packed["accessors"][0]["bufferView"].as_u64().unwrap() as usize;
    let mut short = packed.clone();
    let n = short["bufferViews"][v]["extensions"]["EXT_meshopt_compression"]["byteLength"].as_u64().unwrap();
    short["bufferViews"][v]["extensions"]["EXT_meshopt_compression"]["byteLength"] = json!(n / 2);
    let err = load(&short).unwrap_err().to_string();
    assert!(
        err.contains(&format!(
            "bufferViews[{v}].extensions.EXT_meshopt_compression: its Attributes data does not decode"
        )),
        "{err}"
    );
    // The compressed data's buffer without its data (no uri).
    let mut missing = packed.clone();
    let data = packed["buffers"].as_array().unwrap().len() - 1;
    missing["buffers"][data].as_object_mut().unwrap().remove("uri");
    let err = load(&missing).unwrap_err().to_string();
    assert!(err.contains(&format!("buffers[{data}], whose data is not in the file")), "{err}");
    let mut count = packed.clone();
    count["bufferViews"][v]["extensions"]["EXT_meshopt_compression"]["count"] = json!(1);
    let err = load(&count).unwrap_err().to_string();
    assert!(
        err.contains(&format!("bufferViews[{v}].extensions.EXT_meshopt_compression.count 1 × byteStride")),
        "{err}"
    );
    assert!(!err.contains('\n'));
}

/// `doc` (a builder's document, floats in `data:` buffers) as Blender's exporter and
/// `gltf-transform draco` write it with `KHR_draco_mesh_compression`: each primitive one Draco
/// stream (`draco-core`'s encoder at `speed`, `bits` the quantisation of positions, normals and
/// the other attributes, None for none) in a new buffer, its accessors without views, counted as
/// the stream decodes, and an index accessor (unsigned ints) for its faces.
fn draco_compressed(doc: &Value, speed: i32, bits: Option<[i32; 3]>) -> Value {
    use draco_core::{
        DataType, EncoderBuffer, EncoderOptions, GeometryAttributeType, Mesh, MeshEncoder, PointAttribute,
        PointIndex,
    };
    let mut out = doc.clone();
    let mut packed: Vec<u8> = Vec::new();
    let buffer = out["buffers"].as_array().unwrap().len();
    for m in 0..out["meshes"].as_array().unwrap().len() {
        for p in 0..out["meshes"][m]["primitives"].as_array().unwrap().len() {
            let prim = out["meshes"][m]["primitives"][p].clone();
            let attributes: Vec<(String, usize)> = prim["attributes"]
                .as_object()
                .unwrap()
                .iter()
                .map(|(k, v)| (k.clone(), v.as_u64().unwrap() as usize))
                .collect();
            let mut mesh = Mesh::new();
            let mut options = EncoderOptions::new();
            options.set_global_int("encoding_speed", speed);
            options.set_global_int("decoding_speed", speed);
            let mut points = 0;
            let mut kinds = Vec::new();
            for (name, k) in &attributes {
                let floats = accessor_floats(doc, *k);
                let n = match doc["accessors"][*k]["type"].as_str().unwrap() {
                    "VEC2" => 2,
                    "VEC3" => 3,
                    _ => 4,
                };
                points = floats.len() / n;
                let (kind, q) = match name.as_str() {
                    "POSITION" => (GeometryAttributeType::Position, 0),
                    "NORMAL" => (GeometryAttributeType::Normal, 1),
                    "TEXCOORD_0" => (GeometryAttributeType::TexCoord, 2),
                    _ => (GeometryAttributeType::Generic, 2),
                };
                let mut attribute = PointAttribute::new();
                attribute.init(kind, n as u8, DataType::Float32, false, points);
                let bytes: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
                attribute.buffer_mut().write(0, &bytes);
                let id = mesh.add_attribute(attribute);
                if let Some(bits) = bits {
                    options.set_attribute_int(id, "quantization_bits", bits[q]);
                }
                let bound =
                    |c: usize, f: fn(f32, f32) -> f32| floats.iter().skip(c).step_by(n).copied().reduce(f);
                let bounds = (0..n).map(|c| (bound(c, f32::min), bound(c, f32::max))).collect::<Vec<_>>();
                kinds.push((name.clone(), n, id, bounds));
            }
            mesh.set_num_points(points);
            for f in 0..points / 3 {
                let f = 3 * f as u32;
                mesh.add_face([PointIndex(f), PointIndex(f + 1), PointIndex(f + 2)]);
            }
            let mut encoder = MeshEncoder::new();
            encoder.set_mesh(mesh);
            let mut stream = EncoderBuffer::new();
            let info = encoder.encode_with_info(&options, &mut stream).unwrap();
            packed.resize(packed.len().next_multiple_of(4), 0);
            let view = out["bufferViews"].as_array().unwrap().len();
            out["bufferViews"].as_array_mut().unwrap().push(json!({
                "buffer": buffer, "byteOffset": packed.len(), "byteLength": stream.data().len()
            }));
            packed.extend(stream.data());
            let mut ids = serde_json::Map::new();
            for (name, n, id, bounds) in kinds {
                let a = info.attributes.iter().find(|a| a.source_attribute_id == id).unwrap();
                ids.insert(name.clone(), json!(a.unique_id));
                let k = out["accessors"].as_array().unwrap().len();
                out["accessors"].as_array_mut().unwrap().push(json!({
                    "componentType": 5126, "count": info.num_encoded_points, "type": format!("VEC{n}")
                }));
                if name == "POSITION" {
                    out["accessors"][k]["min"] = json!(bounds.iter().map(|b| b.0).collect::<Vec<_>>());
                    out["accessors"][k]["max"] = json!(bounds.iter().map(|b| b.1).collect::<Vec<_>>());
                }
                out["meshes"][m]["primitives"][p]["attributes"][&name] = json!(k);
            }
            let k = out["accessors"].as_array().unwrap().len();
            out["accessors"].as_array_mut().unwrap().push(json!({
                "componentType": 5125, "count": 3 * info.num_encoded_faces, "type": "SCALAR"
            }));
            out["meshes"][m]["primitives"][p]["indices"] = json!(k);
            out["meshes"][m]["primitives"][p]["extensions"] =
                json!({"KHR_draco_mesh_compression": {"bufferView": view, "attributes": ids}});
        }
    }
    out["buffers"]
        .as_array_mut()
        .unwrap()
        .push(json!({"byteLength": packed.len(), "uri": data_uri("application/octet-stream", &packed)}));
    for list in ["extensionsUsed", "extensionsRequired"] {
        let mut names = out[list].as_array().cloned().unwrap_or_default();
        names.push(json!("KHR_draco_mesh_compression"));
        out[list] = json!(names);
    }
    out
}

/// Whether triangles `s` and `t` have the same corners within `tolerance`, in the same winding
/// from any first corner (Draco's traversal may start a face at any of its corners).
fn same_triangle(s: &shared::triangle::Triangle, t: &shared::triangle::Triangle, tolerance: f32) -> bool {
    let (c, d) = ([s.v0, s.v1, s.v2], [t.v0, t.v1, t.v2]);
    let near = |x: [f32; 3], y: [f32; 3]| {
        (Vec3::from_array(x) - Vec3::from_array(y)).abs().max_element() <= tolerance
    };
    (0..3).any(|r| (0..3).all(|i| near(c[i], d[(i + r) % 3])))
}

/// `KHR_draco_mesh_compression`: a textured, normal-mapped floor with `TANGENT`s and a smooth
/// ball, each primitive one Draco stream. Encoded without quantisation in Draco's sequential
/// mode (which keeps the order) it loads to exactly the float file's triangles, normals,
/// coordinates and tangent frames; with Blender's exporter's settings (EdgeBreaker at speed 4,
/// positions on 14 bits, normals on 10, other attributes on 12) to the same triangles within the
/// quantisation's step, and the same shading normal within a normal's. Without its index
/// accessor the sequential stream loads too (its faces are its points in order). A stream cut
/// short, a count or an attribute id the stream does not hold, or a stream in a buffer the file
/// does not hold, is refused in one line by its path.
#[test]
fn draco_compressed_primitives_load_as_the_meshes_they_encode() {
    let mut float = with_tangents(normal_mapped_doc(0.5, true), [0.0, 0.0, 1.0, 1.0]);
    let mut b = GltfBuilder::new();
    let ball = b.pbr("ball", [0.8; 3], 0.0, 0.3);
    b.smooth_sphere(ball, Vec3::new(0.0, 0.5, 0.0), 0.4, 8);
    let balls: Value = serde_json::from_str(&b.to_json()).unwrap();
    // The ball's mesh, material, accessors, view and buffer appended to the floor's file.
    let shift = |key: &str| float[key].as_array().unwrap().len();
    let (meshes, materials, accessors, views, buffers) =
        (shift("meshes"), shift("materials"), shift("accessors"), shift("bufferViews"), shift("buffers"));
    for mut a in balls["accessors"].as_array().unwrap().clone() {
        a["bufferView"] = json!(a["bufferView"].as_u64().unwrap() as usize + views);
        float["accessors"].as_array_mut().unwrap().push(a);
    }
    for mut v in balls["bufferViews"].as_array().unwrap().clone() {
        v["buffer"] = json!(v["buffer"].as_u64().unwrap() as usize + buffers);
        float["bufferViews"].as_array_mut().unwrap().push(v);
    }
    float["buffers"].as_array_mut().unwrap().extend(balls["buffers"].as_array().unwrap().clone());
    float["materials"].as_array_mut().unwrap().extend(balls["materials"].as_array().unwrap().clone());
    let mut mesh = balls["meshes"][0].clone();
    for p in mesh["primitives"].as_array_mut().unwrap() {
        p["material"] = json!(p["material"].as_u64().unwrap() as usize + materials);
        for (_, k) in p["attributes"].as_object_mut().unwrap() {
            *k = json!(k.as_u64().unwrap() as usize + accessors);
        }
    }
    float["meshes"].as_array_mut().unwrap().push(mesh);
    let node = float["nodes"].as_array().unwrap().len();
    float["nodes"].as_array_mut().unwrap().push(json!({"mesh": meshes}));
    float["scenes"][0]["nodes"].as_array_mut().unwrap().push(json!(node));
    let a = load(&float).unwrap();
    assert!(a.normals.len() > 100, "the ball is smooth: {} normals", a.normals.len());

    // Sequential, not quantised: exactly the float file.
    let exact = load(&draco_compressed(&float, 10, None)).unwrap();
    assert!(exact.warnings.is_empty(), "{:?}", exact.warnings);
    assert_eq!(a.triangles, exact.triangles);
    assert_eq!(a.normals, exact.normals);
    assert_eq!(a.texcoords, exact.texcoords);
    assert_eq!(a.tangents, exact.tangents);
    // Without its index accessor the sequential stream's faces are its points in order.
    let mut sequential = draco_compressed(&float, 10, None);
    sequential["meshes"][0]["primitives"][0].as_object_mut().unwrap().remove("indices");
    assert_eq!(load(&sequential).unwrap().triangles, a.triangles);

    // Blender's exporter's settings: the same triangles, each within the grid's step.
    let blender = draco_compressed(&float, 4, Some([14, 10, 12]));
    let b = load(&blender).unwrap();
    assert!(b.warnings.is_empty(), "{:?}", b.warnings);
    assert_eq!(a.triangles.len(), b.triangles.len());
    let step = 2.0 / (1 << 14) as f32; // the floor's 2 m side on 14 bits
    let mut expected: Vec<_> = a.triangles.clone();
    for t in &b.triangles {
        let i = expected.iter().position(|s| same_triangle(s, t, step));
        let i = i.unwrap_or_else(|| panic!("{:?} is no triangle of the float file", [t.v0, t.v1, t.v2]));
        expected.swap_remove(i);
    }
    let (na, nb) = (floor_normal(&a), floor_normal(&b));
    assert!((na.shading - nb.shading).length() < 4e-3, "{} against {}", na.shading, nb.shading);
    assert!(na.shading.dot(Vec3::Y) < 0.99, "the normal texture bends the floor's normal");

    // Refused by path: the stream cut short, a count, an attribute id, the stream's data missing.
    let at = "meshes[0].primitives[0].extensions.KHR_draco_mesh_compression";
    let v = blender["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"]
        .as_u64()
        .unwrap() as usize;
    let position = blender["meshes"][0]["primitives"][0]["attributes"]["POSITION"].as_u64().unwrap() as usize;
    let points = blender["accessors"][position]["count"].as_u64().unwrap();
    let mut short = blender.clone();
    short["bufferViews"][v]["byteLength"] =
        json!(blender["bufferViews"][v]["byteLength"].as_u64().unwrap() / 2);
    let mut count = blender.clone();
    count["accessors"][position]["count"] = json!(points + 1);
    let mut id = blender.clone();
    id["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["POSITION"] =
        json!(9);
    let mut missing = blender.clone();
    let data = blender["buffers"].as_array().unwrap().len() - 1;
    missing["buffers"][data].as_object_mut().unwrap().remove("uri");
    for (doc, expected) in [
        (short, format!("{at}: its Draco data does not decode")),
        (
            count,
            format!(
                "{at}.attributes.POSITION: accessors[{position}].count {}, but the Draco data decodes {points} points",
                points + 1
            ),
        ),
        (id, format!("{at}.attributes.POSITION: the Draco data has no attribute 9")),
        (missing, format!("buffers[{data}], whose data is not in the file")),
    ] {
        let Err(err) = load(&doc).map_err(|e| e.to_string()) else { panic!("loaded; expected: {expected}") };
        assert!(err.contains(&expected), "{err}\nexpected: {expected}");
        assert!(!err.contains('\n'), "{err}");
    }
}

/// `KHR_draco_mesh_compression` as Blender's exporter writes it (Google's encoder; the lamp-lit
/// glass scene of `scripts/peers/blender_round_trip.py`, `tests/draco/PROVENANCE.md`) loads to
/// exactly the triangles, normals and texture coordinates Google's decoder reads from it.
#[test]
fn blender_s_draco_export_loads_as_google_s_decoder_reads_it() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/draco");
    let draco = SceneData::load(&root.join("blender/round_trip.gltf")).unwrap();
    let decoded = SceneData::load(&root.join("decoded/round_trip.gltf")).unwrap();
    assert!(draco.warnings.is_empty(), "{:?}", draco.warnings);
    assert_eq!(draco.triangles.len(), 1616, "two planes, a cube and two ico spheres");
    assert_eq!(draco.triangles, decoded.triangles);
    assert_eq!(draco.normals, decoded.normals);
    assert_eq!(draco.texcoords, decoded.texcoords);
    assert!(!draco.texcoords.is_empty() && !draco.normals.is_empty());
    assert_eq!(draco.punctual.len(), 3, "the point lamp, the spot and the sun");
}

/// KTX2 textures (`KHR_texture_basisu`, required) as Binomial's Basis Universal encoder writes
/// them — the `textured` scene through `scripts/peers/ktx2_encode.mjs`: ETC1S with BasisLZ and
/// every mip level, UASTC, UASTC with Zstandard (`tests/ktx2/PROVENANCE.md`) — load to exactly
/// the texels Binomial's transcoder reads from them (each variant's `decoded/` twin, its images
/// transcoded by three.js's build of it and written as PNG). Their sizes (a 4×1 and a 16×4 among
/// them) and rows (one texture is not symmetric) are the images'.
#[test]
fn ktx2_textures_load_as_binomial_s_transcoder_reads_them() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/ktx2");
    let sizes = |s: &SceneData| s.textures.iter().map(|t| (t.width, t.height)).collect::<Vec<_>>();
    let mut texels = Vec::new();
    for variant in ["etc1s_mipmaps", "uastc", "uastc_zstd"] {
        let ktx2 = SceneData::load(&root.join(variant).join("scene.gltf")).unwrap();
        let decoded = SceneData::load(&root.join(variant).join("decoded/scene.gltf")).unwrap();
        assert!(ktx2.warnings.is_empty(), "{variant}: {:?}", ktx2.warnings);
        assert_eq!(sizes(&ktx2), [(8, 8), (16, 4), (4, 1), (4, 4)], "{variant}");
        assert_eq!(ktx2.textures, decoded.textures, "{variant}");
        assert_eq!(ktx2.material_textures, decoded.material_textures, "{variant}");
        assert_eq!(ktx2.texels, decoded.texels, "{variant}");
        texels.push(ktx2.texels);
    }
    assert_ne!(texels[0], texels[1], "ETC1S and UASTC decode differently");

    // With a fallback `source` (the ETC1S twin's PNG, whose texels differ), the extension's
    // KTX2 image is read; a KTX2 image cut in its level data, its key/value data or its header
    // is refused in one line by its index.
    let dir = std::env::temp_dir().join(format!("smlt-ktx2-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for entry in std::fs::read_dir(root.join("uastc")).unwrap() {
        let path = entry.unwrap().path();
        if path.is_file() {
            std::fs::copy(&path, dir.join(path.file_name().unwrap())).unwrap();
        }
    }
    std::fs::copy(root.join("etc1s_mipmaps/decoded/baseColor_2.png"), dir.join("fallback.png")).unwrap();
    let mut doc: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("scene.gltf")).unwrap()).unwrap();
    doc.as_object_mut().unwrap().remove("extensionsRequired");
    let images = doc["images"].as_array_mut().unwrap();
    images.push(json!({"uri": "fallback.png"}));
    let fallback = images.len() - 1;
    for texture in doc["textures"].as_array_mut().unwrap() {
        texture["source"] = json!(fallback);
    }
    std::fs::write(dir.join("fallback.gltf"), doc.to_string()).unwrap();
    assert_eq!(SceneData::load(&dir.join("fallback.gltf")).unwrap().texels, texels[1]);
    let bytes = std::fs::read(dir.join("baseColor_2.ktx2")).unwrap();
    for (cut, said) in [(bytes.len() - 8, "does not decode"), (120, "key/value data"), (40, "cut short")] {
        std::fs::write(dir.join("baseColor_2.ktx2"), &bytes[..cut]).unwrap();
        let err = SceneData::load(&dir.join("scene.gltf")).unwrap_err().to_string();
        assert!(err.contains("images[1]") && err.contains(said) && !err.contains('\n'), "{err}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
