//! Helpers shared by the integration tests.

#![allow(dead_code)]

pub mod rng;
pub mod scenes;
pub mod stats;

use smlt::gpu::Gpu;

/// Opens the Vulkan device for a GPU test. Without one the test fails when `CI=true` (CI has
/// lavapipe, so a missing device is a broken set-up), and elsewhere is skipped with the reason.
pub fn gpu_or_skip(test: &str) -> Option<Gpu> {
    match Gpu::new() {
        Ok(gpu) => {
            println!("{test}: adapter {}", gpu.describe());
            Some(gpu)
        }
        Err(e) if std::env::var("CI").as_deref() == Ok("true") => {
            panic!("{test}: CI=true and no usable Vulkan device: {e}")
        }
        Err(e) => {
            eprintln!("SKIPPED {test}: no usable Vulkan device: {e}");
            None
        }
    }
}
