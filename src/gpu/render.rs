//! Runs the render kernel. A [`Renderer`] holds one compiled pipeline (a
//! formula in one algebra); frames differ only in uniforms (camera, time,
//! parameters), so animations and benchmarks never recompile.

use super::{pack_params, Gpu, GpuError};
use crate::codegen::{render_shader_with, Domain};
use crate::ir::Ir;
use super::pixels::{convert, map_all, PackedFrame, RawPixel};
use crate::render::{Camera, Frame, Stats, StatsAcc};
use crate::validate::{validate, ValidateError};
use bytemuck::{Pod, Zeroable};
use std::time::Instant;
use wgpu::util::DeviceExt;

/// Largest image side accepted.
pub const MAX_SIZE: u32 = 16384;

/// 8×8 pixel tiles per workgroup of the render kernel (`TILES_PER_GROUP`
/// in bisect.wgsl).
const TILES_PER_GROUP: u32 = 4;
/// The largest side of one dispatch: (4088 / 8)² tiles / 4 < 65535 groups.
const MAX_DISPATCH_TILE: u32 = 4088;

/// Everything one frame needs besides the formula.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Domain box `x0, x1, y0, y1, z0, z1`.
    pub bbox: [f64; 6],
    /// The camera.
    pub camera: Camera,
    /// Absolute termination width along the ray.
    pub eps: f64,
    /// Time value `t`.
    pub time: f64,
    /// Parameter values in the formula's parameter order.
    pub params: Vec<f32>,
    /// Iteration budget per pixel (well below lavapipe's 65,535 loop cap).
    pub max_iter: u32,
    /// Largest tile side per dispatch.
    pub tile: u32,
    /// Draw unresolved pixels in magenta.
    pub debug_unresolved: bool,
    /// Also clip rays to the ball of this radius around the box centre.
    pub clip_sphere: Option<f64>,
}

impl Settings {
    /// The CLI's defaults for a box and an image size: the default camera,
    /// eps = 2^-11 × the box diagonal, t = 0, no parameters, no clip ball.
    pub fn for_box(bbox: [f64; 6], width: u32, height: u32) -> Settings {
        Settings {
            width,
            height,
            bbox,
            camera: Camera::default_for(&bbox, 40.0, width as f64 / height as f64),
            eps: crate::render::box_diagonal(&bbox) * 2f64.powi(-11),
            time: 0.0,
            params: vec![],
            max_iter: DEFAULT_MAX_ITER,
            tile: 1024,
            debug_unresolved: false,
            clip_sphere: None,
        }
    }
}

/// Default iteration budget.
pub const DEFAULT_MAX_ITER: u32 = 8192;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Uniforms {
    eye: [f32; 4],
    forward: [f32; 4],
    right: [f32; 4],
    up: [f32; 4],
    box_min: [f32; 4],
    box_max: [f32; 4], // w: clip-sphere radius (0: none)
    size: [u32; 2],
    tile_origin: [u32; 2],
    tile_size: [u32; 2],
    max_iter: u32,
    flags: u32,
    tan_half_fov: f32,
    eps: f32,
    inf: f32,
    time: f32,
    mono_depth: u32,
    iso_count: u32,
    env_size: [u32; 2],
    light: [f32; 4],
    iso: [f32; 8],
    opacity: f32,
    reflectivity: f32,
    pad: [u32; 2],
    params: [f32; 64],
}

/// `unpack2x16unorm`.
pub(crate) fn unorm2(v: u32) -> [f32; 2] {
    [(v & 0xffff) as f32 / 65535.0, (v >> 16) as f32 / 65535.0]
}

/// `unpack2x16snorm`.
pub(crate) fn snorm2(v: u32) -> [f32; 2] {
    let c = |x: u16| (x as i16 as f32 / 32767.0).max(-1.0);
    [c(v as u16), c((v >> 16) as u16)]
}

