//! Headless wgpu: getting a device, running a validated compute shader, and
//! reading results back. Getting a device ([`Gpu::new`]) is separate from the
//! work done with it, so tests and batch commands share one device.
//!
//! wgpu's default handler panics on uncaptured errors; every call that can
//! fail runs inside an error scope and becomes a [`GpuError`].

pub mod eval;
pub mod pixels;
pub mod render;
pub mod sphere;

use std::time::Duration;

/// GPU failures.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter: no Vulkan driver installed.
    #[error("no GPU adapter found (no Vulkan driver?)\n  = help: without a GPU, install Mesa's CPU Vulkan driver: sudo apt-get install -y mesa-vulkan-drivers libvulkan1")]
    NoAdapter,
    /// The adapter refused to give a device.
    #[error("cannot open the GPU device '{adapter}': {message}")]
    NoDevice {
        /// Adapter name.
        adapter: String,
        /// Why.
        message: String,
    },
    /// A request beyond the device's limits.
    #[error("{0}")]
    Limits(String),
    /// A wgpu validation / out-of-memory / internal error.
    #[error("GPU error during {during}: {message}")]
    Device {
        /// What isotrace was doing.
        during: &'static str,
        /// wgpu's message.
        message: String,
    },
}

/// Which device the numbers came from.
#[derive(Debug, Clone, serde::Serialize)]
pub struct DeviceInfo {
    /// Adapter name, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub name: String,
    /// Driver name and version.
    pub driver: String,
    /// Backend (Vulkan, …).
    pub backend: String,
    /// Device type (Cpu, DiscreteGpu, …).
    pub device_type: String,
}

/// A headless device and queue.
pub struct Gpu {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// What it is.
    pub info: DeviceInfo,
    /// Largest storage buffer binding.
    pub max_storage_binding: u64,
    /// Nanoseconds per timestamp tick, when timestamp queries work.
    pub timestamp_period: Option<f32>,
    /// Storage buffers can be mapped directly (CPU devices).
    pub map_in_place: bool,
}

