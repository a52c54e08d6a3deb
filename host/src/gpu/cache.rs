//! The driver's compiled kernels kept on disk between runs, where the adapter supports Vulkan
//! pipeline caches (NVIDIA's driver does; lavapipe's holds only a header).

use super::KERNELS_SPV;

/// A wgpu `PipelineCache` and the file it is loaded from and saved to: the driver's compiled
/// kernels, keyed by adapter (vendor, device) and by the kernels module's hash.
pub struct DiskCache {
    /// The cache pipelines are created with.
    pub cache: wgpu::PipelineCache,
    path: std::path::PathBuf,
}

impl DiskCache {
    /// The cache directory: `$SMLT_CACHE_DIR`, else `$XDG_CACHE_HOME/smlt`, else `~/.cache/smlt`.
    fn directory() -> Option<std::path::PathBuf> {
        if let Some(d) = std::env::var_os("SMLT_CACHE_DIR") {
            return Some(d.into());
        }
        if let Some(d) = std::env::var_os("XDG_CACHE_HOME").filter(|d| !d.is_empty()) {
            return Some(std::path::PathBuf::from(d).join("smlt"));
        }
        std::env::var_os("HOME").map(|h| std::path::PathBuf::from(h).join(".cache").join("smlt"))
    }

    /// The cache for this adapter and kernels module, loaded from disk when it was saved before.
    pub fn open(device: &wgpu::Device, info: &wgpu::AdapterInfo) -> Option<Self> {
        let key = wgpu::util::pipeline_cache_key(info)?;
        let module = crate::hash::content_hash(KERNELS_SPV);
        let path = Self::directory()?.join(format!("{key}_{module}.bin"));
        let data = std::fs::read(&path).ok();
        // SAFETY: the data is what `get_data` returned for this adapter key and module (or
        // absent); wgpu and the driver validate its header and fall back to an empty cache.
        let cache = unsafe {
            device.create_pipeline_cache(&wgpu::PipelineCacheDescriptor {
                label: Some("smlt kernels"),
                data: data.as_deref(),
                fallback: true,
            })
        };
        Some(Self { cache, path })
    }

    /// Writes the cache's data to disk (to a temporary file renamed into place); a failure
    /// only costs the next run its compile time, so it is ignored.
    pub fn save(&self) {
        let Some(data) = self.cache.get_data() else { return };
        if std::fs::read(&self.path).ok().as_deref() == Some(&data[..]) {
            return;
        }
        if let Some(dir) = self.path.parent() {
            let _ = std::fs::create_dir_all(dir);
        }
        let tmp = self.path.with_extension(format!("{}.tmp", std::process::id()));
        if std::fs::write(&tmp, &data).is_ok() {
            let _ = std::fs::rename(&tmp, &self.path);
        }
    }
}