/// Render failures.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// naga rejected the generated shader (an isotrace bug).
    #[error(transparent)]
    Validate(#[from] ValidateError),
    /// The device failed.
    #[error(transparent)]
    Gpu(#[from] GpuError),
    /// Bad settings (size, camera, eps).
    #[error("{0}")]
    Settings(String),
    /// The user's inline WGSL does not validate (rendered against their file).
    #[error("{0}")]
    Inline(String),
}

/// Switches for the traversal's optimisations, so their effect can be
/// measured and their results compared (every combination is exact: each
/// only skips work that is proven unnecessary).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Optimizations {
    /// Tile pass: enclose f over depth slabs of each 8×8 tile's frustum and
    /// let rays skip the slabs proven empty.
    pub tile_culling: bool,
    /// Derivative enclosures from depth [`Optimizations::monotone_depth`] on:
    /// monotone cells are rejected or solved by scalar root finding, the
    /// others are also bounded by the mean-value form.
    pub monotone: bool,
    /// First bisection depth at which the derivative is evaluated. 0 (the
    /// whole segment) measured fastest: 11 % on the geometric mean of eight
    /// Knoll surfaces against depth 2, up to 36 % on cloth.
    pub monotone_depth: u32,
}

impl Default for Optimizations {
    fn default() -> Self {
        Optimizations { tile_culling: true, monotone: true, monotone_depth: 0 }
    }
}

/// A compiled render pipeline for one formula and algebra.
pub struct Renderer<'g> {
    gpu: &'g Gpu,
    pipeline: wgpu::ComputePipeline,
    /// The tile pass (entry point `tiles`).
    tiles: wgpu::ComputePipeline,
    /// The algebra of the inclusion function.
    pub domain: Domain,
    /// The shader source (validated).
    pub wgsl: String,
    /// Optimisation switches (uniforms: changing them never recompiles).
    pub optimizations: Optimizations,
    /// The modalities it was compiled for, with their values.
    pub modalities: Modalities,
    env: wgpu::Buffer,
    csg_surfaces: usize,
    /// The pixel buffer and its read-back copy, reused between frames.
    buffers: super::TileBuffers,
}

/// An environment image (equirectangular), rgba8 packed per texel.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvImage {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Row-major rgba8 texels (`u32::from_le_bytes([r, g, b, a])`).
    pub texels: Vec<u32>,
}

/// Knoll et al.'s visualisation modalities. Structural choices (which code
/// exists) are compiled in; values are uniforms.
#[derive(Debug, Clone, PartialEq)]
pub struct Modalities {
    /// Shadow rays from the point light.
    pub shadows: bool,
    /// Point light (default: above and left of the eye).
    pub light: Option<glam::DVec3>,
    /// eps of shadow rays (default 4 × eps).
    pub shadow_eps: Option<f64>,
    /// Surface layers per pixel (1: opaque).
    pub layers: u32,
    /// Per-layer opacity when layers > 1.
    pub opacity: f64,
    /// Isovalues (empty: just 0). At most 8.
    pub isovalues: Vec<f64>,
    /// Reflection bounces.
    pub reflect: u32,
    /// Weight of each reflection.
    pub reflectivity: f64,
    /// Colour mode drawn by the kernel: 0 Phong, 1 |grad f|, 2 depth.
    pub color_mode: u32,
    /// Procedural environment: 0 sky, 1 checkered ground (ignored with an image).
    pub env_mode: u32,
    /// Environment image.
    pub env: Option<EnvImage>,
    /// User WGSL (`--inline`): functions and hooks.
    pub inline: Option<crate::inline::InlineWgsl>,
}

impl Default for Modalities {
    fn default() -> Self {
        Modalities {
            shadows: false,
            light: None,
            shadow_eps: None,
            layers: 1,
            opacity: 1.0,
            isovalues: vec![],
            reflect: 0,
            reflectivity: 0.35,
            color_mode: 0,
            env_mode: 0,
            env: None,
            inline: None,
        }
    }
}

impl Modalities {
    /// The compile-time part.
    pub fn config(&self) -> crate::codegen::RenderConfig {
        crate::codegen::RenderConfig {
            shadows: self.shadows,
            layers: self.layers.max(1),
            reflect: self.reflect,
            iso_count: self.isovalues.len().clamp(1, 8) as u32,
            color_mode: self.color_mode,
            env_mode: if self.env.is_some() { 2 } else { self.env_mode },
        }
    }
}