impl Gpu {
    /// Opens the default adapter (honouring `WGPU_ADAPTER_NAME` / `WGPU_BACKEND`
    /// without panicking when they match nothing).
    pub fn new() -> Result<Gpu, GpuError> {
        // Mesa's device-select layer complains on stderr without this.
        if std::env::var_os("XDG_RUNTIME_DIR").is_none() && std::env::var_os("NODEVICE_SELECT").is_none() {
            // SAFETY: called before any other thread of ours touches the environment.
            unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
        }
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        if std::env::var_os("WGPU_BACKEND").is_none() {
            desc.backends = wgpu::Backends::VULKAN;
        }
        let instance = wgpu::Instance::new(desc);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            ..Default::default()
        }))
        .map_err(|_| GpuError::NoAdapter)?;
        let ai = adapter.get_info();
        let info = DeviceInfo {
            name: ai.name.clone(),
            driver: format!("{} {}", ai.driver, ai.driver_info).trim().to_string(),
            backend: format!("{:?}", ai.backend),
            device_type: format!("{:?}", ai.device_type),
        };
        let limits = adapter.limits();
        let want_ts = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut features = if want_ts { wgpu::Features::TIMESTAMP_QUERY } else { wgpu::Features::empty() };
        // On a CPU device the kernels' output can be mapped in place instead
        // of being copied to a read-back buffer first (30 MB per 1024² frame).
        let map_in_place = ai.device_type == wgpu::DeviceType::Cpu && adapter.features().contains(wgpu::Features::MAPPABLE_PRIMARY_BUFFERS);
        if map_in_place {
            features |= wgpu::Features::MAPPABLE_PRIMARY_BUFFERS;
        }
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("isotrace"),
            required_features: features,
            required_limits: limits.clone(),
            ..Default::default()
        }))
        .map_err(|e| GpuError::NoDevice { adapter: ai.name.clone(), message: e.to_string() })?;
        device.on_uncaptured_error(std::sync::Arc::new(|e| {
            eprintln!("isotrace: uncaptured GPU error: {e}");
        }));
        let timestamp_period = want_ts.then(|| queue.get_timestamp_period());
        Ok(Gpu { device, queue, info, max_storage_binding: limits.max_storage_buffer_binding_size as u64, timestamp_period, map_in_place })
    }

    /// Runs `f` inside a validation + out-of-memory error scope.
    pub fn scoped<T>(&self, during: &'static str, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let val = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let r = f();
        let e1 = pollster::block_on(val.pop());
        let e2 = pollster::block_on(oom.pop());
        match e1.or(e2) {
            Some(e) => Err(GpuError::Device { during, message: e.to_string() }),
            None => Ok(r),
        }
    }

    /// Creates a compute pipeline from WGSL that has passed naga validation.
    pub fn pipeline(&self, label: &str, wgsl: &str) -> Result<wgpu::ComputePipeline, GpuError> {
        Ok(self.pipelines(label, wgsl, &["main"])?.remove(0))
    }

    /// One pipeline per entry point of one validated WGSL module, all with
    /// `layout` (or each with its own derived layout when `None`).
    pub fn pipelines(&self, label: &str, wgsl: &str, entries: &[&str]) -> Result<Vec<wgpu::ComputePipeline>, GpuError> {
        self.pipelines_with_layout(label, wgsl, entries, None)
    }

    /// See [`Gpu::pipelines`].
    pub fn pipelines_with_layout(
        &self,
        label: &str,
        wgsl: &str,
        entries: &[&str],
        layout: Option<&wgpu::PipelineLayout>,
    ) -> Result<Vec<wgpu::ComputePipeline>, GpuError> {
        self.scoped("shader compilation", || {
            let module = self.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(wgsl.into()),
            });
            entries
                .iter()
                .map(|e| {
                    self.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                        label: Some(label),
                        layout,
                        module: &module,
                        entry_point: Some(e),
                        compilation_options: Default::default(),
                        cache: None,
                    })
                })
                .collect()
        })
    }

    /// Blocks until the queue is idle.
    pub fn wait(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(Duration::from_secs(600)) })
            .map(|_| ())
            .map_err(|e| GpuError::Device { during: "waiting for the GPU", message: e.to_string() })
    }

    /// Copies `size` bytes of `src` into a mappable buffer and reads them.
    pub fn read_buffer(&self, encoder: &mut wgpu::CommandEncoder, src: &wgpu::Buffer, size: u64) -> wgpu::Buffer {
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("read-back"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        encoder.copy_buffer_to_buffer(src, 0, &staging, 0, size);
        staging
    }

    /// Maps a read-back buffer made by [`Gpu::read_buffer`] and hands its
    /// bytes to `f` without copying them first.
    pub fn map_read_with<T>(&self, staging: &wgpu::Buffer, f: impl FnOnce(&[u8]) -> T) -> Result<T, GpuError> {
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        let err = |m: String| GpuError::Device { during: "reading results", message: m };
        rx.recv().map_err(|e| err(e.to_string()))?.map_err(|e| err(e.to_string()))?;
        let view = staging.get_mapped_range(..).map_err(|e| err(e.to_string()))?;
        let out = f(&view);
        drop(view);
        staging.unmap();
        Ok(out)
    }

    /// Maps a read-back buffer made by [`Gpu::read_buffer`] after submission.
    pub fn map_read(&self, staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        rx.recv()
            .map_err(|e| GpuError::Device { during: "reading results", message: e.to_string() })?
            .map_err(|e| GpuError::Device { during: "reading results", message: e.to_string() })?;
        let view = staging
            .get_mapped_range(..)
            .map_err(|e| GpuError::Device { during: "reading results", message: e.to_string() })?;
        let bytes = view.to_vec();
        drop(view);
        staging.unmap();
        Ok(bytes)
    }
}

