//! Every ray caster answers every query the same way, ray by ray, on every real scene in
//! `../shared/scenes/` and every generated stand-in: the device's wide-BVH traversal (the
//! shared body run on the host), obvhs's traversal of the same BVH, Embree (the CPU backend's
//! caster where it is installed), and the `raycast` kernel on the Vulkan device. 10^5 closest-hit and 10^5 occlusion
//! queries a scene, from points on the scene's own triangles (as path vertices are) in uniform
//! directions, a seventh of them axis-parallel. The `cutout` scene's MASK and BLEND triangles
//! let rays through in each caster alike; `cut_outs_let_rays_through` checks where.
//!
//! The shared traversal and obvhs's run the same triangle test over the same BVH, so they must
//! agree exactly: the same t, the same triangle but for ties (two triangles hit at the same t:
//! a ray through a shared edge), which are counted and bounded. Embree (the CPU backend's
//! caster where it is installed, as in CI) and the device compute in their own floating point,
//! so t may differ in the last bits (within 1e-5 relative counts as the same) and a ray grazing
//! an edge may hit the neighbouring triangle or slip through; those are counted and bounded.

mod common;

use std::path::Path;

use common::rng::Xorshift;
use glam::{Vec2, Vec3};
use shared::cutout::blend_key;
use shared::params::RenderParams;
use shared::ray_caster::{Hit, RayCaster, NO_HIT};
use shared::rays::{cast, Ray, RAY_CLOSEST, RAY_OCCLUSION};
use smlt::passes;
use smlt::scene::SceneData;

/// Queries of each kind per scene.
const QUERIES: usize = 100_000;

/// The queries: closest-hit rays from random points of random triangles (tmin a ten-thousandth
/// of the scene's diagonal, past the origin's own triangle), then one occlusion ray along each
/// with an interval ending before, at or after the closest hit.
fn queries(scene: &SceneData, seed: u64) -> Vec<Ray> {
    let mut u = Xorshift(seed);
    let diagonal = (scene.bounds.1 - scene.bounds.0).length();
    let tmin = 1e-4 * diagonal;
    let caster = scene.shared().caster;
    let mut rays = Vec::with_capacity(2 * QUERIES);
    let mut occlusion = Vec::with_capacity(QUERIES);
    let (lo, hi) = scene.bounds;
    while rays.len() < QUERIES {
        let tri =
            scene.triangles[(u.uniform() * scene.triangles.len() as f32) as usize % scene.triangles.len()];
        let (a, b) = (u.uniform(), u.uniform());
        let (b0, b1) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
        let mut o = tri.point(b0, b1);
        let z = 1.0 - 2.0 * u.uniform();
        let phi = std::f32::consts::TAU * u.uniform();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let mut d = Vec3::new(r * phi.cos(), r * phi.sin(), z);
        if rays.len() % 7 == 0 {
            // Axis-parallel: one or two zero components, of both signs, from a point inside the
            // scene's box (from a point on an axis-aligned wall such a ray would run inside the
            // wall's plane, where hitting a neighbour's edge is a matter of rounding).
            o = lo + (hi - lo) * Vec3::new(u.uniform(), u.uniform(), u.uniform());
            d.x = if rays.len() % 2 == 0 { 0.0 } else { -0.0 };
            if rays.len() % 3 == 0 {
                d.y = if rays.len() % 4 == 0 { 0.0 } else { -0.0 };
            }
        }
        if d.length() < 1e-3 {
            continue;
        }
        let d = d.normalize();
        // Each query its own key for its BLEND draws (the occlusion ray along it another).
        let key = (rays.len() as u32).wrapping_mul(0x9e37_79b9);
        rays.push(Ray::new(RAY_CLOSEST, o, d, tmin, NO_HIT, key));
        let hit = caster.closest_hit(o, d, tmin, NO_HIT, key);
        let reach = if hit.found() { hit.t } else { diagonal };
        let tmax = reach * [0.5, 0.999, 1.001, 2.0][rays.len() % 4];
        occlusion.push(Ray::new(RAY_OCCLUSION, o, d, tmin, tmax, !key));
    }
    rays.extend(occlusion);
    rays
}

