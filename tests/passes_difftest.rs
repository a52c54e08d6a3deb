//! Difftests of every render pass: the device and the CPU run the same kernel body on the same
//! inputs (the CPU's outputs of the previous pass are uploaded to the device), and their
//! outputs must agree — exactly for integers, within a few ulps for floats. A candidate whose
//! ray grazes an edge may take a different branch after a 1-ulp difference; at most 0.5 % of
//! candidates may differ that way, and the test reports how many did.

mod common;

use glam::Vec4;
use shared::layout::{soa_index, unpack_contribution};
use shared::mmlt::{ChainState, PathInfo, PathVertex};
use shared::params::{RenderParams, MODE_BOOTSTRAP};
use shared::{reject_chain, tree};
use smlt::caster::HostCaster;
use smlt::gpu::Gpu;
use smlt::passes;
use smlt::passes::buffers::{GpuBuffers, OnDevice};
use smlt::passes::Stage;
use smlt::render::{
    self, cpu::CpuBuffers, gpu, Backend, Budget, ChainSettings, Integrator, Method, Schedule, Settings,
};
use smlt::scene::SceneData;

fn close(a: f32, b: f32, rel: f32) -> bool {
    a == b || (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-6) || (a.is_nan() && b.is_nan())
}

fn close4(a: Vec4, b: Vec4, rel: f32) -> bool {
    (0..4).all(|i| close(a[i], b[i], rel))
}

fn vertex_close(a: &PathVertex, b: &PathVertex) -> bool {
    a.kind == b.kind
        && a.material == b.material
        && a.triangle == b.triangle
        // Positions to 1e-4 of the scene's size (2 units): after several bounces the device's
        // fused multiply-adds and transcendental approximations move points by ~1e-5.
        && (0..3).all(|i| {
            (a.p[i] - b.p[i]).abs() <= 2e-4 && (a.n[i] - b.n[i]).abs() <= 1e-4 && close(a.beta[i], b.beta[i], 1e-3)
        })
        && close(a.pdf_fwd, b.pdf_fwd, 1e-3)
        && close(a.pdf_rev, b.pdf_rev, 1e-3)
}

fn upload<T: bytemuck::Pod>(gpu: &Gpu, buffer: &wgpu::Buffer, data: &[T]) {
    gpu.queue.write_buffer(buffer, 0, bytemuck::cast_slice(data));
}

/// The weight of every distinct state from the shared math, for targets `c` (root first).
fn expected_weights(method: Schedule, c: &[f32]) -> Vec<f32> {
    match method {
        Schedule::Tree(d) => {
            let mut cc = [0.0; tree::MAX_TREE_STATES];
            cc[..c.len()].copy_from_slice(c);
            let (mut a, mut l, mut w) = (
                [0.0; tree::MAX_TREE_CANDIDATES],
                [0.0; tree::MAX_TREE_LEAVES],
                [0.0; tree::MAX_TREE_STATES],
            );
            tree::evaluate_tree(d, &cc, &mut a, &mut l, &mut w);
            w[..c.len()].to_vec()
        }
        Schedule::RejectChain(len) => {
            let mut cc = [0.0; reject_chain::MAX_REJECT_CHAIN_STATES];
            cc[..c.len()].copy_from_slice(c);
            let (mut a, mut p, mut w) = ([0.0; 64], [0.0; 65], [0.0; 65]);
            reject_chain::evaluate_reject_chain(len, &cc, &mut a, &mut p, &mut w);
            w[..c.len()].to_vec()
        }
    }
}

/// A pixel importance that differs from pixel to pixel (0.5 to 1.36), so that each
/// estimator's division by it is checked on both sides.
fn importance(params: &RenderParams) -> Vec<f32> {
    (0..params.width * params.height).map(|j| 0.5 + (j % 7) as f32 / 7.0).collect()
}

fn allowed(n: usize) -> usize {
    n / 200
}

/// The two sides of a difftest: the device backend and the CPU buffers of the same render, at
/// the same state. Each check runs one stage on both from the same inputs (the CPU's outputs
/// of the stage before) and compares what it wrote.
struct Difftest<'a> {
    method: Schedule,
    base: RenderParams,
    params: RenderParams,
    dev: gpu::GpuBackend,
    cpu: CpuBuffers<'a, HostCaster<'a>>,
    /// The chains' states before `select`.
    start: Vec<ChainState>,
}

