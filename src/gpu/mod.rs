//! Headless wgpu: getting a device, running validated compute shaders, and
//! reading results back. [`Renderer`] runs a render kernel (a traversal
//! over a field source) frame by frame; `dispatch` is its one tile loop. Getting a device ([`Gpu::new`]) is separate from the
//! work done with it, so tests and batch commands share one device.
//!
//! wgpu's default handler panics on uncaptured errors; every call that can
//! fail runs inside an error scope and becomes a [`GpuError`].

pub(crate) mod bisect;
mod binding;
pub(crate) mod dispatch;
pub(crate) mod driver;
pub(crate) mod eval;
mod field;
pub(crate) mod renderer;
mod sphere;
mod uniforms;

pub use driver::ShaderOpt;
pub use renderer::{RenderError, Renderer};

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
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DeviceInfo {
    /// Adapter name, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub name: String,
    /// Driver name and version.
    pub driver: String,
    /// Backend (Vulkan, …).
    pub backend: String,
    /// Device type (Cpu, DiscreteGpu, …).
    pub device_type: String,
    /// Whether a CPU driver optimises its kernels (`driver`); absent
    /// where the setting does not apply.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shader_opt: Option<ShaderOpt>,
}

impl DeviceInfo {
    /// Name, backend and driver version (lavapipe's speed differs between
    /// Mesa releases), and the optimisation where it applies:
    /// `llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan, llvmpipe Mesa 25.0.7 (LLVM
    /// 15.0.6)), shader opt none`.
    pub fn describe(&self) -> String {
        let opt = self.shader_opt.map_or(String::new(), |o| format!(", shader opt {}", o.name()));
        format!("{} ({}, {}){opt}", self.name, self.backend, self.driver)
    }
}

/// Who wrote a shader module's loops, which decides whether naga adds its
/// loop counter.
///
/// naga bounds every loop with a 64-bit countdown by default, so that a
/// driver may not assume that a loop without side effects ends. On
/// lavapipe that counter is costly: its NIR optimiser unrolls small loops
/// and then needs one more round of its whole pass list per unrolled copy
/// to fold the copies' counter tests away (68 rounds for the tape's tile
/// pass, 20 for `@city`'s per-pixel pass, where 6 do without it). The
/// counter stops no runaway loop in any useful time (2^64 iterations), and
/// lavapipe caps every invocation's loops at 65,535 iterations anyway.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Author {
    /// Only isotrace's templates and generated code: every loop is bounded
    /// by a constant, a budget from the uniform block or a count of the
    /// field group's data, all checked on the host. Made without the counter.
    Isotrace,
    /// Also WGSL from the user (`--inline`), whose loops isotrace cannot
    /// vouch for: made with wgpu's default checks.
    WithUserWgsl,
}

impl Author {
    /// The author of a kernel that holds user WGSL or not.
    pub fn of(user_wgsl: bool) -> Author {
        if user_wgsl { Author::WithUserWgsl } else { Author::Isotrace }
    }
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
    /// Compute pipelines created on this device so far (a data-driven
    /// field's edits must create none: the tests count them).
    pub pipelines_created: std::sync::atomic::AtomicU64,
    /// Warm-up dispatches sent and failed (`Binder::warm_up`: best effort;
    /// after a failure the first frame compiles what it would have; the
    /// tests expect none).
    pub warm_ups: [std::sync::atomic::AtomicU64; 2],
    /// Whether the device has subgroup operations: a tape's bisection
    /// kernel then counts its interpreter's loop iterations per SIMD bundle
    /// (what lavapipe's loop cap counts) instead of assuming the worst per
    /// invocation (`crate::field::tape::features::BUNDLE_WORK`). Off when
    /// `ISOTRACE_NO_SUBGROUPS` is set; a caller may clear it before
    /// building renderers (the tests compare both counts).
    pub subgroups: bool,
}

impl Gpu {
    /// Opens the default adapter (honouring `WGPU_ADAPTER_NAME` / `WGPU_BACKEND`
    /// without panicking when they match nothing), with the driver's
    /// optimisation as the environment sets it.
    pub fn new() -> Result<Gpu, GpuError> {
        Self::open(None)
    }

    /// [`Gpu::new`] asking a CPU driver for `opt` (`driver`): effective
    /// for the first device a process opens, which fixes it for the rest
    /// (`info.shader_opt` says what is in effect).
    pub fn with_shader_opt(opt: ShaderOpt) -> Result<Gpu, GpuError> {
        Self::open(Some(opt))
    }

