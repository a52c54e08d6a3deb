//! Malformed input, at random: thousands of files made from the committed scenes by changing
//! one thing — a number replaced by 0, −1, an extreme or a huge count, a byte offset moved, a
//! member removed, bytes of the buffer flipped or the buffer cut, bytes of a `.glb` container
//! flipped or the container cut — each either renders (a tiny budget on the CPU backend) or is
//! refused with one line, and never panics or hangs (a watchdog aborts the run if one case
//! takes over 20 s). `SMLT_MALFORMED_CASES=N` runs N cases instead of the default.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

mod common;

use base64::Engine;
use common::rng::Xorshift;
use serde_json::Value;
use smlt::render::{self, cpu::CpuBackend, Budget, ChainSettings, Integrator, Settings};
use smlt::scene::SceneData;

/// A base document: its JSON and its one buffer's bytes.
struct Base {
    json: Value,
    bin: Vec<u8>,
}

impl Base {
    /// The document with `bin` as its buffer, as a .gltf with a data URI.
    fn gltf(json: &Value, bin: &[u8]) -> Vec<u8> {
        let mut j = json.clone();
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(bin)
        );
        if let Some(Value::Object(buffer)) = j.pointer_mut("/buffers/0") {
            buffer.insert("uri".into(), Value::String(uri));
        }
        serde_json::to_vec(&j).unwrap()
    }

    /// The document as a .glb container (JSON chunk, BIN chunk).
    fn glb(json: &Value, bin: &[u8]) -> Vec<u8> {
        let mut j = json.clone();
        if let Some(Value::Object(buffer)) = j.pointer_mut("/buffers/0") {
            buffer.remove("uri");
        }
        let mut text = serde_json::to_vec(&j).unwrap();
        while !text.len().is_multiple_of(4) {
            text.push(b' ');
        }
        let mut data = bin.to_vec();
        while !data.len().is_multiple_of(4) {
            data.push(0);
        }
        let total = 12 + 8 + text.len() + 8 + data.len();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(text.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&text);
        out.extend_from_slice(&(data.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&data);
        out
    }
}

/// The committed default scene (non-indexed), Blender's Draco export of the round-trip scene
/// (`tests/draco`: every primitive a Draco stream, its image inlined), the `textured` scene with
/// KTX2 textures (`tests/ktx2`: ETC1S with BasisLZ, one UASTC with Zstandard, in the buffer),
/// Blender's posed armature (`tests/skin/posed`: a skin's joints, weights and inverse bind
/// matrices) and the measured Cornell box (indexed, from `../shared/scenes`, which CI has).
fn bases() -> Vec<Base> {
    let mut out = Vec::new();
    let json: Value = serde_json::from_str(include_str!("../scenes/cornell.gltf")).unwrap();
    let uri = json["buffers"][0]["uri"].as_str().unwrap();
    let bin = base64::engine::general_purpose::STANDARD.decode(uri.split_once(',').unwrap().1).unwrap();
    out.push(Base { json, bin });
    let draco = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/draco/blender");
    let mut json: Value =
        serde_json::from_str(&std::fs::read_to_string(draco.join("round_trip.gltf")).unwrap()).unwrap();
    let png = std::fs::read(draco.join(json["images"][0]["uri"].as_str().unwrap())).unwrap();
    json["images"][0]["uri"] = Value::String(format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(png)
    ));
    let bin = std::fs::read(draco.join(json["buffers"][0]["uri"].as_str().unwrap())).unwrap();
    out.push(Base { json, bin });
    let ktx2 = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/ktx2");
    let mut json: Value =
        serde_json::from_str(&std::fs::read_to_string(ktx2.join("etc1s_mipmaps/scene.gltf")).unwrap())
            .unwrap();
    let mut bin = std::fs::read(ktx2.join("etc1s_mipmaps/scene.bin")).unwrap();
    for i in 0..json["images"].as_array().unwrap().len() {
        let file = json["images"][i]["uri"].as_str().unwrap().to_string();
        let variant = if i == 2 { "uastc_zstd" } else { "etc1s_mipmaps" };
        let bytes = std::fs::read(ktx2.join(variant).join(file)).unwrap();
        bin.resize(bin.len().next_multiple_of(4), 0);
        let views = json["bufferViews"].as_array_mut().unwrap();
        views.push(serde_json::json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()}));
        json["images"][i] = serde_json::json!({"bufferView": views.len() - 1, "mimeType": "image/ktx2"});
        bin.extend(bytes);
    }
    json["buffers"][0]["byteLength"] = serde_json::json!(bin.len());
    out.push(Base { json, bin });
    let skin = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/skin/posed");
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(skin.join("round_trip.gltf")).unwrap()).unwrap();
    let bin = std::fs::read(skin.join("round_trip.bin")).unwrap();
    out.push(Base { json, bin });
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/scenes/cornell_box");
    match (std::fs::read_to_string(dir.join("cornell_box.gltf")), std::fs::read(dir.join("cornell_box.bin")))
    {
        (Ok(text), Ok(bin)) => out.push(Base { json: serde_json::from_str(&text).unwrap(), bin }),
        _ => {
            assert_ne!(std::env::var("CI").as_deref(), Ok("true"), "CI=true and no {}", dir.display());
            eprintln!("SKIPPED the measured Cornell box: no {}", dir.display());
        }
    }
    out
}