impl<'a> Difftest<'a> {
    fn new(gpu: Gpu, method: Schedule, estimator: render::Estimator, scene: &'a SceneData) -> Self {
        let s = Settings {
            width: 24,
            height: 16,
            max_depth: 5,
            seed: 3,
            integrator: Integrator::new(
                Method::Metropolis { schedule: method, estimator },
                ChainSettings { bootstrap_samples: 2048, ..Default::default() },
            ),
            budget: Budget::MutationsPerPixel(1.0),
            candidates: 2048,
            ..Default::default()
        };
        let base = render::base_params(scene, &s);
        let dev = gpu::GpuBackend::new(gpu, scene, &base).expect("device buffers");
        upload(dev.gpu(), &dev.buffers().importance, &importance(&base));
        Difftest {
            method,
            base,
            params: RenderParams { iteration: 5, ..base },
            dev,
            cpu: CpuBuffers::new(scene.shared(), &base, importance(&base).into()),
            start: Vec::new(),
        }
    }

    fn candidates(&self) -> usize {
        self.base.candidates as usize
    }

    fn chains(&self) -> usize {
        self.base.chains as usize
    }

    /// Bootstrap (mutate, trace, connect in bootstrap mode); then both sides start their chains
    /// identically, at the first N bootstrap samples.
    fn bootstrap(&mut self) {
        let (method, c, n) = (self.method, self.candidates(), self.chains());
        let boot = RenderParams { mode: MODE_BOOTSTRAP, ..self.base };
        let (a, depths) = self.cpu.bootstrap(&boot);
        self.dev.run(&boot, &[Stage::Mutate, Stage::Trace, Stage::Connect]).unwrap();
        let b: Vec<Vec4> = self.dev.gpu().read(&self.dev.buffers().iteration.contributions, c).unwrap();
        let differ = a.iter().zip(&b).filter(|(x, y)| !close4(**x, **y, 1e-3)).count();
        println!("{method}: bootstrap contributions differing: {differ} of {c}");
        assert!(differ <= allowed(c));
        let dims = self.base.dims;
        let mut chain_u = vec![0.0f32; n * dims as usize];
        for p in 0..n as u32 {
            for d in 0..dims {
                chain_u[soa_index(p, d, n as u32)] = shared::params::bootstrap_sample(self.base.seed, p, d);
            }
        }
        self.start = (0..n)
            .map(|p| ChainState { contribution: a[p].to_array(), depth: depths[p], ..Default::default() })
            .collect();
        self.cpu.iteration.chain_u.copy_from_slice(&chain_u);
        self.cpu.iteration.chains.copy_from_slice(&self.start);
        self.dev.start(&chain_u, &self.start, &importance(&self.base)).unwrap();
    }

    /// mutate: the same candidate samples and depths, exactly.
    fn mutate(&mut self) {
        let c = self.candidates();
        let (params, cpu) = (&self.params, &mut self.cpu);
        cpu.run(Stage::Mutate, params, &mut []);
        self.dev.run(params, &[Stage::Mutate]).unwrap();
        let dev_u: Vec<f32> =
            self.dev.gpu().read(&self.dev.buffers().iteration.cand_u, cpu.iteration.cand_u.len()).unwrap();
        let differ =
            cpu.iteration.cand_u.iter().zip(&dev_u).filter(|(x, y)| (**x - **y).abs() > 1e-6).count();
        println!("{}: mutate samples differing: {differ} of {}", self.method, dev_u.len());
        assert_eq!(differ, 0);
        let dev_depth: Vec<u32> = self.dev.gpu().read(&self.dev.buffers().iteration.cand_depth, c).unwrap();
        assert_eq!(cpu.iteration.cand_depth, dev_depth, "candidate depths");
    }

    /// trace, from the CPU's candidate samples: the same path infos and used vertices.
    fn trace(&mut self) {
        let c = self.candidates();
        let (params, cpu) = (&self.params, &mut self.cpu);
        upload(self.dev.gpu(), &self.dev.buffers().iteration.cand_u, &cpu.iteration.cand_u);
        cpu.run(Stage::Trace, params, &mut []);
        self.dev.run(params, &[Stage::Trace]).unwrap();
        let dev_paths: Vec<PathInfo> = self.dev.gpu().read(&self.dev.buffers().iteration.paths, c).unwrap();
        let dev_vertices: Vec<PathVertex> = self
            .dev
            .gpu()
            .read(&self.dev.buffers().iteration.vertices, cpu.iteration.vertices.len())
            .unwrap();
        let slots = shared::mmlt::vertex_slots(params.max_depth);
        let vertex = |v: &[PathVertex], k: usize, slot: u32| v[soa_index(k as u32, slot, c as u32)];
        let mut differ = 0;
        for (k, (&pa, &pb)) in cpu.iteration.paths.iter().zip(&dev_paths).enumerate() {
            let same_vertices = (0..slots).all(|slot| {
                let used = slot < pa.camera_vertices || slot >= slots - pa.light_vertices;
                !used
                    || vertex_close(
                        &vertex(&cpu.iteration.vertices, k, slot),
                        &vertex(&dev_vertices, k, slot),
                    )
            });
            if pa != pb || !same_vertices {
                differ += 1;
                if differ <= 3 && std::env::var("SMLT_DIFF_VERBOSE").is_ok() {
                    println!("candidate {k}: cpu {pa:?}\n  dev {pb:?}");
                    for slot in 0..slots {
                        let (x, y) =
                            (vertex(&cpu.iteration.vertices, k, slot), vertex(&dev_vertices, k, slot));
                        if !vertex_close(&x, &y) {
                            println!("  slot {slot}: cpu {x:?}\n          dev {y:?}");
                        }
                    }
                }
            }
        }
        println!("{}: traced candidates differing: {differ} of {c}", self.method);
        assert!(differ <= allowed(c));
    }