/// The output buffer of a tiled kernel and its read-back copy, kept between
/// frames and tiles of the same size (allocating ~30 MB per frame cost
/// ~15 ms on lavapipe).
#[derive(Default)]
pub struct TileBuffers(std::sync::Mutex<Option<(u64, wgpu::Buffer, wgpu::Buffer)>>);

impl TileBuffers {
    /// The output buffer and the buffer to map: the same one when the
    /// device maps storage buffers in place.
    fn get(&self, gpu: &Gpu, size: u64) -> (wgpu::Buffer, wgpu::Buffer) {
        let d = &gpu.device;
        let mut cache = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if cache.as_ref().is_none_or(|(s, _, _)| *s != size) {
            let map = if gpu.map_in_place { wgpu::BufferUsages::MAP_READ } else { wgpu::BufferUsages::COPY_SRC };
            let out = d.create_buffer(&wgpu::BufferDescriptor {
                label: Some("pixels"),
                size,
                usage: wgpu::BufferUsages::STORAGE | map,
                mapped_at_creation: false,
            });
            let staging = if gpu.map_in_place {
                out.clone()
            } else {
                d.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("pixels read-back"),
                    size,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            };
            *cache = Some((size, out, staging));
        }
        let (_, out, staging) = cache.as_ref().expect("just filled");
        (out.clone(), staging.clone())
    }

}

/// A tile pass that runs one invocation per 8×8 pixel tile (8×8 tiles a
/// workgroup) before the per-pixel kernel and queues the tiles the kernel
/// must run: the kernel is then dispatched indirectly with the counts the
/// pass leaves at the start of `list` (reset to (0, 1, 1, 0) first). Both
/// pipelines share the bind group layout.
pub type PrePass<'a> = (&'a wgpu::ComputePipeline, &'a wgpu::Buffer);

