//! smlt's compute kernels. Each pass is one file: its declaration ([`stage!`]: the bindings,
//! from which its `Io` struct, its `#[spirv(compute)]` entry point `<pass>_cs`, the host's
//! binding list and the CPU call are made) and its body, an ordinary Rust function of an
//! invocation index and that `Io` (which the host also runs on CPU threads for `--device cpu`
//! and for the GPU-vs-CPU difftests). All math lives in the `shared` crate.
#![cfg_attr(target_arch = "spirv", no_std)]
#![deny(missing_docs)]

#[macro_use]
pub mod stage;

pub mod connect;
pub mod mutate;
pub mod path_tracer;
pub mod raycast;
pub mod select;
pub mod selftest;
pub mod splat;
pub mod trace;

/// Threads per workgroup of every 1-D kernel.
pub const WORKGROUP_SIZE: u32 = 64;

/// Every kernel of the module: its entry point, its own bindings (set 0), and whether it binds
/// the scene (set 1), as each declaration gives them.
pub const KERNELS: &[stage::Kernel] = &[
    stage::Kernel::of(selftest::ENTRY_POINT, selftest::BINDINGS, selftest::BINDS_SCENE),
    stage::Kernel::of(mutate::ENTRY_POINT, mutate::BINDINGS, mutate::BINDS_SCENE),
    stage::Kernel::of(trace::ENTRY_POINT, trace::BINDINGS, trace::BINDS_SCENE),
    stage::Kernel::of(connect::ENTRY_POINT, connect::BINDINGS, connect::BINDS_SCENE),
    stage::Kernel::of(select::ENTRY_POINT, select::BINDINGS, select::BINDS_SCENE),
    stage::Kernel::of(splat::ENTRY_POINT, splat::BINDINGS, splat::BINDS_SCENE),
    stage::Kernel::of(path_tracer::ENTRY_POINT, path_tracer::BINDINGS, path_tracer::BINDS_SCENE),
    stage::Kernel::of(raycast::ENTRY_POINT, raycast::BINDINGS, raycast::BINDS_SCENE),
];

/// Every entry point of the module, for the host to declare when it hands the SPIR-V to the
/// driver unchanged.
pub const ENTRY_POINTS: [&str; KERNELS.len()] = {
    let mut names = [""; KERNELS.len()];
    let mut i = 0;
    while i < KERNELS.len() {
        names[i] = KERNELS[i].entry_point;
        i += 1;
    }
    names
};