    /// connect, from the CPU's vertices and paths: the same contributions and pixels.
    fn connect(&mut self) {
        let c = self.candidates();
        let (params, cpu) = (&self.params, &mut self.cpu);
        upload(self.dev.gpu(), &self.dev.buffers().iteration.vertices, &cpu.iteration.vertices);
        upload(self.dev.gpu(), &self.dev.buffers().iteration.paths, &cpu.iteration.paths);
        cpu.run(Stage::Connect, params, &mut []);
        // The path estimator's connect writes the vertices each path read as the candidate's
        // depth: the device starts from a sentinel it must overwrite.
        let path = self.base.estimator == shared::params::ESTIMATOR_PATH;
        let before = if path {
            vec![u32::MAX; cpu.iteration.cand_depth.len()]
        } else {
            cpu.iteration.cand_depth.clone()
        };
        upload(self.dev.gpu(), &self.dev.buffers().iteration.cand_depth, &before);
        self.dev.run(params, &[Stage::Connect]).unwrap();
        let dev_depth: Vec<u32> = self.dev.gpu().read(&self.dev.buffers().iteration.cand_depth, c).unwrap();
        let depth_differ = cpu.iteration.cand_depth.iter().zip(&dev_depth).filter(|(a, b)| a != b).count();
        assert!(depth_differ <= allowed(c), "candidate depths after connect: {depth_differ} differ");
        if path {
            let short = cpu.iteration.cand_depth[..c].iter().filter(|&&v| v < self.base.max_depth).count();
            println!("{}: paths that read fewer than max_depth vertices: {short} of {c}", self.method);
            assert!(short > 0 && cpu.iteration.cand_depth[..c].iter().all(|&v| v <= self.base.max_depth));
        }
        let dev_contrib: Vec<Vec4> =
            self.dev.gpu().read(&self.dev.buffers().iteration.contributions, c).unwrap();
        let differ = cpu
            .iteration
            .contributions
            .iter()
            .zip(&dev_contrib)
            .filter(|(x, y)| !close4(**x, **y, 1e-3))
            .count();
        let nonzero = cpu.iteration.contributions.iter().filter(|v| v.truncate().max_element() > 0.0).count();
        println!("{}: connected contributions differing: {differ} of {c} ({nonzero} non-zero)", self.method);
        // Not a vacuous check: a twentieth of the candidates carry light at least (the lamps'
        // open sky leaves most of them dark).
        assert!(differ <= allowed(c) && nonzero > c / 20);
        for (x, y) in cpu.iteration.contributions.iter().zip(&dev_contrib) {
            assert_eq!(unpack_contribution(*x).1, unpack_contribution(*y).1, "pixel bits");
        }
    }