/// JSON pointers of every number in `v`.
fn number_paths(v: &Value, at: String, out: &mut Vec<String>) {
    match v {
        Value::Number(_) => out.push(at),
        Value::Array(a) => a.iter().enumerate().for_each(|(i, x)| number_paths(x, format!("{at}/{i}"), out)),
        Value::Object(o) => o.iter().for_each(|(k, x)| number_paths(x, format!("{at}/{k}"), out)),
        _ => {}
    }
}

/// JSON pointers of every object member in `v`.
fn member_paths(v: &Value, at: String, out: &mut Vec<String>) {
    match v {
        Value::Array(a) => a.iter().enumerate().for_each(|(i, x)| member_paths(x, format!("{at}/{i}"), out)),
        Value::Object(o) => o.iter().for_each(|(k, x)| {
            out.push(format!("{at}/{k}"));
            member_paths(x, format!("{at}/{k}"), out)
        }),
        _ => {}
    }
}

/// One malformed file made from `base`, and what was changed.
fn mutate(base: &Base, rng: &mut Xorshift) -> (Vec<u8>, String) {
    let (mut json, mut bin) = (base.json.clone(), base.bin.clone());
    let glb = rng.below(4) == 0;
    let what = match rng.below(5) {
        0 | 1 => {
            let mut paths = Vec::new();
            number_paths(&json, String::new(), &mut paths);
            let path = &paths[rng.below(paths.len())];
            let values = [0.0, -1.0, 1.0, 2.0, 3.2, 0.5, 7.0, 1e9, 4294967295.0, 1e30, -1e30, 1e-30, 65536.0];
            let value = values[rng.below(values.len())];
            *json.pointer_mut(path).unwrap() = serde_json::json!(value);
            format!("{path} = {value}")
        }
        2 => {
            let mut paths = Vec::new();
            member_paths(&json, String::new(), &mut paths);
            let path = &paths[rng.below(paths.len())];
            let (parent, key) = path.rsplit_once('/').unwrap();
            if let Some(Value::Object(o)) =
                if parent.is_empty() { Some(&mut json) } else { json.pointer_mut(parent) }
            {
                o.remove(key);
            }
            format!("{path} removed")
        }
        3 => {
            let n = 1 + rng.below(8);
            for _ in 0..n {
                let i = rng.below(bin.len());
                bin[i] ^= 1 << rng.below(8);
            }
            format!("{n} buffer bytes flipped")
        }
        _ => {
            let len = rng.below(bin.len());
            bin.truncate(len);
            format!("buffer cut to {len} bytes")
        }
    };
    if glb {
        let mut bytes = Base::glb(&json, &bin);
        if rng.below(2) == 0 {
            let i = rng.below(bytes.len());
            bytes[i] = rng.next_u64() as u8;
            return (bytes, format!("{what}; .glb byte {i} changed"));
        }
        if rng.below(4) == 0 {
            let len = rng.below(bytes.len());
            bytes.truncate(len);
            return (bytes, format!("{what}; .glb cut to {len} bytes"));
        }
        return (bytes, format!("{what} (.glb)"));
    }
    (Base::gltf(&json, &bin), what)
}