/// What one caster answered for one query.
fn answer<R: RayCaster>(caster: &R, ray: &Ray) -> Hit {
    let (o, d) = (Vec3::from_array(ray.origin), Vec3::from_array(ray.direction));
    if ray.kind == RAY_CLOSEST {
        caster.closest_hit(o, d, ray.tmin, ray.tmax, ray.key)
    } else {
        let blocked = caster.occluded(o, d, ray.tmin, ray.tmax, ray.key);
        Hit { t: if blocked { 0.0 } else { NO_HIT }, triangle: 0 }
    }
}

/// How two casters' answers to the same queries compare.
#[derive(Debug, Default)]
struct Agreement {
    hits: usize,
    /// The same t, different triangles: a ray through a shared edge, or onto two coincident
    /// faces (a box standing on a floor).
    ties: usize,
    /// Different answers: one hit and one miss, or different t.
    differ: usize,
}

/// Compares answers; t counts as the same within 1e-5 relative, or within 10^-7 of the
/// scene's `diagonal` (a hit a few millimetres from the origin, where one ulp of the origin's
/// coordinates is most of 1e-5 of t).
fn compare(a: &[Hit], b: &[Hit], rays: &[Ray], diagonal: f32) -> Agreement {
    let mut out = Agreement::default();
    for ((x, y), ray) in a.iter().zip(b).zip(rays) {
        out.hits += x.found() as usize;
        let tolerance = 1e-5 * x.t.abs().max(y.t.abs()).max(0.01 * diagonal);
        if x.found() != y.found() || (x.found() && (x.t - y.t).abs() > tolerance) {
            if out.differ < 5 {
                println!("  differ: {ray:?}: {x:?} vs {y:?}");
            }
            out.differ += 1;
        } else if ray.kind == RAY_CLOSEST && x.found() && x.triangle != y.triangle {
            out.ties += 1;
        }
    }
    out
}

/// The scenes: every generated stand-in and the real scenes (which CI must have).
fn scenes() -> Vec<SceneData> {
    let mut scenes: Vec<SceneData> = ["cornell", "atrium", "nave", "sunblind", "slit", "cutout"]
        .iter()
        .map(|name| {
            let json = smlt::scenes::generate(name, 1).expect("a generated scene");
            SceneData::from_slice(json.as_bytes(), name).expect("the scene loads")
        })
        .collect();
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes");
    for file in
        ["sibenik/sibenik.gltf", "sponza_dabrovic/sponza_dabrovic.gltf", "cornell_box/cornell_box.gltf"]
    {
        let path = shared.join(file);
        if path.exists() {
            scenes.push(SceneData::load(&path).expect("the real scene loads"));
        } else {
            assert_ne!(std::env::var("CI").as_deref(), Ok("true"), "CI=true and no {}", path.display());
            eprintln!("SKIPPED {}: not there", path.display());
        }
    }
    scenes
}

