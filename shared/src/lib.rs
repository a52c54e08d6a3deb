//! Everything smlt computes, written once and compiled twice: for the host (std, unit tests,
//! `--device cpu`) and for SPIR-V (rust-gpu kernels). Structs that cross the host/device
//! boundary are `#[repr(C)]` and `bytemuck::Pod`; every formula from the paper is one
//! documented function with its tests beside it.
//!
//! One concept a file:
//! - [`rng`]: the counter-based random numbers, keyed by (seed, chain, iteration, dimension);
//! - [`mutation`]: Kelemen et al.'s small and large steps in primary sample space;
//! - [`acceptance`]: the Metropolis–Hastings acceptance `a(y|x) = min(1, c(y)/c(x))`;
//! - [`normalisation`]: the image normalisation b, from the bootstrap and every large step;
//! - [`discrete`]: drawing an index in proportion to weights; [`element`]: a buffer read
//!   without a panic path;
//! - [`tree`]: the speculative mutation tree (the paper's §4, Eq. 2 and Eq. 3 generalised);
//! - [`reject_chain`]: the reject chain of Byrd et al. (the paper's §3.3);
//! - [`layout`]: SoA indexing and the packed `float4` contribution;
//! - [`camera`], [`bsdf`] (with [`microfacet`]'s GGX and the layers of [`sheen`] and [`clearcoat`]), [`light`], [`punctual`], [`environment`] (both from outside the scene: [`distant`]),
//!   [`triangle`]: the scene primitives, and
//!   [`color`]'s luminance;
//! - [`texture`]: texture lookups from one texel buffer; [`surface`]: the material and the
//!   normals at a surface point, its textures applied; [`normals`]: geometric and shading
//!   normals, and the adjoint's cosine;
//! - [`params`]: what every dispatch of the chains' stages knows;
//! - [`ray_caster`]: the one seam between the path code and ray casting (and the ray origin
//!   offset every path code uses), and [`cwbvh`], the
//!   device's caster (a compressed 8-wide BVH), and [`cutout`], the cut-outs (glTF's MASK and
//!   BLEND) every caster lets rays through; [`scene`]: what the kernels read of a scene;
//! - [`mmlt`]: Multiplexed MLT path sampling (the trace and connect stages);
//! - [`path_tracer`]: the path tracer (`pt`, and the ground truth), which shares no path code
//!   with [`mmlt`];
//! - [`pssmlt`]: Metropolis chains over the path tracer's estimate (the path estimator);
//! - [`rays`]: ray queries as data, for the bench's bare ray throughput.
#![cfg_attr(target_arch = "spirv", no_std)]
#![deny(missing_docs)]

pub mod acceptance;
pub mod bsdf;
pub mod camera;
pub mod clearcoat;
pub mod color;
pub mod cutout;
pub mod cwbvh;
pub mod discrete;
pub mod distant;
pub mod element;
pub mod environment;
pub mod float;
pub mod layout;
pub mod light;
pub mod metallic_roughness;
pub mod microfacet;
pub mod mmlt;
pub mod mutation;
pub mod normal_map;
pub mod normalisation;
pub mod normals;
pub mod params;
pub mod path_tracer;
pub mod pssmlt;
pub mod punctual;
pub mod ray_caster;
pub mod rays;
pub mod reject_chain;
pub mod rng;
pub mod scene;
pub mod sheen;
pub mod surface;
#[cfg(all(test, not(target_arch = "spirv")))]
mod testing;
pub mod texture;
pub mod tree;
pub mod triangle;

pub use glam;
