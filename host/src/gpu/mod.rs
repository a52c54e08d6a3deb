//! The Vulkan device through wgpu: choosing an adapter, loading the rust-gpu SPIR-V module,
//! building compute pipelines and moving buffers to and from the device.

use std::borrow::Cow;

mod adapters;
mod cache;
mod spirv;

pub use adapters::{adapters, choose_adapter, is_real_gpu, provide_runtime_dir};
use cache::DiskCache;
pub use spirv::{spirv_entry_points, spirv_interfaces, EntryInterface};

/// The kernels compiled by `build.rs` with rust-gpu: one module, every `<pass>_cs` entry point.
pub const KERNELS_SPV: &[u8] = include_bytes!(env!("SMLT_KERNELS_SPV"));

/// What can go wrong while getting or using the device, each with a message that names it.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No Vulkan adapter at all: no driver, or no loader.
    #[error(
        "no Vulkan adapter found: install a Vulkan driver, or Mesa's CPU driver lavapipe \
         (`apt-get install mesa-vulkan-drivers libvulkan1`, which scripts/setup.sh does), \
         or render with --device cpu"
    )]
    NoAdapter,
    /// `--adapter` named no adapter.
    #[error(
        "no Vulkan adapter matches --adapter {wanted}; the adapters are: {available} (see `smlt devices`)"
    )]
    NoSuchAdapter {
        /// What the user asked for.
        wanted: String,
        /// The adapters there are, as index: name.
        available: String,
    },
    /// The adapter refused to create a device.
    #[error("the Vulkan adapter {adapter} could not create a device: {source}")]
    RequestDevice {
        /// The adapter's name.
        adapter: String,
        /// wgpu's reason.
        source: wgpu::RequestDeviceError,
    },
    /// The adapter cannot take SPIR-V unchanged and naga's translation rejected the module.
    #[error(
        "the Vulkan adapter {adapter} lacks SPIR-V passthrough and naga cannot translate the \
         kernels ({reason}); use a driver with passthrough support (lavapipe, NVIDIA) or --device cpu"
    )]
    ShaderModule {
        /// The adapter's name.
        adapter: String,
        /// naga's message, on one line.
        reason: String,
    },
    /// The compiled module and `kernels::ENTRY_POINTS` disagree (a build problem).
    #[error("the kernels module's entry points {found:?} are not the declared {declared:?}")]
    EntryPoints {
        /// What the SPIR-V holds.
        found: Vec<String>,
        /// What `kernels::ENTRY_POINTS` declares.
        declared: Vec<String>,
    },
    /// The driver or wgpu rejected a pipeline.
    #[error("the device rejected kernel {entry}: {message}")]
    Pipeline {
        /// The kernel's entry-point name (e.g. `trace_cs`).
        entry: String,
        /// wgpu's validation message, on one line.
        message: String,
    },
    /// A stage's declared binding has no buffer of its name and element type (a build
    /// problem: `kernels::stage` and the backend's buffers disagree).
    #[error("kernel {entry} binds {binding}, but {problem}")]
    Binding {
        /// The kernel's entry-point name.
        entry: String,
        /// The binding's name, as the stage declares it.
        binding: String,
        /// What is wrong with it.
        problem: String,
    },
    /// A buffer could not be read back.
    #[error("reading a buffer back from the device failed: {0}")]
    Readback(String),
    /// Waiting for submitted work failed (the device was lost, or timed out).
    #[error("waiting for the device to finish its work failed: {0}")]
    Wait(String),
}

/// How the SPIR-V module reached the driver.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShaderPath {
    /// Handed to the driver unchanged (wgpu's PASSTHROUGH_SHADERS).
    Passthrough,
    /// Translated by naga's SPIR-V front end.
    Naga,
}

/// An open device with the kernels module loaded (cloning shares the device).
#[derive(Clone)]
pub struct Gpu {
    /// The adapter's name, type and driver.
    pub info: wgpu::AdapterInfo,
    /// The device's limits (what we asked for: the adapter's own).
    pub limits: wgpu::Limits,
    /// The optional features the device was opened with (passthrough, float atomics,
    /// timestamp queries), where the adapter has them.
    pub features: wgpu::Features,
    #[allow(missing_docs)] // wgpu's device and its queue: named for what they are
    pub device: wgpu::Device,
    #[allow(missing_docs)]
    pub queue: wgpu::Queue,
    /// The kernels module.
    pub module: wgpu::ShaderModule,
    /// How the module was loaded.
    pub shader_path: ShaderPath,
    /// Pipelines already built, by entry point and binding signature: a driver compiles a
    /// large kernel in seconds, and the bench builds the same passes for many methods.
    pipelines: std::sync::Arc<std::sync::Mutex<Pipelines>>,
    /// The driver's pipeline cache, kept on disk between runs where the adapter supports it.
    disk_cache: Option<std::sync::Arc<DiskCache>>,
}

