//! The CPU backend's path tracer runs as a wavefront (`smlt::passes::path_tracer::round_batch`):
//! a bounce's rays of many paths cast together, through Embree's 16-wide packets where it is
//! installed. Its image is the per-pixel body's (`shared::path_tracer::pixel_round`, the
//! device's) bit for bit, through either CPU caster: on the default scene, on glass under a spot
//! lamp, on glTF's BRDF with textures, on cut-outs (which Embree casts one ray at a time) and
//! under an environment seen through glass. Embree's packet and single-ray traversals answer
//! these queries alike (`tests/ray_casters.rs` checks batches query by query).

mod common;

use shared::path_tracer::pixel_round;
use smlt::passes::path_tracer::{cpu, BATCH};
use smlt::render;
use smlt::scene::SceneData;

fn generated(name: &str) -> SceneData {
    let json = smlt::scenes::generate(name, 1).expect("a generated scene");
    SceneData::from_slice(json.as_bytes(), name).expect("the generated scene loads")
}

/// A round of 3 samples a pixel at 45×31 (not a multiple of the batch, so the last batch is
/// short), through the wavefront and pixel by pixel, through each caster; returns how many
/// pixels saw light.
fn same_image(scene: &SceneData, label: &str) -> usize {
    let (width, height) = (45, 31);
    assert!(!((width * height) as usize).is_multiple_of(BATCH));
    let params = render::path_tracer_params(scene, (width, height), 8, 11, 3);
    let mut lit = 0;
    // Embree's packets are what this checks; CI installs Embree (scripts/setup.sh).
    if let Some(why) = smlt::caster::embree_unavailable() {
        assert_ne!(std::env::var("CI").as_deref(), Ok("true"), "CI=true and no Embree: {why}");
        eprintln!("SKIPPED Embree's packets (obvhs twice): {why}");
    }
    for (caster, view) in [("the CPU backend's caster", scene.shared()), ("obvhs", scene.obvhs_view())] {
        let mut wavefront = vec![0.0f32; (width * height * 3) as usize];
        cpu(&params, view, &mut wavefront);
        let per_pixel: Vec<f32> =
            (0..width * height).flat_map(|p| pixel_round(&params, view, p).to_array()).collect();
        let differ = wavefront.iter().zip(&per_pixel).filter(|(a, b)| a.to_bits() != b.to_bits()).count();
        assert_eq!(differ, 0, "{label} through {caster}: {differ} of {} values differ", per_pixel.len());
        lit = per_pixel.chunks(3).filter(|p| p.iter().sum::<f32>() > 0.0).count();
        println!("{label} through {} ({caster}): {lit} lit pixels, the same bits", view.caster.describe());
    }
    lit
}

#[test]
fn the_wavefront_renders_the_per_pixel_image() {
    let cornell = SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell").unwrap();
    let pixels = 45 * 31;
    for (scene, label) in [
        (cornell, "cornell"),
        (generated("caustic"), "caustic"),
        (generated("textured"), "textured"),
        (generated("cutout"), "cutout"),
        (common::scenes::sky_scene(), "sky scene"),
    ] {
        let lit = same_image(&scene, label);
        assert!(lit > pixels / 2, "{label}: {lit} of {pixels} pixels lit");
    }
}