#[test]
fn every_caster_answers_every_query_alike() {
    let gpu = common::gpu_or_skip("every_caster_answers_every_query_alike");
    for (i, scene) in scenes().iter().enumerate() {
        let rays = queries(scene, 0x9E37_79B9 + i as u64);
        let wide = scene.device_view().caster;
        let obvhs = scene.obvhs_view().caster;
        let host = scene.shared().caster;
        let shared_answers: Vec<Hit> = rays.iter().map(|r| answer(&wide, r)).collect();
        let obvhs_answers: Vec<Hit> = rays.iter().map(|r| answer(&obvhs, r)).collect();
        let diagonal = (scene.bounds.1 - scene.bounds.0).length();
        let exact = compare(&shared_answers, &obvhs_answers, &rays, diagonal);
        println!(
            "{}: {} triangles, {} queries, {} hit/blocked; shared vs obvhs: {} ties, {} differ",
            scene.name,
            scene.triangles.len(),
            rays.len(),
            exact.hits,
            exact.ties,
            exact.differ
        );
        // The same triangle test over the same BVH: the same answers.
        assert_eq!(exact.differ, 0, "{}: the shared and obvhs traversals disagree", scene.name);
        assert!(exact.ties * 1000 <= rays.len(), "{}: {} ties", scene.name, exact.ties);
        assert!(exact.hits * 4 > rays.len(), "{}: the queries should mostly hit", scene.name);
        // A batch (the path tracer's wavefront; Embree's packets of 16) answers each query as
        // the caster does alone, through either CPU caster.
        for caster in [host, obvhs] {
            let (closest, occlusion): (Vec<&Ray>, Vec<&Ray>) =
                rays.iter().partition(|r| r.kind == RAY_CLOSEST);
            let query = |r: &&Ray| smlt::caster::Query {
                origin: Vec3::from_array(r.origin),
                direction: Vec3::from_array(r.direction),
                tmin: r.tmin,
                tmax: r.tmax,
                key: r.key,
            };
            let mut hits = vec![Hit::NONE; closest.len()];
            caster.closest_hits(&closest.iter().map(query).collect::<Vec<_>>(), &mut hits);
            assert!(
                hits.iter().zip(&closest).all(|(h, r)| *h == answer(&caster, r)),
                "{}",
                caster.describe()
            );
            let mut blocked = vec![false; occlusion.len()];
            caster.occluded_all(&occlusion.iter().map(query).collect::<Vec<_>>(), &mut blocked);
            assert!(
                blocked.iter().zip(&occlusion).all(|(b, r)| *b == (answer(&caster, r).t == 0.0)),
                "{}",
                caster.describe()
            );
        }
        if let smlt::caster::HostCaster::Embree(_) = host {
            let embree_answers: Vec<Hit> = rays.iter().map(|r| answer(&host, r)).collect();
            let e = compare(&shared_answers, &embree_answers, &rays, diagonal);
            println!("{}: shared vs Embree: {} ties, {} differ", scene.name, e.ties, e.differ);
            // Embree's own triangle test: a ray through an edge may take the neighbour or slip
            // through, and of two coincident faces it may report the other.
            assert!(e.differ * 2000 <= rays.len(), "{}: {} Embree answers differ", scene.name, e.differ);
            assert!(e.ties * 100 <= rays.len(), "{}: {} Embree ties", scene.name, e.ties);
        } else {
            assert_ne!(
                std::env::var("CI").as_deref(),
                Ok("true"),
                "CI=true and no Embree: {:?}",
                smlt::caster::embree_unavailable()
            );
            eprintln!("SKIPPED the Embree comparison: {:?}", smlt::caster::embree_unavailable());
        }
        let Some(gpu) = &gpu else { continue };
        // One query per invocation: the kernel's answer word is the query's own.
        let params = RenderParams { candidates: rays.len() as u32, ..Default::default() };
        let replayed =
            smlt_bench::raycast::replay_rays(gpu, scene, &rays, params.candidates).expect("device replay");
        let mut expected = vec![0u32; rays.len()];
        passes::raycast::cpu(&params, scene.obvhs_view(), &rays, &mut expected);
        assert_eq!(expected, rays.iter().map(|r| cast(&obvhs, r)).collect::<Vec<_>>());
        let (mut differ, mut ties) = (0, 0);
        for (k, (&dev, &cpu)) in replayed.iter().zip(&expected).enumerate() {
            if dev != cpu {
                // A different triangle at the same distance is a tie; anything else differs.
                let tie = rays[k].kind == RAY_CLOSEST && dev > 0 && cpu > 0 && {
                    let (o, d) = (Vec3::from_array(rays[k].origin), Vec3::from_array(rays[k].direction));
                    let t = |slot: u32| {
                        shared::triangle::intersect_triangle(
                            &scene.triangles[slot as usize - 1],
                            o,
                            d,
                            0.0,
                            NO_HIT,
                        )
                    };
                    (t(dev) - t(cpu)).abs() <= 1e-5 * t(cpu).abs()
                };
                if tie {
                    ties += 1;
                } else {
                    differ += 1;
                }
            }
        }
        println!("{}: device vs obvhs: {ties} ties, {differ} differ", scene.name);
        assert!(differ * 2000 <= rays.len(), "{}: {differ} device answers differ", scene.name);
        assert!(ties * 1000 <= rays.len(), "{}: {ties} device ties", scene.name);
    }
}