impl<'g> Renderer<'g> {
    /// Generates, validates and compiles the render kernel.
    pub fn new(gpu: &'g Gpu, ir: &Ir, domain: Domain) -> Result<Renderer<'g>, RenderError> {
        Self::with_modalities(gpu, ir, domain, Modalities::default())
    }

    /// Like [`Renderer::new`], with modalities.
    pub fn with_modalities(gpu: &'g Gpu, ir: &Ir, domain: Domain, modalities: Modalities) -> Result<Renderer<'g>, RenderError> {
        if modalities.isovalues.len() > 8 {
            return Err(RenderError::Settings(format!("at most 8 isovalues, got {}", modalities.isovalues.len())));
        }
        if modalities.layers > 8 {
            return Err(RenderError::Settings(format!("at most 8 layers, got {}", modalities.layers)));
        }
        let wgsl = render_shader_with(ir, domain, &modalities.config(), modalities.inline.as_ref());
        match &modalities.inline {
            Some(user) => {
                let start = wgsl.find(&user.text).unwrap_or(0);
                crate::validate::validate_with_inline(&wgsl, start..start + user.text.len(), &user.path, &user.text).map_err(|e| match e {
                    crate::validate::InlineError::User(m) => RenderError::Inline(m),
                    crate::validate::InlineError::Bug(b) => RenderError::Validate(b),
                })?;
            }
            None => {
                validate(&wgsl)?;
            }
        }
        let layout = render_layout(&gpu.device);
        let mut pipelines = gpu.pipelines_with_layout("isotrace render", &wgsl, &["main", "tiles"], Some(&layout))?;
        let tiles = pipelines.pop().expect("two entry points");
        let pipeline = pipelines.pop().expect("two entry points");
        let texels: Vec<u32> = modalities.env.as_ref().map_or(vec![0], |e| e.texels.clone());
        let env = gpu.scoped("environment upload", || {
            gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("environment"),
                contents: bytemuck::cast_slice(&texels),
                usage: wgpu::BufferUsages::STORAGE,
            })
        })?;
        Ok(Renderer { gpu, pipeline, tiles, domain, wgsl, optimizations: Optimizations::default(), modalities, env, csg_surfaces: ir.surfaces.len(), buffers: super::TileBuffers::default() })
    }

    /// Renders one frame, tile by tile.
    pub fn render(&self, s: &Settings) -> Result<Frame, RenderError> {
        let mut f = Frame { width: 0, height: 0, pixels: Vec::new(), stats: Stats::default() };
        self.render_into(s, &mut f)?;
        Ok(f)
    }

    /// Renders one frame into `frame`, reusing its pixel memory: a viewer
    /// or an animation renders every frame into the same one. (Touching
    /// 50 MB of fresh pages costs ~10 ms a 1024² frame on this machine.)
    pub fn render_into(&self, s: &Settings, out: &mut Frame) -> Result<(), RenderError> {
        let start = Instant::now();
        let (pixels, stats) = self.collect(s, std::mem::take(&mut out.pixels), convert)?;
        *out = Frame { width: s.width, height: s.height, pixels, stats };
        out.stats.wall_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(())
    }

    /// Renders one frame into `out` and keeps the kernel's records packed
    /// (see [`PackedFrame`]), with the same statistics as [`Renderer::render_into`].
    pub fn render_packed(&self, s: &Settings, out: &mut PackedFrame) -> Result<(), RenderError> {
        let start = Instant::now();
        let (records, stats) = self.collect(s, std::mem::take(&mut out.records), |r| *r)?;
        *out = PackedFrame { width: s.width, height: s.height, stats, records };
        out.stats.wall_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(())
    }