    /// select, from the CPU's contributions: the same chain states, samples, tallies and
    /// splat records, and splat weights that are the shared tree / reject-chain weights.
    fn select(&mut self) {
        let (method, n) = (self.method, self.chains());
        let (params, cpu) = (&self.params, &mut self.cpu);
        upload(self.dev.gpu(), &self.dev.buffers().iteration.contributions, &cpu.iteration.contributions);
        cpu.run(Stage::Select, params, &mut []);
        self.dev.run(params, &[Stage::Select]).unwrap();
        let dev_chains: Vec<ChainState> =
            self.dev.gpu().read(&self.dev.buffers().iteration.chains, n).unwrap();
        let dev_chain_u: Vec<f32> =
            self.dev.gpu().read(&self.dev.buffers().iteration.chain_u, cpu.iteration.chain_u.len()).unwrap();
        let records = Stage::Splat.invocations(params) as usize;
        let dev_splats: Vec<Vec4> =
            self.dev.gpu().read(&self.dev.buffers().iteration.splats, records).unwrap();
        // A chain whose next-state draw falls within rounding of a probability boundary may move
        // differently on the two sides; every other chain must have identical samples.
        let same_state: Vec<bool> = (0..n)
            .map(|p| {
                let (x, y) = (cpu.iteration.chains[p], dev_chains[p]);
                close4(Vec4::from_array(x.contribution), Vec4::from_array(y.contribution), 1e-6)
                    && close(x.accepted, y.accepted, 1e-4)
                    && x.invalid == y.invalid
                    && x.depth == y.depth
                    && x.large_count == y.large_count
                    && close(x.large_sum, y.large_sum, 1e-4)
            })
            .collect();
        let differ = same_state.iter().filter(|x| !**x).count();
        let moved =
            (0..n).filter(|&p| cpu.iteration.chains[p].contribution != self.start[p].contribution).count();
        let tallied = cpu.iteration.chains.iter().filter(|x| x.large_count > 0).count();
        assert!(tallied > 0, "{method}: select tallies the large steps' targets for b");
        println!("{method}: chain states differing: {differ} of {n} ({moved} moved)");
        assert!(differ <= allowed(n).max(1) && moved > 0);
        for p in (0..n as u32).filter(|&p| same_state[p as usize]) {
            for d in 0..params.dims {
                let i = soa_index(p, d, n as u32);
                assert_eq!(cpu.iteration.chain_u[i], dev_chain_u[i], "chain {p} sample {d} after selection");
            }
        }
        // A record holds (F/c)·w, whose luminance is w.
        let per = params.candidates_per_chain() as usize;
        let mut checked = 0;
        for p in 0..n {
            let mut c =
                vec![shared::color::luminance(Vec4::from_array(self.start[p].contribution).truncate())];
            c.extend(
                (0..per)
                    .map(|k| shared::color::luminance(cpu.iteration.contributions[p * per + k].truncate())),
            );
            let expected = expected_weights(method, &c);
            for (state, w) in expected.iter().enumerate() {
                let record = dev_splats[p * (per + 1) + state];
                let got = if unpack_contribution(record).1 == shared::layout::NO_PIXEL {
                    0.0
                } else {
                    shared::color::luminance(record.truncate())
                };
                // A state with no contribution (c = 0) keeps its weight in the total but splats
                // nothing.
                let w = if c[state] > 0.0 { *w } else { 0.0 };
                // luminance((F/c)·w) = w exactly only while F is a normal float.
                if same_state[p] && (c[state] == 0.0 || c[state] > 1e-30) {
                    assert!(
                        (got - w).abs() <= 1e-4 * w.max(1.0),
                        "chain {p} state {state}: weight {got} vs {w}"
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > n);
        let differ = cpu.iteration.splats[..records]
            .iter()
            .zip(&dev_splats)
            .filter(|(x, y)| !close4(**x, **y, 1e-4))
            .count();
        println!("{method}: splat records differing: {differ} of {records}");
        assert!(differ <= allowed(records).max(1));
    }

    /// splat, from the CPU's records: the device's f32 image equals the CPU's f64 sum.
    fn splat(&mut self) {
        let (params, cpu) = (&self.params, &mut self.cpu);
        let mut cpu_image = vec![0.0f64; (params.width * params.height * 3) as usize];
        cpu.run(Stage::Splat, params, &mut cpu_image);
        upload(self.dev.gpu(), &self.dev.buffers().iteration.splats, &cpu.iteration.splats);
        self.dev.run(params, &[Stage::Splat]).unwrap();
        let mut drained = render::Accumulation::new((params.width * params.height) as usize);
        self.dev.drain(&mut drained).unwrap();
        for (x, y) in cpu_image.iter().zip(&drained.image) {
            assert!((x - y).abs() <= 1e-5 * x.abs().max(1.0), "image {x} vs {y}");
        }
        assert!(cpu_image.iter().any(|v| *v > 0.0));
    }
}

/// Every stage of an iteration, device against CPU, each from the same inputs.
fn difftest(gpu: Gpu, method: Schedule) {
    difftest_estimator(gpu, method, render::Estimator::Multiplexed);
}

/// [`difftest`] with chains over `estimator`.
fn difftest_estimator(gpu: Gpu, method: Schedule, estimator: render::Estimator) {
    let scene = SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell").expect("cornell");
    difftest_scene(gpu, method, estimator, &scene);
}

/// [`difftest_estimator`] on `scene`.
fn difftest_scene(gpu: Gpu, method: Schedule, estimator: render::Estimator, scene: &SceneData) {
    let mut t = Difftest::new(gpu, method, estimator, scene);
    t.bootstrap();
    t.mutate();
    t.trace();
    t.connect();
    t.select();
    t.splat();
}

#[test]
fn naive_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("naive_passes_agree_on_device_and_cpu") {
        difftest(gpu, Schedule::Tree(1));
    }
}

/// The path estimator's stages (`trace` idle, the whole path in `connect`), naive, s3 and rc4.
#[test]
fn path_estimator_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("path_estimator_passes_agree_on_device_and_cpu") {
        difftest_estimator(gpu.clone(), Schedule::Tree(1), render::Estimator::Path);
        difftest_estimator(gpu.clone(), Schedule::Tree(3), render::Estimator::Path);
        difftest_estimator(gpu, Schedule::RejectChain(4), render::Estimator::Path);
    }
}

/// Under punctual lights (`lamps`: a point lamp, a spot and a sun): their light subpaths,
/// connections and weights, and the path estimator's next-event estimation.
#[test]
fn punctual_light_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("punctual_light_passes_agree_on_device_and_cpu") {
        let scene = SceneData::from_slice(include_bytes!("../scenes/lamps.gltf"), "lamps").expect("lamps");
        difftest_scene(gpu.clone(), Schedule::Tree(1), render::Estimator::Multiplexed, &scene);
        difftest_scene(gpu, Schedule::Tree(1), render::Estimator::Path, &scene);
    }
}

