//! `smlt devices`: the Vulkan adapters, the CPU backend, and what `--device auto` picks.

/// Runs `smlt devices`.
pub fn run() -> anyhow::Result<()> {
    let adapters = smlt::gpu::adapters();
    if adapters.is_empty() {
        println!("no Vulkan adapter (install a Vulkan driver, or lavapipe: scripts/setup.sh)");
    }
    for (i, a) in adapters.iter().enumerate() {
        let info = a.get_info();
        println!(
            "{i}: {} ({:?}, {:?}, {} {}){}",
            info.name,
            info.device_type,
            info.backend,
            info.driver,
            info.driver_info,
            if smlt::gpu::is_real_gpu(&info) { "" } else { " — not a GPU" }
        );
    }
    println!("cpu: the CPU backend, {} threads (--device cpu)", smlt::render::cpu::default_threads());
    let auto = if adapters.iter().any(|a| smlt::gpu::is_real_gpu(&a.get_info())) {
        "the best GPU above"
    } else {
        "cpu"
    };
    println!("--device auto chooses: {auto}");
    Ok(())
}