    /// Renders one frame and writes `f` of each record, row-major, into
    /// `buf` (its memory reused), gathering the statistics on the way.
    fn collect<T: Copy + Send>(&self, s: &Settings, mut buf: Vec<T>, f: fn(&RawPixel) -> T) -> Result<(Vec<T>, Stats), RenderError> {
        check_settings(s)?;
        let (w, h) = (s.width, s.height);
        let n = (w * h) as usize;
        buf.clear();
        let mut acc = StatsAcc::default();
        let mut stats = self.run(s, |(tx, ty, tw, th), raw| {
            if (tw, th) == (w, h) {
                // The usual case, one dispatch for the frame: write straight
                // into the (reused) memory, on every core, without filling it
                // first.
                buf.reserve(n);
                acc.merge(map_all(raw, &mut buf.spare_capacity_mut()[..n], f));
                // SAFETY: map_all initialised all n elements.
                unsafe { buf.set_len(n) };
                return;
            }
            if buf.is_empty() {
                buf.resize(n, f(&RawPixel::zeroed()));
            }
            for (row, chunk) in raw.chunks_exact(tw as usize).enumerate() {
                let start = ((ty + row as u32) * w + tx) as usize;
                for (dst, r) in buf[start..start + tw as usize].iter_mut().zip(chunk) {
                    *dst = f(r);
                    r.count(&mut acc);
                }
            }
        })?;
        acc.finish(&mut stats);
        Ok((buf, stats))
    }

    /// Runs the dispatches of one frame, tile by tile, and hands each
    /// tile's records to `sink` with its rectangle (x, y, width, height).
    /// Returns the statistics that do not depend on the pixels.
    fn run(&self, s: &Settings, mut sink: impl FnMut((u32, u32, u32, u32), &[RawPixel])) -> Result<Stats, RenderError> {
        let frame = s.camera.frame().map_err(RenderError::Settings)?;
        let (w, h) = (s.width, s.height);
        // A tile's pixel records must fit the device's largest storage binding.
        let fit = ((self.gpu.max_storage_binding / std::mem::size_of::<RawPixel>() as u64) as f64).sqrt() as u32 / 8 * 8;
        // And the indirect dispatch of `main` (a workgroup per
        // TILES_PER_GROUP queued 8×8 tiles) must stay within 65535 groups.
        let tile = s.tile.clamp(8, MAX_SIZE).min(fit.max(8)).min(MAX_DISPATCH_TILE);
        let v4 = |v: glam::DVec3| [v.x as f32, v.y as f32, v.z as f32, 0.0];
        let m = &self.modalities;
        let dist = (s.camera.eye - s.camera.target).length();
        let light = m.light.unwrap_or(s.camera.eye + (0.6 * frame.up - 0.4 * frame.right) * dist);
        let mut iso = [0.0f32; 8];
        for (k, v) in m.isovalues.iter().take(8).enumerate() {
            iso[k] = *v as f32;
        }
        let mut u = Uniforms {
            eye: v4(s.camera.eye),
            forward: v4(frame.forward),
            right: v4(frame.right),
            up: v4(frame.up),
            box_min: [s.bbox[0] as f32, s.bbox[2] as f32, s.bbox[4] as f32, 0.0],
            box_max: [s.bbox[1] as f32, s.bbox[3] as f32, s.bbox[5] as f32, s.clip_sphere.unwrap_or(0.0) as f32],
            size: [w, h],
            tile_origin: [0, 0],
            tile_size: [0, 0],
            max_iter: s.max_iter.clamp(1, 60_000),
            flags: u32::from(s.debug_unresolved) | (u32::from(!self.optimizations.tile_culling) << 1),
            mono_depth: if self.optimizations.monotone { self.optimizations.monotone_depth } else { u32::MAX },
            tan_half_fov: frame.tan_half_fov as f32,
            eps: s.eps as f32,
            inf: f32::INFINITY,
            time: s.time as f32,
            iso_count: m.isovalues.len().clamp(1, 8) as u32,
            env_size: m.env.as_ref().map_or([0, 0], |e| [e.width, e.height]),
            light: [light.x as f32, light.y as f32, light.z as f32, m.shadow_eps.unwrap_or(4.0 * s.eps) as f32],
            iso,
            opacity: m.opacity as f32,
            reflectivity: m.reflectivity as f32,
            pad: [0; 2],
            params: pack_params(&s.params)?,
        };
        let (mut gpu_ms, mut tile_ms) = (0.0, 0.0);
        let mut dispatches = 0;
        for ty in (0..h).step_by(tile as usize) {
            for tx in (0..w).step_by(tile as usize) {
                let (tw, th) = (tile.min(w - tx), tile.min(h - ty));
                u.tile_origin = [tx, ty];
                u.tile_size = [tw, th];
                let (ms, pre_ms) = self.dispatch(&u, tw, th, |raw| sink((tx, ty, tw, th), raw))?;
                gpu_ms += ms;
                tile_ms += pre_ms;
                dispatches += 1;
            }
        }
        let diag = crate::render::box_diagonal(&s.bbox);
        Ok(Stats {
            gpu_ms,
            tile_ms,
            dispatches,
            d_max: (diag / s.eps).log2().ceil().clamp(0.0, 18.0) as u32,
            iso_channel: self.modalities.isovalues.len() > 1 || self.csg_surfaces > 1,
            ..Default::default()
        })
    }