/// Naive and s3 over the multiplexed estimator and naive over the path estimator on `scene`.
fn difftest_both_estimators(gpu: Gpu, scene: &SceneData) {
    difftest_scene(gpu.clone(), Schedule::Tree(1), render::Estimator::Multiplexed, scene);
    difftest_scene(gpu.clone(), Schedule::Tree(3), render::Estimator::Multiplexed, scene);
    difftest_scene(gpu, Schedule::Tree(1), render::Estimator::Path, scene);
}

/// Through glass (`caustic`: a clear solid ball, an absorbing amber block, a thin pane, under a
/// spot and an area lamp): the dielectric's delta lobes in both subpaths, Beer–Lambert inside
/// the solids, the delta vertices' weights, and the path estimator through the same glass.
#[test]
fn glass_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("glass_passes_agree_on_device_and_cpu") {
        let scene =
            SceneData::from_slice(include_bytes!("../scenes/caustic.gltf"), "caustic").expect("caustic");
        difftest_both_estimators(gpu, &scene);
    }
}

/// Through rough glass (`rough_glass_caustic`: a frosted solid ball and a frosted thin pane
/// under a point lamp): the rough dielectric's refraction and a thin wall's mirrored reflection
/// lobe, sampled and evaluated in every stage, connected to like any other surface.
#[test]
fn rough_glass_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("rough_glass_passes_agree_on_device_and_cpu") {
        difftest_both_estimators(gpu, &common::scenes::rough_glass_caustic(0.5));
    }
}

/// Under the environment (`sky_scene`: a sky with a sun, a glass ball, a triangle lamp): camera
/// subpaths that end on the environment, light subpaths that leave its disks, connections to
/// it and their weights, and the path estimator's escapes.
#[test]
fn environment_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("environment_passes_agree_on_device_and_cpu") {
        let scene = common::scenes::sky_scene();
        difftest_both_estimators(gpu, &scene);
    }
}

/// On glTF's metallic-roughness BRDF (`brdf_scene` under its point lamp: rough metal, a
/// dielectric layer over diffuse, a smooth mirror's delta lobe): the lobe choice, visible-normal
/// sampling and the mixture's densities in both subpaths and the path estimator.
#[test]
fn brdf_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("brdf_passes_agree_on_device_and_cpu") {
        difftest_both_estimators(gpu, &common::scenes::brdf_scene(true));
    }
}

/// Under glTF's clear coat (`coated_scene` under its point lamp: smooth and rough coats over
/// every kind of base): the coat's lobe choice, its mirror, its weight by the viewer's side in
/// both subpaths, and the path estimator.
#[test]
fn clearcoat_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("clearcoat_passes_agree_on_device_and_cpu") {
        difftest_both_estimators(gpu, &common::scenes::coated_scene(true));
    }
}

/// On textures (`textured_scene`: every slot, NEAREST and bilinear, wraps, a transform, an
/// emissive texture on the lamp): the texel store and its lookups at every vertex.
#[test]
fn textured_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("textured_passes_agree_on_device_and_cpu") {
        difftest_both_estimators(gpu, &common::scenes::textured_scene());
    }
}

/// On vertex colours (`tests/colors/attribute`: Blender's export of a ball whose faces' colours
/// its material reads from `COLOR_0`, under `sky_map` too, so that most paths carry light): the
/// colour store and the base colour it multiplies.
#[test]
fn vertex_colour_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("vertex_colour_passes_agree_on_device_and_cpu") {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/colors/attribute/round_trip.gltf");
        let scene = SceneData::load_with_environment(&path, Some(common::scenes::sky_map(30.0)));
        difftest_both_estimators(gpu, &scene.expect("the coloured ball"));
    }
}

