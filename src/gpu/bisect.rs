//! Bisection's part of the render pipeline on the host: its uniform block
//! (modalities, budget, optimisations), the environment image of the frame
//! group, and the tile pass's buffers in the pass group.

use super::dispatch::Rect;
use super::renderer::{PassBuffers, TraversalHost};
use super::{slot_entry, Gpu, GpuError};
use crate::kernel::bindings::{ENVIRONMENT, RESUME_STATES, TILE_IDS, TILE_LIST, TILE_MASKS};
use crate::layout::{BisectBlock, FLAG_NO_TAPE_SHORTENING, FLAG_NO_TILE_CULLING};
use crate::render::record::RayStats;
use crate::render::settings::MAX_ITER_LIMIT;
use crate::render::{BisectOptions, CameraBasis, Environment, Optimizations, Settings, SphereOptions, Stats, Traversal};

/// 8×8 pixel tiles per workgroup of the per-pixel pass (`TILES_PER_GROUP`
/// in traverse/bisect/tiles.wgsl).
pub(crate) const TILES_PER_GROUP: u32 = 4;

/// Bisection on the host.
pub(crate) struct Host {
    options: BisectOptions,
    /// The environment image (one dummy texel when procedural).
    env: wgpu::Buffer,
}

impl Host {
    /// Uploads the environment.
    pub fn new(gpu: &Gpu, options: BisectOptions) -> Result<Host, GpuError> {
        let texels: &[u32] = match &options.modalities.env {
            Environment::Image(e) => &e.texels,
            _ => &[0],
        };
        let env = gpu.storage("environment", bytemuck::cast_slice(texels))?;
        Ok(Host { options, env })
    }
}

/// Bisection's uniform block for a frame (device-free: the viewer's page
/// gets the same bytes).
pub(crate) fn block(options: &BisectOptions, s: &Settings, cam: &CameraBasis) -> BisectBlock {
    let m = &options.modalities;
    let o = &options.optimizations;
    let dist = (s.camera.eye - s.camera.target).length();
    let light = m.light.unwrap_or(s.camera.eye + (0.6 * cam.up - 0.4 * cam.right) * dist);
    let mut iso = [0.0f32; 8];
    for (k, v) in m.isovalues.iter().take(8).enumerate() {
        iso[k] = *v as f32;
    }
    BisectBlock {
        light: [light.x as f32, light.y as f32, light.z as f32, m.shadow_eps.unwrap_or(4.0 * s.eps) as f32],
        iso,
        env_size: match &m.env {
            Environment::Image(e) => [e.width, e.height],
            _ => [0, 0],
        },
        max_iter: s.max_iter.clamp(1, MAX_ITER_LIMIT),
        mono_depth: if o.monotone { o.monotone_depth } else { u32::MAX },
        iso_count: m.isovalues.len().clamp(1, 8) as u32,
        opacity: m.opacity as f32,
        reflectivity: m.reflectivity as f32,
        pad0: 0,
    }
}

/// Bisection's frame flags.
pub(crate) fn flags(options: &BisectOptions) -> u32 {
    let o = &options.optimizations;
    (if o.tile_culling { 0 } else { FLAG_NO_TILE_CULLING }) | if o.tape_shortening { 0 } else { FLAG_NO_TAPE_SHORTENING }
}

impl TraversalHost for Host {
    fn block(&self, s: &Settings, cam: &CameraBasis) -> Vec<u8> {
        bytemuck::bytes_of(&block(&self.options, s, cam)).to_vec()
    }

    fn flags(&self) -> u32 {
        flags(&self.options)
    }

    fn frame_resources(&self) -> Vec<(wgpu::BindGroupLayoutEntry, &wgpu::Buffer)> {
        vec![(slot_entry(&ENVIRONMENT), &self.env)]
    }

    fn pass_layout(&self) -> Vec<wgpu::BindGroupLayoutEntry> {
        [TILE_MASKS, TILE_LIST, TILE_IDS, RESUME_STATES].iter().map(slot_entry).collect()
    }

    /// Per 8×8 tile: its candidate-slab mask (vec4<u32>), and the list of
    /// tiles with candidates with the indirect dispatch counts of `main`;
    /// per pixel, its resume state across rounds of `main` (new buffers
    /// are zeroed: every pixel starts new). Only a resumable pass reads
    /// those states; for the others the binding gets 16 bytes, since wgpu
    /// zeroes a new buffer at its first use, and 16 MB at 1024² would cost
    /// every frame a clear and the page faults of fresh memory.
    fn pass_buffers(&self, gpu: &Gpu, rect: Rect, resumable: bool) -> PassBuffers {
        use wgpu::BufferUsages as B;
        let buffer = |label, size: u64, usage| gpu.device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: size.max(16), usage, mapped_at_creation: false });
        let masks = buffer("tile masks", rect.tiles() * 16, B::STORAGE);
        let (list, ids) = super::tile_list_buffers(gpu, rect);
        let resume = buffer("resume states", if resumable { rect.pixels() * 16 } else { 16 }, B::STORAGE);
        PassBuffers { entries: vec![(TILE_MASKS.binding, masks), (TILE_LIST.binding, list.clone()), (TILE_IDS.binding, ids), (RESUME_STATES.binding, resume)], list: Some(list) }
    }

    fn tiles_per_group(&self) -> u32 {
        TILES_PER_GROUP
    }

    fn pre_pass(&self) -> bool {
        self.options.optimizations.tile_culling
    }

    fn ray_stats_binding(&self) -> Option<u32> {
        None
    }

    fn finish(&self, s: &Settings, _rays: &RayStats, stats: &mut Stats) {
        let diag = crate::render::box_diagonal(&s.bbox);
        stats.bisect.d_max = (diag / s.eps).log2().ceil().clamp(0.0, 18.0) as u32;
        stats.iso_channel |= self.options.modalities.isovalues.len() > 1;
    }

    fn options(&self) -> Traversal {
        Traversal::Bisect(self.options.clone())
    }

    fn method(&self) -> crate::render::Method {
        crate::render::Method::Bisect
    }

    fn optimizations_mut(&mut self) -> Option<&mut Optimizations> {
        Some(&mut self.options.optimizations)
    }

    fn sphere_options_mut(&mut self) -> Option<&mut SphereOptions> {
        None
    }
}