/// Every host caster lets rays through the `cutout` scene's cut-outs where glTF says: straight
/// down through the perforated screen (MASK), a ray at a hole's centre reaches the floor and one
/// at a solid texel's centre stops on the screen; across the fading pane (BLEND), the share of
/// rays it stops at each of its ramp's texel centres is its opacity, 0.8 × (1, 2/3, 1/3, 0),
/// within four binomial standard deviations; and every occlusion query answers as the
/// closest-hit query along the same ray.
#[test]
fn cut_outs_let_rays_through() {
    let json = smlt::scenes::generate("cutout", 1).expect("the cutout scene");
    let scene = SceneData::from_slice(json.as_bytes(), "cutout").expect("the scene loads");
    let material = |name: &str| {
        let doc: serde_json::Value = serde_json::from_str(&json).unwrap();
        // Material 0 is glTF's default material; the document's follow.
        1 + doc["materials"].as_array().unwrap().iter().position(|m| m["name"] == name).unwrap() as u32
    };
    let (screen, pane) = (material("perforated screen"), material("fading pane"));
    let wide = scene.device_view().caster;
    let obvhs = scene.obvhs_view().caster;
    let host = scene.shared().caster;
    // A query and the occlusion query along it (to 1.0), with one key.
    type Cast<'a> = &'a dyn Fn(Vec3, Vec3, f32, f32, u32) -> (Hit, bool);
    let casters: [(&str, Cast); 3] = [
        ("shared", &|o, d, t0, t1, k| (wide.closest_hit(o, d, t0, t1, k), wide.occluded(o, d, t0, 1.0, k))),
        ("obvhs", &|o, d, t0, t1, k| (obvhs.closest_hit(o, d, t0, t1, k), obvhs.occluded(o, d, t0, 1.0, k))),
        ("host", &|o, d, t0, t1, k| (host.closest_hit(o, d, t0, t1, k), host.occluded(o, d, t0, 1.0, k))),
    ];
    for (name, cast) in casters {
        // The screen at y = 1.9: u = 2x, v = 2z, two texels a period, holes where the texel
        // indices' sum is even. Rays from y = 2.2, 0.3 above it, straight down.
        let mut holes = 0;
        for i in 0..8 {
            for j in 0..8 {
                let (tu, tv) = (0.25 + 0.5 * (i % 2) as f32, 0.25 + 0.5 * (j % 2) as f32);
                let (x, z) = ((-2.0 + (i / 2) as f32 + tu) / 2.0, (-3.0 + (j / 2) as f32 + tv) / 2.0);
                let hole = (i % 2 + j % 2) % 2 == 0;
                let (hit, blocked) = cast(Vec3::new(x, 2.2, z), Vec3::NEG_Y, 1e-4, NO_HIT, 0);
                assert!(hit.found(), "{name}: ({x}, {z}) hits nothing");
                let on_screen = (hit.t - 0.3).abs() < 1e-4;
                assert_eq!(on_screen, !hole, "{name}: ({x}, {z}): {hit:?}, hole {hole}");
                assert_eq!(
                    scene.triangles[hit.triangle as usize].material == screen,
                    !hole,
                    "{name}: ({x}, {z})"
                );
                assert_eq!(blocked, hit.t < 1.0, "{name}: occlusion at ({x}, {z})");
                holes += hole as u32;
            }
        }
        assert_eq!(holes, 32);
        // The pane at x = 0.8: u = z / 1.6 + 0.75; rays along +x from x = 0, at heights in
        // [0.7, 1.5] (clear of the block and the screen).
        for (k, ramp) in [1.0, 2.0 / 3.0, 1.0 / 3.0, 0.0].into_iter().enumerate() {
            let z = (0.125 + 0.25 * k as f32 - 0.75) * 1.6;
            let n = 20_000;
            let mut stopped = 0;
            for r in 0..n {
                let o = Vec3::new(0.0, 0.7 + 0.8 * (r as f32 + 0.5) / n as f32, z);
                let key = blend_key(Vec2::new(r as f32 / n as f32, ramp as f32));
                let (hit, blocked) = cast(o, Vec3::X, 1e-4, NO_HIT, key);
                let on_pane = hit.found() && (hit.t - 0.8).abs() < 1e-4;
                assert_eq!(on_pane, hit.found() && scene.triangles[hit.triangle as usize].material == pane);
                assert_eq!(blocked, hit.t < 1.0, "{name}: occlusion at {o}");
                stopped += on_pane as u32;
            }
            let p = 0.8 * ramp;
            let share = stopped as f64 / n as f64;
            let sigma = (p * (1.0 - p) / n as f64).sqrt();
            println!("{name}: pane at ramp {ramp:.3}: stopped {share:.4}, opacity {p:.4}");
            assert!((share - p).abs() <= 4.0 * sigma + 1e-12, "{name}: pane stopped {share}, opacity {p}");
        }
    }
}