/// On anisotropic roughness (`KHR_materials_anisotropy`): the colour fixture's ball a brushed
/// metal and its floor an anisotropic dielectric turned 60° by its factor and texel by texel by
/// a 4 × 4 anisotropyTexture (whose blue scales the strength), both framed by MikkTSpace's
/// tangents over Blender's `TEXCOORD_0`, under `sky_map`: the tangent store, the lobes' frame,
/// the texture's direction and strength, and the anisotropic GGX's evaluation and sampling in
/// every stage. The floor's layer takes the same texture as `KHR_materials_specular`'s two
/// (its alpha the factor's, its rgb the colour's).
#[test]
fn anisotropic_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("anisotropic_passes_agree_on_device_and_cpu") {
        let fixture = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/colors/attribute");
        let mut doc: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(fixture.join("round_trip.gltf")).unwrap()).unwrap();
        let brushed = serde_json::json!({"anisotropyStrength": 0.8});
        let turned = serde_json::json!({"anisotropyStrength": 0.6, "anisotropyRotation": 1.05,
            "anisotropyTexture": {"index": 0}});
        let image = smlt::scenes::png(4, 4, |x, y| {
            [(30 + 60 * x) as u8, (230 - 55 * y) as u8, (90 + 40 * ((x + y) % 4)) as u8, (80 + 50 * y) as u8]
        });
        use base64::Engine;
        let uri =
            format!("data:image/png;base64,{}", base64::engine::general_purpose::STANDARD.encode(image));
        doc["images"] = serde_json::json!([{ "uri": uri }]);
        doc["textures"] = serde_json::json!([{ "source": 0 }]);
        for (material, extension) in [(3, brushed), (0, turned)] {
            let m = &mut doc["materials"][material];
            m["pbrMetallicRoughness"]["metallicFactor"] =
                serde_json::json!(if material == 3 { 1.0 } else { 0.0 });
            m["pbrMetallicRoughness"]["roughnessFactor"] = serde_json::json!(0.3);
            // Blender wrote specularFactor 0 (Lambert): the extension's whole, the spec's layer.
            m["extensions"] = serde_json::json!({ "KHR_materials_anisotropy": extension });
        }
        doc["materials"][0]["extensions"]["KHR_materials_specular"] = serde_json::json!({
            "specularFactor": 0.9, "specularTexture": {"index": 0},
            "specularColorFactor": [1.0, 0.8, 0.6], "specularColorTexture": {"index": 0}});
        doc["extensionsUsed"].as_array_mut().unwrap().push(serde_json::json!("KHR_materials_specular"));
        doc["extensionsUsed"].as_array_mut().unwrap().push(serde_json::json!("KHR_materials_anisotropy"));
        let dir = std::env::temp_dir().join(format!("smlt-anisotropic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::copy(fixture.join("round_trip.bin"), dir.join("round_trip.bin")).unwrap();
        std::fs::write(dir.join("round_trip.gltf"), doc.to_string()).unwrap();
        let scene = SceneData::load_with_environment(
            &dir.join("round_trip.gltf"),
            Some(common::scenes::sky_map(30.0)),
        );
        std::fs::remove_dir_all(&dir).unwrap();
        let scene = scene.expect("the anisotropic ball");
        assert!(scene.tangents.iter().any(|t| t.t != [0.0; 12]), "the floor's and the ball's tangents");
        let lobes = [0, 3].map(|k| scene.materials[k + 1]);
        assert!(lobes.iter().all(|m| !m.is_lambertian() && m.alphas().x > m.alphas().y), "{lobes:?}");
        let floor = scene.material_textures[lobes[0].textures as usize];
        assert!(floor.anisotropy.is_some() && floor.specular.is_some() && floor.specular_color.is_some());
        difftest_both_estimators(gpu, &scene);
    }
}

/// On smooth normals (`scenes/smooth.gltf`: interpolated `NORMAL`s on a white, a gold and a
/// glass ball; `bent_floor`: normals leaning 40°): the normal store, the shading frame, the
/// zero where the normals disagree about a side, and the adjoint cosine on light subpaths.
#[test]
fn smooth_normal_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("smooth_normal_passes_agree_on_device_and_cpu") {
        let smooth =
            SceneData::from_slice(include_bytes!("../scenes/smooth.gltf"), "smooth").expect("smooth");
        difftest_both_estimators(gpu.clone(), &smooth);
        difftest_both_estimators(gpu, &common::scenes::bent_floor());
    }
}

