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

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    /// Every declaration numbers its bindings 0, 1, … in order with no gap (what the entry point
    /// and the host's binding list both follow), writes something and reads something, and
    /// names each binding once.
    #[test]
    fn every_declaration_numbers_its_bindings_in_order() {
        for k in KERNELS {
            for (i, b) in k.bindings.iter().enumerate() {
                assert_eq!((b.set, b.binding), (0, i as u32), "{}: {}", k.entry_point, b.name);
                assert!(
                    k.bindings[i + 1..].iter().all(|c| c.name != b.name),
                    "{}: {} twice",
                    k.entry_point,
                    b.name
                );
            }
            for (i, b) in stage::SCENE_BINDINGS.iter().enumerate() {
                assert_eq!((b.set, b.binding), (stage::SCENE_SET, i as u32), "scene: {}", b.name);
            }
            let all = k.interface();
            assert!(all.iter().any(|(_, _, w)| *w), "{} writes nothing", k.entry_point);
            assert!(all.iter().any(|(_, _, w)| !*w), "{} reads nothing", k.entry_point);
        }
        let mut names: std::vec::Vec<&str> = KERNELS.iter().map(|k| k.entry_point).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), KERNELS.len(), "an entry point twice");
    }
}
