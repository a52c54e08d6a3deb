//! The render's buffers, laid out once. [`DeviceBuffers`] is generic over where its buffers
//! live — a [`Storage`]: device buffers ([`OnDevice`]), host vectors ([`OnHost`]), or only
//! their byte sizes ([`Sizes`]) — so the device backend, the CPU backend's groups of chains and
//! the reported device memory and limit checks all come from the same `new` functions. Each
//! buffer is made under the name the kernels bind it by (`kernels::stage`): a device pass
//! finds its buffers by those names, and the test below checks every stage's against [`Sizes`].

use bytemuck::Pod;
use glam::Vec4;
use shared::bsdf::Material;
use shared::cwbvh::WideNode;
use shared::environment::Environment;
use shared::light::LightEntry;
use shared::mmlt::{vertex_slots, ChainState, PathInfo, PathVertex};
use shared::normal_map::TriangleTangents;
use shared::normals::TriangleNormals;
use shared::params::{RenderParams, ESTIMATOR_PATH};
use shared::punctual::PunctualLight;
use shared::surface::{MaterialTextures, TriangleColors, TriangleTexcoords};
use shared::texture::Texture;
use shared::triangle::Triangle;

use super::{Named, Stage};
use crate::gpu::Gpu;
use crate::scene::SceneData;

/// Where buffers live: makes a buffer of `count` zeroed `T`s, or one holding `data`, under
/// `name` (what a kernel binds it by: `kernels::stage`) and `label` (what a person reads).
pub trait Storage {
    /// A buffer of `T`s.
    type Of<T: Pod>;
    /// What the storage keeps of every buffer it made (by name, for binding them).
    type Registry;
    /// `count` zeroed elements.
    fn zeroed<T: Pod>(&mut self, name: &'static str, label: &'static str, count: usize) -> Self::Of<T>;
    /// A copy of `data`.
    fn copy_of<T: Pod>(&mut self, name: &'static str, label: &'static str, data: &[T]) -> Self::Of<T>;
    /// The buffers made so far, handed over (the storage forgets them).
    fn registry(&mut self) -> Self::Registry;
}

/// Buffers on a Vulkan device (the handle shares the device), each also kept by name.
pub struct OnDevice {
    gpu: Gpu,
    made: Vec<(&'static str, &'static str, wgpu::Buffer)>,
}

impl OnDevice {
    /// Storage on `gpu`'s device.
    pub fn new(gpu: Gpu) -> Self {
        Self { gpu, made: Vec::new() }
    }
}

/// Device buffers by name, with their element types (what [`Pass::new`](super::Pass::new)
/// binds a kernel's declared bindings to).
#[derive(Default)]
pub struct Registry(Vec<(&'static str, &'static str, wgpu::Buffer)>);

impl Registry {
    /// The buffer named `name`.
    pub fn named(&self, name: &str) -> Option<Named<'_>> {
        self.0.iter().find(|(n, ..)| *n == name).map(|(_, element, buffer)| Named { buffer, element })
    }
}

impl Storage for OnDevice {
    type Of<T: Pod> = wgpu::Buffer;
    type Registry = Registry;
    fn zeroed<T: Pod>(&mut self, name: &'static str, label: &'static str, count: usize) -> wgpu::Buffer {
        let buffer = self.gpu.storage_zeroed::<T>(label, count);
        self.made.push((name, std::any::type_name::<T>(), buffer.clone()));
        buffer
    }
    fn copy_of<T: Pod>(&mut self, name: &'static str, label: &'static str, data: &[T]) -> wgpu::Buffer {
        let buffer = self.gpu.storage_from(label, data);
        self.made.push((name, std::any::type_name::<T>(), buffer.clone()));
        buffer
    }
    fn registry(&mut self) -> Registry {
        Registry(std::mem::take(&mut self.made))
    }
}

/// Buffers in host memory (the CPU backend).
pub struct OnHost;

impl Storage for OnHost {
    type Of<T: Pod> = Vec<T>;
    type Registry = ();
    fn zeroed<T: Pod>(&mut self, _name: &'static str, _label: &'static str, count: usize) -> Vec<T> {
        vec![T::zeroed(); count]
    }
    fn copy_of<T: Pod>(&mut self, _name: &'static str, _label: &'static str, data: &[T]) -> Vec<T> {
        data.to_vec()
    }
    fn registry(&mut self) {}
}

/// One buffer as [`Sizes`] lists it.
#[derive(Clone, Debug, PartialEq)]
pub struct BufferSize {
    /// What a kernel binds it by.
    pub name: &'static str,
    /// What a person reads.
    pub label: &'static str,
    /// `std::any::type_name` of its element.
    pub element: &'static str,
    #[allow(missing_docs)] // its size
    pub bytes: u64,
}

/// No buffers: only each one's name, element type and byte size, in layout order.
#[derive(Default)]
pub struct Sizes(pub Vec<BufferSize>);