    fn open(opt: Option<ShaderOpt>) -> Result<Gpu, GpuError> {
        // Mesa's device-select layer complains on stderr without this.
        if std::env::var_os("XDG_RUNTIME_DIR").is_none() && std::env::var_os("NODEVICE_SELECT").is_none() {
            // SAFETY: called before any other thread of ours touches the environment.
            unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
        }
        driver::start(opt);
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
            shader_opt: driver::in_effect(&ai.name, ai.device_type == wgpu::DeviceType::Cpu),
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
        let subgroups = adapter.features().contains(wgpu::Features::SUBGROUP) && std::env::var_os("ISOTRACE_NO_SUBGROUPS").is_none();
        if subgroups {
            features |= wgpu::Features::SUBGROUP;
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
        Ok(Gpu {
            device,
            queue,
            info,
            max_storage_binding: limits.max_storage_buffer_binding_size as u64,
            timestamp_period,
            map_in_place,
            pipelines_created: Default::default(),
            warm_ups: Default::default(),
            subgroups,
        })
    }

    /// Runs `f` inside a validation + out-of-memory error scope.
    pub(crate) fn scoped<T>(&self, during: &'static str, f: impl FnOnce() -> T) -> Result<T, GpuError> {
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
    pub(crate) fn pipeline(&self, label: &str, wgsl: &str, author: Author) -> Result<wgpu::ComputePipeline, GpuError> {
        Ok(self.pipelines(label, wgsl, author, &["main"])?.remove(0))
    }

    /// One pipeline per entry point of one validated WGSL module, each with
    /// its own derived layout.
    pub(crate) fn pipelines(&self, label: &str, wgsl: &str, author: Author, entries: &[&str]) -> Result<Vec<wgpu::ComputePipeline>, GpuError> {
        self.pipelines_then(label, (wgsl, author), entries, None, |_| ())
    }

    /// One pipeline per entry point of one validated WGSL module, all with
    /// `layout` (or each with its own derived layout when `None`), created
    /// side by side, calling `then` with the pipelines of `entries[1..]` as
    /// soon as they exist, while `entries[0]` may still be in the making. A
    /// render kernel's first entry is its large per-pixel pass; `then` has
    /// lavapipe compile the small passes meanwhile (`binding::Binder::warm_up`),
    /// which it would otherwise do at the first frame's dispatch, after the
    /// per-pixel pass's creation. `author` decides naga's loop counter
    /// ([`Author`]).
    pub(crate) fn pipelines_then(
        &self,
        label: &str,
        (wgsl, author): (&str, Author),
        entries: &[&str],
        layout: Option<&wgpu::PipelineLayout>,
        then: impl FnOnce(&[wgpu::ComputePipeline]) + Send,
    ) -> Result<Vec<wgpu::ComputePipeline>, GpuError> {
        self.pipelines_created.fetch_add(entries.len() as u64, std::sync::atomic::Ordering::Relaxed);
        let module = self.scoped("shader compilation", || {
            let desc = wgpu::ShaderModuleDescriptor { label: Some(label), source: wgpu::ShaderSource::Wgsl(wgsl.into()) };
            match author {
                Author::Isotrace => {
                    let mut checks = wgpu::ShaderRuntimeChecks::checked();
                    checks.force_loop_bounding = false;
                    // SAFETY: wgpu asks that every loop of the module
                    // terminate; see `Author::Isotrace`. Bounds checks stay.
                    unsafe { self.device.create_shader_module_trusted(desc, checks) }
                }
                Author::WithUserWgsl => self.device.create_shader_module(desc),
            }
        })?;
        let create = |e: &str| {
            // Error scopes belong to the thread that pushed them.
            self.scoped("shader compilation", || {
                self.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(label),
                    layout,
                    module: &module,
                    entry_point: Some(e),
                    compilation_options: Default::default(),
                    cache: None,
                })
            })
        };
        let Some((first, rest)) = entries.split_first() else { return Ok(vec![]) };
        // A pipeline per thread: lavapipe translates each entry point to its
        // own IR at creation, the whole inlined field in each. Created side
        // by side on two cores, a big field's passes take little longer
        // than its largest one alone.
        std::thread::scope(|s| {
            let others = s.spawn(|| {
                let handles: Vec<_> = rest.iter().map(|e| s.spawn(move || create(e))).collect();
                let made = handles.into_iter().map(join_scoped).collect::<Result<Vec<_>, _>>()?;
                then(&made);
                Ok::<_, GpuError>(made)
            });
            let mut all = vec![create(first)?];
            all.extend(join_scoped(others)?);
            Ok(all)
        })
    }