/// Loads and renders `bytes`: Ok(true) rendered, Ok(false) refused (with its one-line reason
/// checked), Err(panic message) when anything panicked.
fn attempt(bytes: &[u8]) -> Result<Result<(), String>, String> {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let scene = SceneData::from_slice(bytes, "case").map_err(|e| e.to_string())?;
        let chains = ChainSettings { bootstrap_samples: 256, ..Default::default() };
        let s = Settings {
            width: 4,
            height: 3,
            max_depth: 3,
            integrator: Integrator::new("s2".parse().unwrap(), chains),
            budget: Budget::MutationsPerPixel(4.0),
            candidates: 48,
            ..Default::default()
        };
        let params = render::base_params(&scene, &s);
        let mut backend = CpuBackend::new(&scene, &params, 1).map_err(|e| e.to_string())?;
        let image = render::render(&scene, &s, &mut backend, |_: f64| {}).map_err(|e| e.to_string())?;
        assert_eq!(image.rgb.len(), 4 * 3 * 3);
        Ok(())
    }));
    outcome.map_err(|p| {
        p.downcast_ref::<String>()
            .cloned()
            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default()
    })
}

#[test]
fn malformed_files_render_or_are_refused_in_one_line() {
    let cases: u64 =
        std::env::var("SMLT_MALFORMED_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(20_000);
    let bases = bases();
    // The watchdog: no case may hang.
    static STARTED: AtomicU64 = AtomicU64::new(0);
    let epoch = Instant::now();
    std::thread::spawn(move || loop {
        std::thread::sleep(Duration::from_secs(1));
        let started = STARTED.load(Ordering::Relaxed);
        if started > 0 && epoch.elapsed().as_secs().saturating_sub(started) > 20 {
            eprintln!("a malformed case ran for over 20 s");
            std::process::abort();
        }
    });
    let mut rng = Xorshift(0x5DEE_CE66_D1CE_4E5B);
    let (mut rendered, mut refused) = (0u64, 0u64);
    let mut reasons: std::collections::BTreeMap<String, u64> = Default::default();
    let mut panics = Vec::new();
    for case in 0..cases {
        let base = &bases[case as usize % bases.len()];
        let (bytes, what) = mutate(base, &mut rng);
        STARTED.store(epoch.elapsed().as_secs().max(1), Ordering::Relaxed);
        match attempt(&bytes) {
            Ok(Ok(())) => rendered += 1,
            Ok(Err(reason)) => {
                assert!(!reason.contains('\n') && !reason.is_empty(), "case {case} ({what}): {reason:?}");
                refused += 1;
                let kind: String = reason.split(':').take(2).collect::<Vec<_>>().join(":");
                *reasons.entry(kind.chars().take(60).collect()).or_default() += 1;
            }
            Err(panic) => panics.push(format!("case {case} ({what}): {panic}")),
        }
        STARTED.store(0, Ordering::Relaxed);
    }
    println!(
        "{cases} cases in {:.1} s: {rendered} rendered, {refused} refused",
        epoch.elapsed().as_secs_f64()
    );
    let mut common: Vec<_> = reasons.into_iter().collect();
    common.sort_by_key(|c| std::cmp::Reverse(c.1));
    for (reason, n) in common.iter().take(12) {
        println!("  {n:>5}  {reason}");
    }
    assert!(panics.is_empty(), "{} panics, first: {}", panics.len(), panics[0]);
    assert!(rendered > cases / 10 && refused > cases / 10, "the mutations should both render and be refused");
}