    /// Runs one tile and hands its packed pixels to `unpack`; returns the
    /// GPU milliseconds.
    fn dispatch(&self, u: &Uniforms, tw: u32, th: u32, unpack: impl FnOnce(&[RawPixel])) -> Result<(f64, f64), RenderError> {
        let record = std::mem::size_of::<RawPixel>() as u64;
        // Per 8×8 tile: its candidate-slab mask (2 × u32), and the list of
        // tiles with candidates with the indirect dispatch counts of `main`.
        let tiles = tw.div_ceil(8) as u64 * th.div_ceil(8) as u64;
        let buffer = |label, size: u64, usage| {
            self.gpu.device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: size.max(16), usage, mapped_at_creation: false })
        };
        let masks = buffer("tile masks", tiles * 16, wgpu::BufferUsages::STORAGE);
        let list = buffer("tile list", 16, wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST);
        let ids = buffer("tile ids", tiles * 4, wgpu::BufferUsages::STORAGE);
        let pre = self.optimizations.tile_culling.then_some((&self.tiles, &list));
        Ok(super::dispatch_tile(
            self.gpu,
            &self.pipeline,
            pre,
            "render dispatch",
            bytemuck::bytes_of(u),
            &[(2, &self.env), (3, &masks), (4, &list), (5, &ids)],
            &self.buffers,
            (tw, th, record, TILES_PER_GROUP),
            |bytes| unpack(bytemuck::cast_slice::<u8, RawPixel>(bytes)),
        )?)
    }
}

/// The bind group layout both entry points of the render kernel share:
/// uniforms, pixels, environment, tile masks, tile list, tile ids.
fn render_layout(d: &wgpu::Device) -> wgpu::PipelineLayout {
    let entry = |binding, ty| wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None };
    let storage = |read_only| wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Storage { read_only },
        has_dynamic_offset: false,
        min_binding_size: None,
    };
    let bgl = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("render"),
        entries: &[
            entry(0, storage(true)),
            entry(1, storage(false)),
            entry(2, storage(true)),
            entry(3, storage(false)),
            entry(4, storage(false)),
            entry(5, storage(false)),
        ],
    });
    d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some("render"), bind_group_layouts: &[Some(&bgl)], immediate_size: 0 })
}



/// Size, box, clip ball and eps of a frame, checked before any GPU work
/// (shared by both traversals).
pub(crate) fn check_settings(s: &Settings) -> Result<(), RenderError> {
    let bad = |m: String| Err(RenderError::Settings(m));
    if s.width == 0 || s.height == 0 || s.width > MAX_SIZE || s.height > MAX_SIZE {
        return bad(format!("invalid --size {}x{}: each side must be between 1 and {MAX_SIZE}", s.width, s.height));
    }
    for a in 0..3 {
        let (lo, hi) = (s.bbox[2 * a], s.bbox[2 * a + 1]);
        if !(lo < hi) || !lo.is_finite() || !hi.is_finite() {
            return bad(format!("invalid --box: axis {} has [{lo}, {hi}]; each axis needs lo < hi", ["x", "y", "z"][a]));
        }
    }
    if s.clip_sphere.is_some_and(|r| !(r > 0.0 && r.is_finite())) {
        return bad("invalid clip sphere: the radius must be positive".into());
    }
    if !(s.eps > 0.0 && s.eps.is_finite()) {
        return bad(format!("invalid --eps {}: it must be a positive width", s.eps));
    }
    Ok(())
}