impl Storage for Sizes {
    type Of<T: Pod> = ();
    type Registry = ();
    fn zeroed<T: Pod>(&mut self, name: &'static str, label: &'static str, count: usize) {
        let element = std::any::type_name::<T>();
        self.0.push(BufferSize { name, label, element, bytes: (count * std::mem::size_of::<T>()) as u64 });
    }
    fn copy_of<T: Pod>(&mut self, name: &'static str, label: &'static str, data: &[T]) {
        let element = std::any::type_name::<T>();
        self.0.push(BufferSize { name, label, element, bytes: std::mem::size_of_val(data) as u64 });
    }
    fn registry(&mut self) {}
}

/// What an iteration's stages read and write for a set of chains: the whole render's on the
/// device, one group's on the CPU backend.
pub struct IterationBuffers<S: Storage> {
    /// Chain samples, SoA (`p + i·N`).
    pub chain_u: S::Of<f32>,
    #[allow(missing_docs)] // the chains' states
    pub chains: S::Of<ChainState>,
    /// Candidate samples, SoA (`k + i·C`).
    pub cand_u: S::Of<f32>,
    /// Candidate path depths.
    pub cand_depth: S::Of<u32>,
    /// Subpath vertices, SoA (`k + slot·C`).
    pub vertices: S::Of<PathVertex>,
    /// One a candidate.
    pub paths: S::Of<PathInfo>,
    /// Packed contributions (`shared::layout`), one a candidate.
    pub contributions: S::Of<Vec4>,
    /// Splat records, one per distinct state of each chain.
    pub splats: S::Of<Vec4>,
}

impl<S: Storage> IterationBuffers<S> {
    /// The buffers of `params.chains` chains tracing `params.candidates` candidates.
    pub fn new(s: &mut S, params: &RenderParams) -> Self {
        let (c, n, dims) = (params.candidates as usize, params.chains as usize, params.dims as usize);
        Self {
            chain_u: s.zeroed("chain_u", "chain samples", n * dims),
            chains: s.zeroed("chains", "chain states", n),
            cand_u: s.zeroed("cand_u", "candidate samples", c * dims),
            cand_depth: s.zeroed("cand_depth", "candidate depths", c),
            // The path estimator keeps no subpath vertices (one element: a binding is never empty).
            vertices: s.zeroed(
                "vertices",
                "vertices",
                if params.estimator == ESTIMATOR_PATH {
                    1
                } else {
                    c * vertex_slots(params.max_depth) as usize
                },
            ),
            paths: s.zeroed("paths", "path infos", c),
            contributions: s.zeroed("contributions", "contributions", c),
            splats: s.zeroed("splats", "splat records", Stage::Splat.invocations(params) as usize),
        }
    }
}

/// The scene as buffers: what the kernels bind of it.
pub struct SceneBuffers<S: Storage> {
    /// The compressed wide BVH's nodes.
    pub nodes: S::Of<WideNode>,
    /// In the BVH's order.
    pub triangles: S::Of<Triangle>,
    #[allow(missing_docs)] // indexed by `Triangle::material`
    pub materials: S::Of<Material>,
    /// The light-selection CDF.
    pub lights: S::Of<LightEntry>,
    /// The punctual lights (at least one entry).
    pub punctual: S::Of<PunctualLight>,
    /// The environment light (one entry).
    pub environment: S::Of<Environment>,
    /// Its texels and CDFs (at least one value).
    pub environment_map: S::Of<f32>,
    /// The materials' textures (entry 0 unused).
    pub material_textures: S::Of<MaterialTextures>,
    /// The textures (at least one entry).
    pub textures: S::Of<Texture>,
    /// Every texture's texels (at least one).
    pub texels: S::Of<u32>,
    /// Per triangle where a material has textures (at least one entry).
    pub texcoords: S::Of<TriangleTexcoords>,
    /// Per triangle where a mesh has smooth normals (at least one entry).
    pub normals: S::Of<TriangleNormals>,
    /// Per triangle where a mesh has vertex tangents (at least one entry).
    pub tangents: S::Of<TriangleTangents>,
    /// Per triangle where a material has vertex colours (at least one entry).
    pub colors: S::Of<TriangleColors>,
}

impl<S: Storage> SceneBuffers<S> {
    /// The buffers of `scene`, named as `kernels::stage::SCENE_BINDINGS` binds them.
    pub fn new(s: &mut S, scene: &SceneData) -> Self {
        Self {
            nodes: s.copy_of("nodes", "BVH nodes", scene.wide_nodes()),
            triangles: s.copy_of("triangles", "triangles", &scene.triangles),
            materials: s.copy_of("materials", "materials", &scene.materials),
            lights: s.copy_of("lights", "lights", &scene.lights),
            punctual: s.copy_of("punctual", "punctual lights", scene.punctual_lights()),
            environment: s.copy_of("environment", "environment light", &[scene.environment]),
            environment_map: s.copy_of("environment_map", "environment map", &scene.environment_map),
            material_textures: s.copy_of("material_textures", "material textures", &scene.material_textures),
            textures: s.copy_of("textures", "textures", &scene.textures),
            texels: s.copy_of("texels", "texels", &scene.texels),
            texcoords: s.copy_of("texcoords", "texture coordinates", &scene.texcoords),
            normals: s.copy_of("normals", "vertex normals", &scene.normals),
            tangents: s.copy_of("tangents", "vertex tangents", &scene.tangents),
            colors: s.copy_of("colors", "vertex colours", &scene.colors),
        }
    }

