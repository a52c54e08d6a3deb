//! The shading normal smlt shades each pixel's first hit with (world space, normal textures
//! applied), at the pixel's centre, as an EXR whose rgb is the normal's xyz (0 where the ray
//! misses): what `scripts/peers/check_tangents.sh` holds against Cycles' Normal pass. Not a test:
//! a check against another renderer.
//!
//! ```sh
//! cargo run --release --example shading_normals -- SCENE.gltf --width 160 --height 120 \
//!     --out normals.exr [--triangle-frames]
//! ```
//!
//! `--triangle-frames` drops the scene's vertex tangents (its `TANGENT` or MikkTSpace's), so
//! that every normal texture is read in each triangle's own frame (dp/du, −dp/dv).

use std::path::PathBuf;

use shared::ray_caster::{RayCaster, NO_HIT};
use shared::surface::normals_at;
use smlt::scene::SceneData;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |flag: &str| args.iter().position(|a| a == flag).and_then(|i| args.get(i + 1)).cloned();
    let Some(path) = args.first().filter(|a| !a.starts_with("--")) else {
        anyhow::bail!(
            "usage: shading_normals SCENE.gltf --width W --height H --out OUT.exr [--triangle-frames]"
        );
    };
    let width: u32 = value("--width").map_or(Ok(160), |v| v.parse())?;
    let height: u32 = value("--height").map_or(Ok(120), |v| v.parse())?;
    let out = PathBuf::from(value("--out").unwrap_or_else(|| "normals.exr".into()));
    // A white sky, so that a scene without lights loads (the normals do not depend on it).
    let sky = shared::environment::EnvironmentMap::new(1, 1, &[[1.0; 3]], 0.0);
    let mut scene = SceneData::load_with_environment(std::path::Path::new(path), Some(sky))?;
    if args.iter().any(|a| a == "--triangle-frames") {
        scene.tangents = vec![Default::default()];
    }
    let camera = scene.camera(width, height);
    let shared_scene = scene.shared();
    let origin = camera.origin();
    let mut rgb = vec![0.0f32; (3 * width * height) as usize];
    for y in 0..height {
        for x in 0..width {
            let d = camera.direction(x as f32 + 0.5, y as f32 + 0.5);
            let hit = shared_scene.caster.closest_hit(origin, d, 0.0, NO_HIT, 0);
            if !hit.found() {
                continue;
            }
            // Turned to the camera's side, as a renderer's normal pass shows it.
            let n = normals_at(&shared_scene, hit.triangle, origin + d * hit.t).facing(-d).shading;
            let i = 3 * (y * width + x) as usize;
            rgb[i..i + 3].copy_from_slice(&n.to_array());
        }
    }
    smlt::output::write_images(&out, width, height, &rgb)?;
    println!("wrote {}", out.display());
    Ok(())
}