    /// Blocks until the queue is idle.
    pub(crate) fn wait(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(Duration::from_secs(600)) })
            .map(|_| ())
            .map_err(|e| GpuError::Device { during: "waiting for the GPU", message: e.to_string() })
    }

    /// Copies `size` bytes of `src` into a mappable buffer and reads them.
    pub(crate) fn read_buffer(&self, encoder: &mut wgpu::CommandEncoder, src: &wgpu::Buffer, size: u64) -> wgpu::Buffer {
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("read-back"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        encoder.copy_buffer_to_buffer(src, 0, &staging, 0, size);
        staging
    }

    /// Maps several read-back buffers after submission and hands their bytes
    /// to `f` without copying them first.
    pub(crate) fn map_many<T>(&self, staging: &[&wgpu::Buffer], f: impl FnOnce(&[&[u8]]) -> T) -> Result<T, GpuError> {
        let (out, _) = self.map_keeping(staging, false, f)?;
        Ok(out)
    }

    /// [`Gpu::map_many`], leaving the first buffer mapped and returning its
    /// view when `keep_first` (a frame that keeps its records where the
    /// kernel wrote them); the others are unmapped.
    pub(crate) fn map_keeping<T>(&self, staging: &[&wgpu::Buffer], keep_first: bool, f: impl FnOnce(&[&[u8]]) -> T) -> Result<(T, Option<wgpu::BufferView>), GpuError> {
        let (tx, rx) = std::sync::mpsc::channel();
        for b in staging {
            let tx = tx.clone();
            b.map_async(wgpu::MapMode::Read, .., move |r| {
                let _ = tx.send(r);
            });
        }
        self.wait()?;
        let err = |m: String| GpuError::Device { during: "reading results", message: m };
        for _ in staging {
            rx.recv().map_err(|e| err(e.to_string()))?.map_err(|e| err(e.to_string()))?;
        }
        let mut views = staging.iter().map(|b| b.get_mapped_range(..).map_err(|e| err(e.to_string()))).collect::<Result<Vec<_>, _>>()?;
        let slices: Vec<&[u8]> = views.iter().map(|v| &v[..]).collect();
        let out = f(&slices);
        drop(slices);
        let kept = (keep_first && !views.is_empty()).then(|| views.remove(0));
        drop(views);
        for b in &staging[usize::from(kept.is_some())..] {
            b.unmap();
        }
        Ok((out, kept))
    }

    /// Maps a read-back buffer made by [`Gpu::read_buffer`] after submission.
    pub(crate) fn map_read(&self, staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        self.map_many(&[staging], |b| b[0].to_vec())
    }

    /// A read-only storage buffer holding `bytes` (at least 16 bytes: an
    /// empty binding is invalid).
    pub(crate) fn storage(&self, label: &str, bytes: &[u8]) -> Result<wgpu::Buffer, GpuError> {
        use wgpu::util::DeviceExt;
        let mut padded;
        let contents = if bytes.len() < 16 {
            padded = bytes.to_vec();
            padded.resize(16, 0);
            &padded[..]
        } else {
            bytes
        };
        self.scoped("buffer upload", || {
            self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST })
        })
    }
}

impl Gpu {
    /// A sampled texture of 32-bit texels (`format` Rgba32Uint or
    /// Rgba32Float) holding `t`, and its view.
    pub(crate) fn texture<T: bytemuck::Pod>(&self, label: &str, t: &crate::field::Texels<T>, format: wgpu::TextureFormat) -> Result<(wgpu::Texture, wgpu::TextureView), GpuError> {
        use wgpu::util::DeviceExt;
        let max = self.device.limits().max_texture_dimension_2d;
        if t.width > max || t.height > max {
            return Err(GpuError::Limits(format!("{label}: a {}x{} texture is over the device's limit of {max} texels a side: the scene is too large for this device", t.width, t.height)));
        }
        let desc = wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d { width: t.width, height: t.height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        };
        self.scoped("texture upload", || {
            let tex = self.device.create_texture_with_data(&self.queue, &desc, Default::default(), bytemuck::cast_slice(&t.texels));
            let view = tex.create_view(&Default::default());
            (tex, view)
        })
    }
}

/// A scoped thread's result, its panic passed on.
fn join_scoped<T>(h: std::thread::ScopedJoinHandle<'_, T>) -> T {
    h.join().unwrap_or_else(|p| std::panic::resume_unwind(p))
}

/// A compute bind group layout entry for a sampled 2D texture.
pub(crate) fn texture_entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture { sample_type, view_dimension: wgpu::TextureViewDimension::D2, multisampled: false },
        count: None,
    }
}

/// The tile list a traversal's tile pass fills (the indirect dispatch
/// counts of `main`, then the count of queued tiles: 16 bytes) and the ids of
/// the queued tiles, for the 8×8 tiles of `rect` (pass-group bindings 2 and 3
/// of bisection and of sphere tracing over a scene).
pub(crate) fn tile_list_buffers(gpu: &Gpu, rect: dispatch::Rect) -> (wgpu::Buffer, wgpu::Buffer) {
    use wgpu::BufferUsages as B;
    let buffer = |label, size: u64, usage| gpu.device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: size.max(16), usage, mapped_at_creation: false });
    (buffer("tile list", 16, B::STORAGE | B::COPY_SRC | B::COPY_DST), buffer("tile ids", rect.tiles() * 4, B::STORAGE))
}

/// The layout entry of a table's storage buffer.
pub(crate) fn slot_entry(slot: &crate::bindings::Slot) -> wgpu::BindGroupLayoutEntry {
    storage_entry(slot.binding, slot.read_only)
}

/// A compute bind group layout entry for a storage buffer.
pub(crate) fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only }, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    }
}