    /// Whether the buffer named `name` is one of the scene's.
    pub fn holds(name: &str) -> bool {
        kernels::stage::SCENE_BINDINGS.iter().any(|b| b.name == name)
    }
}

/// Every buffer of a render on a device.
pub struct DeviceBuffers<S: Storage> {
    /// One `RenderParams`, rewritten before each dispatch.
    pub params: S::Of<RenderParams>,
    #[allow(missing_docs)] // the stages' own buffers
    pub iteration: IterationBuffers<S>,
    #[allow(missing_docs)] // the scene the stages read
    pub scene: SceneBuffers<S>,
    /// The f32 image, rgb per pixel (the splats add to it as bits).
    pub image: S::Of<f32>,
    /// Ĩ per pixel, the pixel importance (`crate::render::importance`; ones until the
    /// render sets it).
    pub importance: S::Of<f32>,
    /// Every buffer above by name (on a device: what its passes bind).
    pub registry: S::Registry,
}

impl<S: Storage> DeviceBuffers<S> {
    /// The buffers of a render of `scene` with `params`.
    pub fn new(s: &mut S, scene: &SceneData, params: &RenderParams) -> Self {
        let params_buffer = s.copy_of("params", "params", &[*params]);
        let iteration = IterationBuffers::new(s, params);
        let scene = SceneBuffers::new(s, scene);
        let pixels = (params.width * params.height) as usize;
        let image = s.zeroed("image", "image", pixels * 3);
        let importance = s.copy_of("importance", "importance", &vec![1.0f32; pixels]);
        Self { params: params_buffer, iteration, scene, image, importance, registry: s.registry() }
    }
}

/// A render's buffers on a Vulkan device.
pub type GpuBuffers = DeviceBuffers<OnDevice>;

impl GpuBuffers {
    /// The buffer a kernel binds by `name`.
    pub fn named(&self, name: &str) -> Option<Named<'_>> {
        self.registry.named(name)
    }
}

/// The device buffers of a render with their names, element types and byte sizes (for the
/// limits check before allocating, the memory a render reports, and the binding test).
pub fn buffer_sizes(scene: &SceneData, params: &RenderParams) -> Vec<BufferSize> {
    let mut sizes = Sizes::default();
    DeviceBuffers::new(&mut sizes, scene, params);
    sizes.0
}

/// Total bytes of a render's device buffers (the CPU backend holds the same, less the image
/// and the scene, which it reads in place).
pub fn device_bytes(scene: &SceneData, params: &RenderParams) -> u64 {
    buffer_sizes(scene, params).iter().map(|b| b.bytes).sum()
}

#[cfg(test)]
mod tests {
    use kernels::stage::{Binding, SCENE_BINDINGS};

    use super::*;
    use crate::passes::Stage;

    /// Every binding a stage declares (`kernels::stage`) is a render buffer of that name and
    /// element type, and the numbers count up from 0 in each set: the one declaration is all a
    /// stage needs, on the device as on the CPU backend (whose `Bound` the compiler checks). A
    /// buffer added to a declaration and not to the render fails here by name.
    #[test]
    fn every_stage_binds_render_buffers_by_name_and_type() {
        let (_, scene, _) = crate::scenes::open(None, 1).unwrap();
        let params = RenderParams {
            width: 4,
            height: 4,
            chains: 2,
            candidates: 2,
            dims: 8,
            tree_depth: 1,
            max_depth: 3,
            ..Default::default()
        };
        let sizes = buffer_sizes(&scene, &params);
        let check = |stage: &str, set: &[Binding]| {
            for (i, b) in set.iter().enumerate() {
                assert_eq!(b.binding as usize, i, "{stage}: {} is binding {}, not {i}", b.name, b.binding);
                let buffer = sizes.iter().find(|s| s.name == b.name);
                let buffer =
                    buffer.unwrap_or_else(|| panic!("{stage} binds {}, which no render buffer is", b.name));
                assert_eq!(buffer.element, (b.element)(), "{stage}: {}'s element", b.name);
            }
        };
        for stage in Stage::ITERATION {
            check(stage.name(), stage.kernel().bindings);
            if stage.kernel().binds_scene {
                check(stage.name(), SCENE_BINDINGS);
            }
        }
        // The path tracer's pass binds its own params and the render's scene and image.
        let own = ["params"];
        for b in kernels::path_tracer::BINDINGS.iter().filter(|b| !own.contains(&b.name)) {
            let buffer = sizes.iter().find(|s| s.name == b.name).expect(b.name);
            assert_eq!(buffer.element, (b.element)(), "path_tracer: {}", b.name);
        }
        check("path_tracer", SCENE_BINDINGS);
        // Names are unique, so a lookup by name is a lookup of one buffer.
        for (i, a) in sizes.iter().enumerate() {
            assert!(sizes[i + 1..].iter().all(|b| b.name != a.name), "{} twice", a.name);
        }
    }
}