/// On cut-outs (`scenes/cutout.gltf`: a MASK screen of NEAREST holes, a bilinear MASK leaf, a
/// BLEND pane): the alpha lookups inside traversal and the stochastic opacity's hash, in every
/// ray the passes cast.
#[test]
fn cut_out_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("cut_out_passes_agree_on_device_and_cpu") {
        let cutout =
            SceneData::from_slice(include_bytes!("../scenes/cutout.gltf"), "cutout").expect("cutout");
        difftest_both_estimators(gpu, &cutout);
    }
}

#[test]
fn reject_chain_eight_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("reject_chain_eight_passes_agree_on_device_and_cpu") {
        difftest(gpu, Schedule::RejectChain(8));
    }
}

/// The device's candidate buffer for s3: every candidate of a level carries the same
/// perturbation. Candidate 3 (level 3 after "reject, reject") moves the root by δ3; candidates
/// 4, 5, 6 (level 3 after the other histories) move their sources — candidates 1, 0, 2 — by
/// exactly the same δ3; candidate 2 moves candidate 0 by the δ2 that candidate 1 moved the
/// root by.
#[test]
fn speculative_candidates_share_each_levels_perturbation_on_the_device() {
    let Some(gpu) =
        common::gpu_or_skip("speculative_candidates_share_each_levels_perturbation_on_the_device")
    else {
        return;
    };
    let scene = SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell").expect("cornell");
    let s = Settings {
        width: 8,
        height: 8,
        max_depth: 3,
        seed: 11,
        integrator: Integrator::new(
            "s3".parse().unwrap(),
            ChainSettings { bootstrap_samples: 64, ..Default::default() },
        ),
        budget: Budget::MutationsPerPixel(1.0),
        candidates: 7 * 64,
        ..Default::default()
    };
    let base = render::base_params(&scene, &s);
    let (n, c, dims) = (base.chains as usize, base.candidates as usize, base.dims as usize);
    let mut dev = gpu::GpuBackend::new(gpu, &scene, &base).expect("device buffers");
    let chain_u: Vec<f32> = (0..n * dims).map(|i| (i as f32 * 0.618_034).fract()).collect();
    // Chains at the deepest depth, so that every dimension is mutated.
    dev.start(
        &chain_u,
        &vec![ChainState { depth: s.max_depth, ..Default::default() }; n],
        &importance(&base),
    )
    .unwrap();
    let params = RenderParams { iteration: 9, ..base };
    dev.run(&params, &[Stage::Mutate]).unwrap();
    let u: Vec<f32> = dev.gpu().read(&dev.buffers().iteration.cand_u, c * dims).unwrap();
    // The offset from a to b on the unit circle, in (−0.5, 0.5].
    let step = |a: f32, b: f32| {
        let d = b - a;
        d - d.round()
    };
    let mut small = 0;
    for p in 0..n {
        if shared::mutation::is_large_step(s.seed, p as u32, 9, base.mutation.p_large) {
            continue;
        }
        small += 1;
        for d in 0..dims {
            let cand = |k: usize| u[p * 7 + k + d * c];
            let root = chain_u[p + d * n];
            let d3 = step(root, cand(3));
            for (k, source) in [(4, cand(1)), (5, cand(0)), (6, cand(2))] {
                assert!((step(source, cand(k)) - d3).abs() < 1e-6, "chain {p} dim {d}: candidate {k}");
            }
            assert!(
                (step(cand(0), cand(2)) - step(root, cand(1))).abs() < 1e-6,
                "chain {p} dim {d}: level 2"
            );
            // Kelemen's s1..s2, or the image plane's own range for the raster position.
            let m = base.mutation;
            let raster = (m.image_dimension..m.image_dimension + 2).contains(&(d as u32));
            let largest = if raster { m.image_s2 } else { m.s2 };
            let smallest = largest * m.s1 / m.s2;
            assert!(
                d3.abs() <= largest + 1e-6 && d3.abs() >= smallest - 1e-6,
                "chain {p} dim {d}: step {d3} outside {smallest}..{largest}"
            );
        }
    }
    assert!(small > 20, "{small} chains without a large step");
}

#[test]
fn speculative_depth_three_passes_agree_on_device_and_cpu() {
    if let Some(gpu) = common::gpu_or_skip("speculative_depth_three_passes_agree_on_device_and_cpu") {
        difftest(gpu, Schedule::Tree(3));
    }
}

