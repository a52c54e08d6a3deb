//! The render's buffers, laid out once. [`DeviceBuffers`] is generic over where its buffers
//! live — a [`Storage`]: device buffers ([`OnDevice`]), host vectors ([`OnHost`]), or only
//! their byte sizes ([`Sizes`]) — so the device backend, the CPU backend's groups of chains and
//! the reported device memory and limit checks all come from the same `new` functions.

use bytemuck::Pod;
use glam::Vec4;
use shared::bsdf::Material;
use shared::cwbvh::WideNode;
use shared::light::LightEntry;
use shared::mmlt::{vertex_slots, ChainState, PathInfo, PathVertex, RenderParams, ESTIMATOR_PATH};
use shared::triangle::Triangle;

use super::Stage;
use crate::gpu::Gpu;
use crate::scene::SceneData;

/// Where buffers live: makes a buffer of `count` zeroed `T`s, or one holding `data`.
pub trait Storage {
    /// A buffer of `T`s.
    type Of<T: Pod>;
    /// `count` zeroed elements.
    fn zeroed<T: Pod>(&mut self, name: &'static str, count: usize) -> Self::Of<T>;
    /// A copy of `data`.
    fn copy_of<T: Pod>(&mut self, name: &'static str, data: &[T]) -> Self::Of<T>;
}

/// Buffers on a Vulkan device (the handle shares the device).
pub struct OnDevice(pub Gpu);

impl Storage for OnDevice {
    type Of<T: Pod> = wgpu::Buffer;
    fn zeroed<T: Pod>(&mut self, name: &'static str, count: usize) -> wgpu::Buffer {
        self.0.storage_zeroed::<T>(name, count)
    }
    fn copy_of<T: Pod>(&mut self, name: &'static str, data: &[T]) -> wgpu::Buffer {
        self.0.storage_from(name, data)
    }
}

/// Buffers in host memory (the CPU backend).
pub struct OnHost;

impl Storage for OnHost {
    type Of<T: Pod> = Vec<T>;
    fn zeroed<T: Pod>(&mut self, _name: &'static str, count: usize) -> Vec<T> {
        vec![T::zeroed(); count]
    }
    fn copy_of<T: Pod>(&mut self, _name: &'static str, data: &[T]) -> Vec<T> {
        data.to_vec()
    }
}

/// No buffers: only each one's name and byte size, in layout order.
#[derive(Default)]
pub struct Sizes(pub Vec<(&'static str, u64)>);

impl Storage for Sizes {
    type Of<T: Pod> = ();
    fn zeroed<T: Pod>(&mut self, name: &'static str, count: usize) {
        self.0.push((name, (count * std::mem::size_of::<T>()) as u64));
    }
    fn copy_of<T: Pod>(&mut self, name: &'static str, data: &[T]) {
        self.0.push((name, std::mem::size_of_val(data) as u64));
    }
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
            chain_u: s.zeroed("chain samples", n * dims),
            chains: s.zeroed("chain states", n),
            cand_u: s.zeroed("candidate samples", c * dims),
            cand_depth: s.zeroed("candidate depths", c),
            // The path estimator keeps no subpath vertices (one element: a binding is never empty).
            vertices: s.zeroed(
                "vertices",
                if params.estimator == ESTIMATOR_PATH {
                    1
                } else {
                    c * vertex_slots(params.max_depth) as usize
                },
            ),
            paths: s.zeroed("path infos", c),
            contributions: s.zeroed("contributions", c),
            splats: s.zeroed("splat records", Stage::Splat.invocations(params) as usize),
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
}

impl<S: Storage> SceneBuffers<S> {
    /// The buffers' names, as [`Sizes`] lists them.
    pub const NAMES: [&'static str; 4] = ["BVH nodes", "triangles", "materials", "lights"];

    /// The buffers of `scene`.
    pub fn new(s: &mut S, scene: &SceneData) -> Self {
        Self {
            nodes: s.copy_of(Self::NAMES[0], scene.wide_nodes()),
            triangles: s.copy_of(Self::NAMES[1], &scene.triangles),
            materials: s.copy_of(Self::NAMES[2], &scene.materials),
            lights: s.copy_of(Self::NAMES[3], &scene.lights),
        }
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
    /// The f32 image as bits, rgb per pixel.
    pub image: S::Of<u32>,
    /// Ĩ per pixel, the pixel importance (`crate::render::importance`; ones until the
    /// render sets it).
    pub importance: S::Of<f32>,
}

impl<S: Storage> DeviceBuffers<S> {
    /// The buffers of a render of `scene` with `params`.
    pub fn new(s: &mut S, scene: &SceneData, params: &RenderParams) -> Self {
        Self {
            params: s.copy_of("params", &[*params]),
            iteration: IterationBuffers::new(s, params),
            scene: SceneBuffers::new(s, scene),
            image: s.zeroed("image", (params.width * params.height) as usize * 3),
            importance: s.copy_of("importance", &vec![1.0f32; (params.width * params.height) as usize]),
        }
    }
}

/// A render's buffers on a Vulkan device.
pub type GpuBuffers = DeviceBuffers<OnDevice>;

/// The device buffers of a render, by name, with their byte sizes (for the limits check
/// before allocating, and the memory a render reports).
pub fn buffer_sizes(scene: &SceneData, params: &RenderParams) -> Vec<(&'static str, u64)> {
    let mut sizes = Sizes::default();
    DeviceBuffers::new(&mut sizes, scene, params);
    sizes.0
}

/// Total bytes of a render's device buffers (the CPU backend holds the same, less the image
/// and the scene, which it reads in place).
pub fn device_bytes(scene: &SceneData, params: &RenderParams) -> u64 {
    buffer_sizes(scene, params).iter().map(|(_, bytes)| bytes).sum()
}
