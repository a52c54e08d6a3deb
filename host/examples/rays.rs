//! Ray-casting throughput of each ray caster on one scene, one thread, the same rays: the
//! device's wide-BVH traversal (the shared body, run on the host), the CPU backend's caster
//! (obvhs's traversal with smlt's triangle test), and obvhs's own traversal with its own
//! triangle test (the library's ceiling the CPU backend is held against); plus the BVH's build
//! time and memory. Not a test: a measurement for the README and the issue notes.
//!
//! ```sh
//! cargo run --release --example rays -- atrium --tessellation 92   # 1.0 M triangles
//! cargo run --release --example rays -- ../shared/scenes/sibenik/sibenik.gltf
//! ```

use std::time::Instant;

use glam::{Vec3, Vec3A};
use shared::ray_caster::{Hit, RayCaster, NO_HIT};
use smlt::scene::SceneData;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().cloned().unwrap_or_else(|| "cornell".into());
    let tessellation: u32 = match args.iter().position(|a| a == "--tessellation") {
        Some(i) => args.get(i + 1).map_or(Ok(1), |v| v.parse())?,
        None => 1,
    };
    let rays: usize = match args.iter().position(|a| a == "--rays") {
        Some(i) => args.get(i + 1).map_or(Ok(1_000_000), |v| v.parse())?,
        None => 1_000_000,
    };
    let start = Instant::now();
    let json = smlt::scenes::generate(&name, tessellation);
    let parse_start = Instant::now();
    let scene = match &json {
        Some(json) => SceneData::from_slice(json.as_bytes(), &name)?,
        None => SceneData::load(std::path::Path::new(&name))?,
    };
    let load = parse_start.elapsed().as_secs_f64();
    let generated = parse_start.duration_since(start).as_secs_f64();
    // The BVH alone, built again from the loaded triangles as the loader builds it.
    let tris: Vec<obvhs::triangle::Triangle> = scene
        .triangles
        .iter()
        .map(|t| obvhs::triangle::Triangle { v0: t.v0.into(), v1: t.v1.into(), v2: t.v2.into() })
        .collect();
    let build_start = Instant::now();
    let bvh = obvhs::cwbvh::builder::build_cwbvh_from_tris(
        &tris,
        obvhs::BvhBuildParams::medium_build(),
        &mut std::time::Duration::default(),
    );
    let build = build_start.elapsed().as_secs_f64();
    let mib = |bytes: usize| bytes as f64 / 1048576.0;
    println!(
        "{name}: {} triangles; generated in {generated:.2} s, loaded (glTF + BVH + lights) in {load:.2} s; \
         BVH build {build:.2} s; BVH nodes {:.1} MiB, triangles {:.1} MiB",
        scene.triangles.len(),
        mib(std::mem::size_of_val(scene.wide_nodes())),
        mib(std::mem::size_of_val(&scene.triangles[..]))
    );
    // Random points of random triangles, uniform directions.
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let tmin = 1e-4 * (scene.bounds.1 - scene.bounds.0).length();
    let queries: Vec<(Vec3, Vec3)> = (0..rays)
        .map(|_| {
            let tri =
                scene.triangles[(next() * scene.triangles.len() as f32) as usize % scene.triangles.len()];
            let (a, b) = (next(), next());
            let (b0, b1) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
            let z = 1.0 - 2.0 * next();
            let phi = std::f32::consts::TAU * next();
            let r = (1.0 - z * z).max(0.0).sqrt();
            (tri.point(b0, b1), Vec3::new(r * phi.cos(), r * phi.sin(), z))
        })
        .collect();
    let time = |label: &str, cast: &dyn Fn(Vec3, Vec3) -> bool| {
        let start = Instant::now();
        let hits = queries.iter().filter(|(o, d)| cast(*o, *d)).count();
        let seconds = start.elapsed().as_secs_f64();
        println!("  {label:<44} {:>7.2} M rays/s ({hits} hits)", rays as f64 / seconds / 1e6);
    };
    let wide = scene.device_view().caster;
    let build = Instant::now();
    let host = scene.shared().caster;
    println!("  CPU backend caster: {} (built in {:.2} s)", host.describe(), build.elapsed().as_secs_f64());
    let obvhs = scene.obvhs_view().caster;
    time("shared wide BVH (the kernels' traversal)", &|o, d| wide.closest_hit(o, d, tmin, NO_HIT, 0).found());
    time("obvhs traversal, smlt's triangle test", &|o, d| obvhs.closest_hit(o, d, tmin, NO_HIT, 0).found());
    time("CPU backend caster", &|o, d| host.closest_hit(o, d, tmin, NO_HIT, 0).found());
    let rt: Vec<obvhs::rt_triangle::RtTriangle> = bvh
        .primitive_indices
        .iter()
        .map(|&i| obvhs::rt_triangle::RtTriangle::from(&tris[i as usize]))
        .collect();
    time("obvhs ray_traverse + RtTriangle (library)", &|o, d| {
        let ray = obvhs::ray::Ray::new(Vec3A::from(o), Vec3A::from(d), tmin, f32::INFINITY);
        let mut hit = obvhs::ray::RayHit::none();
        bvh.ray_traverse(ray, &mut hit, |r, id| rt[id].intersect(r))
    });
    // Embree's packet traversal over the same rays, sixteen at a time, and how many of its hits
    // are the single rays' (not timed).
    if let smlt::caster::HostCaster::Embree(embree) = host {
        use smlt::caster::{Query, PACKET};
        let query =
            |(o, d): (Vec3, Vec3), tmin: f32| Query { origin: o, direction: d, tmin, tmax: NO_HIT, key: 0 };
        let batch: Vec<Query> = queries.iter().map(|&r| query(r, tmin)).collect();
        let mut found = vec![Hit::NONE; batch.len()];
        let start = Instant::now();
        embree.closest_hits(&batch, &mut found);
        let seconds = start.elapsed().as_secs_f64();
        let hits = found.iter().filter(|h| h.found()).count();
        let same = found
            .iter()
            .zip(&batch)
            .filter(|(h, q)| **h == host.closest_hit(q.origin, q.direction, tmin, NO_HIT, 0))
            .count();
        let label = "Embree packets of 16 (rtcIntersect16)";
        println!(
            "  {label:<44} {:>7.2} M rays/s ({hits} hits; {same} of {} as single rays)",
            batch.len() as f64 / seconds / 1e6,
            batch.len()
        );
        // Camera rays, coherent: the first view at 1024×576, a 4×4 tile of pixels a packet.
        let (w, h) = (1024u32, 576u32);
        let camera = scene.camera(w, h);
        let tiles: Vec<Query> = (0..h / 4)
            .flat_map(|ty| (0..w / 4).map(move |tx| (tx, ty)))
            .flat_map(|(tx, ty)| {
                (0..PACKET as u32).map(move |i| {
                    let (x, y) = (4 * tx + i % 4, 4 * ty + i / 4);
                    query((camera.origin(), camera.direction(x as f32 + 0.5, y as f32 + 0.5)), 0.0)
                })
            })
            .collect();
        let n = tiles.len();
        let start = Instant::now();
        let single =
            tiles.iter().filter(|q| host.closest_hit(q.origin, q.direction, 0.0, NO_HIT, 0).found()).count();
        let single_rate = n as f64 / start.elapsed().as_secs_f64() / 1e6;
        let mut found = vec![Hit::NONE; n];
        let start = Instant::now();
        embree.closest_hits(&tiles, &mut found);
        let packed_rate = n as f64 / start.elapsed().as_secs_f64() / 1e6;
        let packed = found.iter().filter(|h| h.found()).count();
        println!("  {:<44} {single_rate:>7.2} M rays/s ({single} hits)", "camera rays, one at a time");
        println!("  {:<44} {packed_rate:>7.2} M rays/s ({packed} hits)", "camera rays, 4×4 tiles of 16")
    }
    time("shared wide BVH, occlusion to t = 1", &|o, d| wide.occluded(o, d, tmin, 1.0, 0));
    time("obvhs traversal, occlusion to t = 1", &|o, d| obvhs.occluded(o, d, tmin, 1.0, 0));
    time("CPU backend caster, occlusion to t = 1", &|o, d| host.occluded(o, d, tmin, 1.0, 0));
    Ok(())
}