/// Every pass binds what its kernel declares: as many buffers as the entry point's interface
/// holds, and writable exactly where the kernel's parameter is `&mut` (SPIR-V `NonWritable`
/// marks the others). With SPIR-V passthrough nothing else checks this.
#[test]
fn every_pass_binds_what_its_kernel_declares() {
    let Some(gpu) = common::gpu_or_skip("every_pass_binds_what_its_kernel_declares") else {
        return;
    };
    let scene = SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell").unwrap();
    let s = Settings {
        width: 8,
        height: 8,
        max_depth: 3,
        seed: 1,
        integrator: Integrator::new(
            "s2".parse().unwrap(),
            ChainSettings { bootstrap_samples: 192, ..Default::default() },
        ),
        budget: Budget::MutationsPerPixel(1.0),
        candidates: 192,
        ..Default::default()
    };
    let params = render::base_params(&scene, &s);
    let buffers = GpuBuffers::new(&mut OnDevice::new(gpu.clone()), &scene, &params);
    let interfaces = smlt::gpu::spirv_interfaces(&wgpu::util::make_spirv_raw(smlt::gpu::KERNELS_SPV));
    let declared = |entry: &str| -> Vec<bool> {
        let e = interfaces.iter().find(|e| e.name == entry).unwrap_or_else(|| panic!("no {entry}"));
        e.bindings.iter().filter(|(set, ..)| *set == 0).map(|(_, _, writable)| *writable).collect()
    };
    for stage in Stage::ITERATION {
        let pass = stage.pass(&gpu, &buffers).unwrap();
        assert_eq!(pass.writable(), declared(stage.entry_point()), "{}", stage.name());
    }
    let path_params = gpu.storage_from("path tracer params", &[render::path_params(&scene, &s)]);
    let path_tracer = passes::path_tracer::gpu(&gpu, &path_params, &buffers).unwrap();
    assert_eq!(path_tracer.writable(), declared("path_tracer_cs"));
    let ray_params = gpu.storage_from("raycast params", &[params]);
    let rays = gpu.storage_zeroed::<shared::rays::Ray>("rays", 64);
    let answers = gpu.storage_zeroed::<u32>("answers", 64);
    let raycast = passes::raycast::gpu(&gpu, [&ray_params, &rays, &answers], &buffers.registry).unwrap();
    assert_eq!(raycast.writable(), declared("raycast_cs"));
}

/// The path tracer's pass (`--method pt`, and `smlt reference`): one round of 4 samples a
/// pixel on the device and on the CPU backend, pixel by pixel, on the default scene, on
/// Sibenik-like geometry (the nave), under the environment (`sky_scene`), on glTF's BRDF
/// (`brdf_scene`), on textures (`textured_scene`), on smooth normals (`smooth.gltf`) and on cut-outs
/// (`cutout.gltf`): at most
/// 0.5 % of pixel values differ beyond 1e-3 relative
/// (a path that grazes an edge may take the other branch).
#[test]
fn the_path_tracer_agrees_on_device_and_cpu() {
    let Some(gpu) = common::gpu_or_skip("the_path_tracer_agrees_on_device_and_cpu") else { return };
    for (name, scene) in [
        (
            "cornell",
            SceneData::from_slice(include_bytes!("../scenes/cornell.gltf"), "cornell").expect("cornell"),
        ),
        ("nave", SceneData::from_slice(include_bytes!("../scenes/nave.gltf"), "nave").expect("nave")),
        ("sky", common::scenes::sky_scene()),
        ("brdf", common::scenes::brdf_scene(false)),
        ("textured", common::scenes::textured_scene()),
        ("smooth", SceneData::from_slice(include_bytes!("../scenes/smooth.gltf"), "smooth").expect("smooth")),
        ("cutout", SceneData::from_slice(include_bytes!("../scenes/cutout.gltf"), "cutout").expect("cutout")),
    ] {
        let s = Settings {
            width: 24,
            height: 16,
            max_depth: 5,
            seed: 3,
            integrator: Integrator::PathTracer,
            budget: Budget::MutationsPerPixel(4.0),
            candidates: 24 * 16 * 4,
            ..Default::default()
        };
        let params = render::path_params(&scene, &s);
        let base = render::base_params(&scene, &s);
        let round = shared::path_tracer::PathTracerParams { round: 2, ..params };
        let mut images = Vec::new();
        let mut dev = gpu::GpuBackend::new(gpu.clone(), &scene, &base).expect("device buffers");
        let mut cpu = render::cpu::CpuBackend::new(&scene, &base, 2).expect("threads");
        for backend in [&mut dev as &mut dyn Backend, &mut cpu] {
            backend.trace_path_tracer_round(&round).unwrap();
            let mut acc = render::Accumulation::new(24 * 16);
            backend.drain(&mut acc).unwrap();
            images.push(acc.image);
        }
        let n = images[0].len();
        let differ =
            images[0].iter().zip(&images[1]).filter(|(a, b)| !close(**a as f32, **b as f32, 1e-3)).count();
        println!("{name}: path tracer pixel values differing: {differ} of {n}");
        assert!(differ <= allowed(n).max(1), "{name}: {differ} of {n}");
        assert!(images[0].iter().filter(|v| **v > 0.0).count() > n / 2, "{name}: mostly lit");
    }
}
