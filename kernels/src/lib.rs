//! smlt's compute kernels. Each pass is one file: an ordinary Rust function over slices and an
//! invocation index (the body, which the host also runs on CPU threads for `--device cpu` and
//! for the GPU-vs-CPU difftests), and a thin `#[spirv(compute)]` entry point `<pass>_cs` that
//! only unpacks the bindings and calls it. All math lives in the `shared` crate.
#![cfg_attr(target_arch = "spirv", no_std)]
#![deny(missing_docs)]

pub mod connect;
pub mod mutate;
pub mod raycast;
pub mod reference;
pub mod select;
pub mod selftest;
pub mod splat;
pub mod trace;

/// Threads per workgroup of every 1-D kernel.
pub const WORKGROUP_SIZE: u32 = 64;

/// Every entry point of the module, for the host to declare when it hands the SPIR-V to the
/// driver unchanged.
pub const ENTRY_POINTS: &[&str] = &[
    "selftest_cs",
    "mutate_cs",
    "trace_cs",
    "connect_cs",
    "select_cs",
    "splat_cs",
    "reference_cs",
    "raycast_cs",
];