type Pipelines =
    std::collections::HashMap<(String, Vec<Vec<bool>>), (wgpu::ComputePipeline, Vec<wgpu::BindGroupLayout>)>;

impl Gpu {
    /// Opens the best Vulkan adapter (discrete, integrated, virtual, then CPU such as lavapipe)
    /// and loads the kernels, handing the SPIR-V to the driver unchanged where the adapter
    /// allows it and through naga otherwise.
    pub fn new() -> Result<Self, GpuError> {
        Self::open(None)
    }

    /// Opens the adapter `wanted` names ([`choose_adapter`]: an index or part of a name), or
    /// the best one, and loads the kernels.
    pub fn open(wanted: Option<&str>) -> Result<Self, GpuError> {
        let adapter = choose_adapter(adapters(), wanted)?;
        let info = adapter.get_info();
        let limits = adapter.limits();
        let wanted = wgpu::Features::PASSTHROUGH_SHADERS
            | wgpu::Features::SHADER_FLOAT32_ATOMIC
            | wgpu::Features::TIMESTAMP_QUERY
            | wgpu::Features::PIPELINE_CACHE;
        let features = adapter.features() & wanted;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("smlt"),
            required_features: features,
            required_limits: limits.clone(),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|source| GpuError::RequestDevice { adapter: info.name.clone(), source })?;
        let words = wgpu::util::make_spirv_raw(KERNELS_SPV);
        // A pipeline for a name the module lacks loses the device under passthrough, so check
        // the names before handing the module over.
        let mut found = spirv_entry_points(&words);
        let mut declared: Vec<String> = kernels::ENTRY_POINTS.iter().map(|s| s.to_string()).collect();
        found.sort();
        declared.sort();
        if found != declared {
            return Err(GpuError::EntryPoints { found, declared });
        }
        let force_naga = std::env::var("SMLT_SHADER_PATH").as_deref() == Ok("naga");
        let (module, shader_path) = if features.contains(wgpu::Features::PASSTHROUGH_SHADERS) && !force_naga {
            // SAFETY: the module is rust-gpu's output, validated by spirv-val at build time, and
            // every pipeline is created with an explicit layout that matches its bindings.
            let module = unsafe {
                device.create_shader_module_passthrough(wgpu::ShaderModuleDescriptorPassthrough {
                    label: Some("kernels"),
                    entry_points: kernels::ENTRY_POINTS
                        .iter()
                        .map(|name| wgpu::PassthroughShaderEntryPoint {
                            name: Cow::Borrowed(*name),
                            workgroup_size: (kernels::WORKGROUP_SIZE, 1, 1),
                        })
                        .collect(),
                    spirv: Some(Cow::Borrowed(&words)),
                    ..Default::default()
                })
            };
            (module, ShaderPath::Passthrough)
        } else {
            let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("kernels"),
                source: wgpu::ShaderSource::SpirV(words.clone()),
            });
            if let Some(e) = pollster::block_on(scope.pop()) {
                let reason = format!("{e}").split_whitespace().collect::<Vec<_>>().join(" ");
                return Err(GpuError::ShaderModule { adapter: info.name.clone(), reason });
            }
            (module, ShaderPath::Naga)
        };
        let disk_cache = if features.contains(wgpu::Features::PIPELINE_CACHE) {
            DiskCache::open(&device, &info).map(std::sync::Arc::new)
        } else {
            None
        };
        Ok(Self {
            info,
            limits,
            features,
            device,
            queue,
            module,
            shader_path,
            pipelines: Default::default(),
            disk_cache,
        })
    }

    /// A one-line description of the device: name, type, driver, and how kernels are loaded.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {} {}; kernels via {:?})",
            self.info.name, self.info.device_type, self.info.driver, self.info.driver_info, self.shader_path
        )
    }

    /// A compute pipeline for entry point `entry` whose descriptor sets 0, 1, … hold storage
    /// buffers at bindings 0.., `sets[s][i]` saying whether the kernel only reads binding `i` of
    /// set `s`; with the sets' layouts.
    pub fn pipeline(
        &self,
        entry: &str,
        sets: &[Vec<bool>],
    ) -> Result<(wgpu::ComputePipeline, Vec<wgpu::BindGroupLayout>), GpuError> {
        let key = (entry.to_string(), sets.to_vec());
        if let Some(hit) = self.pipelines.lock().expect("pipeline cache").get(&key) {
            return Ok(hit.clone());
        }
        let built = self.build_pipeline(entry, sets)?;
        self.pipelines.lock().expect("pipeline cache").insert(key, built.clone());
        Ok(built)
    }

    fn build_pipeline(
        &self,
        entry: &str,
        sets: &[Vec<bool>],
    ) -> Result<(wgpu::ComputePipeline, Vec<wgpu::BindGroupLayout>), GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let set_layouts: Vec<wgpu::BindGroupLayout> = sets
            .iter()
            .map(|read_only| {
                let entries: Vec<wgpu::BindGroupLayoutEntry> = read_only
                    .iter()
                    .enumerate()
                    .map(|(i, &read_only)| wgpu::BindGroupLayoutEntry {
                        binding: i as u32,
                        visibility: wgpu::ShaderStages::COMPUTE,
                        ty: wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Storage { read_only },
                            has_dynamic_offset: false,
                            min_binding_size: None,
                        },
                        count: None,
                    })
                    .collect();
                self.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some(entry),
                    entries: &entries,
                })
            })
            .collect();
        let layout_refs: Vec<Option<&wgpu::BindGroupLayout>> = set_layouts.iter().map(Some).collect();
        let layout = self.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(entry),
            bind_group_layouts: &layout_refs,
            immediate_size: 0,
        });
        let pipeline = self.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&layout),
            module: &self.module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: self.disk_cache.as_ref().map(|c| &c.cache),
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            let message = format!("{e}").split_whitespace().collect::<Vec<_>>().join(" ");
            return Err(GpuError::Pipeline { entry: entry.to_string(), message });
        }
        Ok((pipeline, set_layouts))
    }

    /// Saves the driver's pipeline cache to disk (where the adapter has one), so that the next
    /// run on this machine skips compiling the kernels.
    pub fn save_pipeline_cache(&self) {
        if let Some(c) = &self.disk_cache {
            c.save();
        }
    }

    /// Waits until the device has finished everything submitted.
    pub fn wait(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Wait(e.to_string()))
    }

    /// A storage buffer holding `data` (at least 4 bytes, as Vulkan wants no empty buffers).
    pub fn storage_from<T: bytemuck::Pod>(&self, label: &str, data: &[T]) -> wgpu::Buffer {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let padded;
        let contents = if bytes.is_empty() {
            padded = [0u8; 4];
            &padded[..]
        } else {
            bytes
        };
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: contents.len().next_multiple_of(4) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.queue.write_buffer(&buffer, 0, contents);
        buffer
    }

    /// A zeroed storage buffer of `len` elements of `T`.
    pub fn storage_zeroed<T: bytemuck::Pod>(&self, label: &str, len: usize) -> wgpu::Buffer {
        self.storage_from(label, &vec![T::zeroed(); len])
    }

    /// A bind group with `buffers` at bindings 0...
    pub fn bind(&self, layout: &wgpu::BindGroupLayout, buffers: &[&wgpu::Buffer]) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry { binding: i as u32, resource: b.as_entire_binding() })
            .collect();
        self.device.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout, entries: &entries })
    }

    /// Records one dispatch of `threads` invocations of a 1-D kernel with workgroups of
    /// `kernels::WORKGROUP_SIZE` and `bind_groups` at sets 0, 1, …, in a compute pass of its own
    /// that writes `timestamps`, if any.
    pub fn dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &wgpu::ComputePipeline,
        bind_groups: &[wgpu::BindGroup],
        threads: u32,
        timestamps: Option<wgpu::ComputePassTimestampWrites>,
    ) {
        let groups = threads.div_ceil(kernels::WORKGROUP_SIZE);
        let mut pass = encoder
            .begin_compute_pass(&wgpu::ComputePassDescriptor { label: None, timestamp_writes: timestamps });
        pass.set_pipeline(pipeline);
        for (set, group) in bind_groups.iter().enumerate() {
            pass.set_bind_group(set as u32, group, &[]);
        }
        pass.dispatch_workgroups(groups, 1, 1);
    }

    /// Copies `len` elements of `T` out of `buffer` (after the work submitted so far).
    pub fn read<T: bytemuck::Pod>(&self, buffer: &wgpu::Buffer, len: usize) -> Result<Vec<T>, GpuError> {
        let size = (len * std::mem::size_of::<T>()).max(4) as u64;
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
        self.queue.submit([encoder.finish()]);
        let slice = staging.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        rx.recv()
            .map_err(|e| GpuError::Readback(e.to_string()))?
            .map_err(|e| GpuError::Readback(e.to_string()))?;
        let view = slice.get_mapped_range().map_err(|e| GpuError::Readback(e.to_string()))?;
        let out = bytemuck::cast_slice::<u8, T>(&view[..len * std::mem::size_of::<T>()]).to_vec();
        drop(view);
        staging.unmap();
        Ok(out)
    }
}
