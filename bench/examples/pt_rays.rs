//! The rays of `pt`'s one sample through pixels spread over a view (the bench's ceiling log,
//! `smlt_bench::raycast::log_paths`), written as little-endian f32 records of nine values —
//! origin (3), tmin, direction (3), tmax, kind (1 closest hit, 2 occlusion) — path after path,
//! so that another ray tracer can cast exactly them (`scripts/peers/mitsuba_rays.py`); and, on
//! one thread, the closest-hit rays/s of the CPU backend's Embree over them one at a time and in
//! packets of 16 (each packet the same bounce of 16 paths, as the wavefront casts them). Not a
//! test: a measurement for docs/results.md.
//!
//! ```sh
//! cargo run --release -p smlt-bench --example pt_rays -- SCENE.gltf VIEW OUT.f32 [WIDTH HEIGHT]
//! ```

use std::path::Path;

use shared::rays::RAY_NONE;
use smlt::scene::SceneData;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [scene, view, out, ..] = args.as_slice() else {
        anyhow::bail!("usage: pt_rays SCENE.gltf VIEW OUT.f32 [WIDTH HEIGHT]");
    };
    let width: u32 = args.get(3).map_or(Ok(128), |w| w.parse())?;
    let height: u32 = args.get(4).map_or(Ok(72), |h| h.parse())?;
    let mut scene = SceneData::load(Path::new(scene))?;
    scene.select_view(view.parse()?)?;
    let params = smlt::render::path_tracer_params(&scene, (width, height), 10, 1, 1);
    let mut records: Vec<u8> = Vec::new();
    let (mut closest, mut occlusion, mut paths) = (0u64, 0u64, 0u64);
    for log in smlt_bench::raycast::log_paths(&scene, &params, 1) {
        let c = log.candidates as usize;
        for k in 0..c {
            paths += 1;
            for ray in log.rays.iter().skip(k).step_by(c).take_while(|r| r.kind != RAY_NONE) {
                let values =
                    [ray.origin.as_slice(), &[ray.tmin], &ray.direction, &[ray.tmax, ray.kind as f32]];
                records.extend(values.concat().iter().flat_map(|v| v.to_le_bytes()));
                closest += (ray.kind == shared::rays::RAY_CLOSEST) as u64;
                occlusion += (ray.kind == shared::rays::RAY_OCCLUSION) as u64;
            }
        }
    }
    std::fs::write(out, records)?;
    println!("{paths} paths: {closest} closest-hit and {occlusion} occlusion rays to {out}");
    let caster = scene.shared().caster;
    if let smlt::caster::HostCaster::Embree(embree) = caster {
        use shared::ray_caster::{Hit, RayCaster};
        // Bounce by bounce over the paths: ray j of every path, then ray j + 1.
        let mut queries = Vec::new();
        for log in smlt_bench::raycast::log_paths(&scene, &params, 1) {
            for ray in log.rays.iter().filter(|r| r.kind == shared::rays::RAY_CLOSEST) {
                queries.push(smlt::caster::Query {
                    origin: glam::Vec3::from_array(ray.origin),
                    direction: glam::Vec3::from_array(ray.direction),
                    tmin: ray.tmin,
                    tmax: ray.tmax,
                    key: ray.key,
                });
            }
        }
        let mut hits = vec![Hit::NONE; queries.len()];
        for _ in 0..3 {
            let start = std::time::Instant::now();
            for (q, h) in queries.iter().zip(hits.iter_mut()) {
                *h = caster.closest_hit(q.origin, q.direction, q.tmin, q.tmax, q.key);
            }
            let single = queries.len() as f64 / start.elapsed().as_secs_f64() / 1e6;
            let start = std::time::Instant::now();
            embree.closest_hits(&queries, &mut hits);
            let packets = queries.len() as f64 / start.elapsed().as_secs_f64() / 1e6;
            println!("one thread, Embree: {single:.2} M closest-hit rays/s one at a time, {packets:.2} in packets of 16");
        }
    }
    Ok(())
}