/// One timed dispatch of a per-pixel kernel over a `tw × th` tile: the
/// uniforms at binding 0 (a read-only storage buffer: see bisect.wgsl), the
/// pixel records (`record` bytes each) at binding 1, `extra` bindings after
/// them, workgroups of `group` 8×8 pixel tiles
/// stacked in z (the kernel maps them to pixels), optionally after a
/// `pre` pass in the same submission. `unpack` gets the records straight
/// from the mapped read-back buffer. Returns the GPU milliseconds of both
/// passes and of the `pre` pass alone (timestamp queries when the device
/// has them, else the submit-to-read-back wall time and 0).
#[allow(clippy::too_many_arguments)]
pub fn dispatch_tile(
    gpu: &Gpu,
    pipeline: &wgpu::ComputePipeline,
    pre: Option<PrePass<'_>>,
    label: &'static str,
    uniforms: &[u8],
    extra: &[(u32, &wgpu::Buffer)],
    buffers: &TileBuffers,
    (tw, th, record, group): (u32, u32, u64, u32),
    unpack: impl FnOnce(&[u8]),
) -> Result<(f64, f64), GpuError> {
    use wgpu::util::DeviceExt;
    let d = &gpu.device;
    let size = tw as u64 * th as u64 * record;
    let ts = gpu.timestamp_period.map(|_| {
        let set = d.create_query_set(&wgpu::QuerySetDescriptor { label: Some(label), ty: wgpu::QueryType::Timestamp, count: 3 });
        let resolve = d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamps"),
            size: 24,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        (set, resolve)
    });
    let last = if pre.is_some() { 2 } else { 1 };
    let t0 = std::time::Instant::now();
    let (staging, ts_staging) = gpu.scoped(label, || {
        let ubuf = d.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents: uniforms, usage: wgpu::BufferUsages::STORAGE });
        let (out, staging) = buffers.get(gpu, size);
        let mut entries = vec![
            wgpu::BindGroupEntry { binding: 0, resource: ubuf.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: out.as_entire_binding() },
        ];
        entries.extend(extra.iter().map(|(b, buf)| wgpu::BindGroupEntry { binding: *b, resource: buf.as_entire_binding() }));
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(label), layout: &pipeline.get_bind_group_layout(0), entries: &entries });
        if let Some((_, indirect)) = pre {
            gpu.queue.write_buffer(indirect, 0, bytemuck::cast_slice(&[0u32, 1, 1, 0]));
        }
        let mut enc = d.create_command_encoder(&Default::default());
        // Query 0: start; 1: end of the pre pass, if any; `last`: end.
        let stamp = |begin: Option<u32>, end: u32| {
            ts.as_ref().map(|(set, _)| wgpu::ComputePassTimestampWrites { query_set: set, beginning_of_pass_write_index: begin, end_of_pass_write_index: Some(end) })
        };
        match pre {
            Some((tiles, list)) => {
                // The tile pass queues tiles in `list` (a storage buffer); it
                // cannot also be the indirect buffer of the next dispatch, so
                // its counts are copied to `args` between the two passes.
                let args = d.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("indirect dispatch"),
                    size: 16,
                    usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                {
                    let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(label), timestamp_writes: stamp(Some(0), 1) });
                    pass.set_bind_group(0, &bind, &[]);
                    pass.set_pipeline(tiles);
                    pass.dispatch_workgroups(tw.div_ceil(64), th.div_ceil(64), 1);
                }
                enc.copy_buffer_to_buffer(list, 0, &args, 0, 12);
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(label), timestamp_writes: stamp(None, last) });
                pass.set_bind_group(0, &bind, &[]);
                pass.set_pipeline(pipeline);
                pass.dispatch_workgroups_indirect(&args, 0);
            }
            None => {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(label), timestamp_writes: stamp(Some(0), last) });
                pass.set_bind_group(0, &bind, &[]);
                pass.set_pipeline(pipeline);
                pass.dispatch_workgroups(tw.div_ceil(8), th.div_ceil(8).div_ceil(group), 1);
            }
        }
        let ts_staging = ts.as_ref().map(|(set, resolve)| {
            enc.resolve_query_set(set, 0..last + 1, resolve, 0);
            gpu.read_buffer(&mut enc, resolve, 8 * (last as u64 + 1))
        });
        if !gpu.map_in_place {
            enc.copy_buffer_to_buffer(&out, 0, &staging, 0, size);
        }
        gpu.queue.submit([enc.finish()]);
        (staging, ts_staging)
    })?;
    gpu.map_read_with(&staging, unpack)?;
    let wall = t0.elapsed().as_secs_f64() * 1e3;
    Ok(match (ts_staging, gpu.timestamp_period) {
        (Some(b), Some(period)) => {
            let t = gpu.map_read(&b)?;
            let v: &[u64] = bytemuck::cast_slice(&t);
            let ms = |a: u64, b: u64| b.saturating_sub(a) as f64 * period as f64 * 1e-6;
            let total = ms(v[0], v[last as usize]);
            if total > 0.0 { (total, if pre.is_some() { ms(v[0], v[1]) } else { 0.0 }) } else { (wall, 0.0) }
        }
        _ => (wall, 0.0),
    })
}

/// Parameter values packed for the uniform `params: array<vec4<f32>, 16>`.
pub const MAX_PARAMS: usize = 64;

/// Packs parameter values into the 64-float uniform block.
pub fn pack_params(values: &[f32]) -> Result<[f32; MAX_PARAMS], GpuError> {
    if values.len() > MAX_PARAMS {
        return Err(GpuError::Limits(format!("too many parameters: {} (the limit is {MAX_PARAMS})", values.len())));
    }
    let mut p = [0.0f32; MAX_PARAMS];
    p[..values.len()].copy_from_slice(values);
    Ok(p)
}
