//! The machine's Vulkan adapters: listing them, telling a real GPU from a CPU driver, picking
//! one by index, name or rank, and keeping Mesa's display probe quiet while they are listed.

use super::GpuError;

/// Gives libwayland a valid `XDG_RUNTIME_DIR` when the environment has none (a machine without
/// a display, a container, a batch job). Mesa's Vulkan device-selection layer looks for a
/// Wayland display while adapters are enumerated, and without that variable libwayland prints
/// `error: XDG_RUNTIME_DIR is invalid or not set in the environment.` — twice, before every
/// render, even one on the CPU backend. With a private, empty directory (mode 0700, as the
/// XDG spec asks) the probe finds no display and says nothing; every other message of the
/// driver still gets through. A valid `XDG_RUNTIME_DIR` is left as it is.
///
/// # Safety
/// Sets an environment variable: call it before any other thread exists.
pub unsafe fn provide_runtime_dir() {
    use std::os::unix::fs::{DirBuilderExt, PermissionsExt};
    let valid = |dir: &std::path::Path| {
        std::fs::metadata(dir).is_ok_and(|m| m.is_dir() && m.permissions().mode() & 0o077 == 0)
    };
    if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| valid(std::path::Path::new(&d))) {
        return;
    }
    // SAFETY: geteuid has no preconditions.
    let uid = unsafe { libc::geteuid() };
    let dir = std::env::temp_dir().join(format!("smlt-runtime-{uid}"));
    let _ = std::fs::DirBuilder::new().mode(0o700).create(&dir);
    if valid(&dir) {
        // SAFETY: the caller guarantees that no other thread exists.
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
    }
}

/// The Vulkan adapters of this machine, in enumeration order (what `--adapter INDEX` counts).
pub fn adapters() -> Vec<wgpu::Adapter> {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = wgpu::Backends::VULKAN;
    let instance = wgpu::Instance::new(desc);
    pollster::block_on(instance.enumerate_adapters(wgpu::Backends::VULKAN))
}

/// Whether an adapter is a real GPU (discrete or integrated), not a CPU driver like lavapipe.
pub fn is_real_gpu(info: &wgpu::AdapterInfo) -> bool {
    matches!(info.device_type, wgpu::DeviceType::DiscreteGpu | wgpu::DeviceType::IntegratedGpu)
}

/// Picks an adapter: the one at index `wanted`, else the first whose name contains `wanted`
/// (case-insensitive), else — with no `wanted` — the best by type (discrete, integrated,
/// virtual, CPU).
pub fn choose_adapter(adapters: Vec<wgpu::Adapter>, wanted: Option<&str>) -> Result<wgpu::Adapter, GpuError> {
    let Some(wanted) = wanted else {
        return adapters
            .into_iter()
            .min_by_key(|a| rank(a.get_info().device_type))
            .ok_or(GpuError::NoAdapter);
    };
    let available = adapters
        .iter()
        .enumerate()
        .map(|(i, a)| format!("{i}: {}", a.get_info().name))
        .collect::<Vec<_>>()
        .join(", ");
    let by_index = wanted.parse::<usize>().ok().filter(|&i| i < adapters.len());
    let lower = wanted.to_lowercase();
    let found = match by_index {
        Some(i) => Some(i),
        None => adapters.iter().position(|a| a.get_info().name.to_lowercase().contains(&lower)),
    };
    match found {
        Some(i) => Ok(adapters.into_iter().nth(i).expect("index in range")),
        None if adapters.is_empty() => Err(GpuError::NoAdapter),
        None => Err(GpuError::NoSuchAdapter {
            wanted: wanted.to_string(),
            available: if available.is_empty() { "none".into() } else { available },
        }),
    }
}

/// Preference among adapter types: a real GPU first, lavapipe (a CPU device) last.
fn rank(device_type: wgpu::DeviceType) -> u32 {
    match device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    }
}
