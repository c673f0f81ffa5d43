//! The field group (`@group(1)`) of a render kernel on the device, made
//! from the field source's table ([`crate::bindings`]): the resources with
//! data of their own are uploaded once; those with a size rule are made per
//! dispatch (kept for the next dispatch of as many tiles); the one a field
//! reports its statistics in is the caller's read-back buffer.

use super::dispatch::Rect;
use super::{storage_entry, texture_entry, Gpu, GpuError};
use crate::bindings::{Binding, Stage, Statistics, TexelFormat};
use crate::field::{BindingRequest, FieldSource, FieldWrite};

/// A dispatch's own field resources. Kept for the next dispatch of as many
/// tiles (making and zeroing them anew is a large part of a frame on
/// lavapipe): only those marked `clear` must start at zero, everything else
/// is written before it is read.
#[derive(Clone)]
pub(crate) struct PerDispatch {
    buffers: Vec<(u32, wgpu::Buffer)>,
    textures: Vec<(u32, wgpu::Texture, wgpu::TextureView)>,
    clears: Vec<wgpu::Buffer>,
}

impl PerDispatch {
    /// The buffers to zero before the dispatch.
    pub fn clears(&self) -> Vec<wgpu::Buffer> {
        self.clears.clone()
    }

    /// The copies after the field's passes (`Stage::copy`): a buffer a
    /// pass wrote into a texture the trace reads.
    pub fn copy(&self, from: u32, to: u32) -> Option<(&wgpu::Buffer, &wgpu::Texture)> {
        let buf = self.buffers.iter().find(|(b, _)| *b == from).map(|(_, b)| b)?;
        let tex = self.textures.iter().find(|(b, _, _)| *b == to).map(|(_, t, _)| t)?;
        Some((buf, tex))
    }
}

/// A field source bound on the device: its table, layout, uploaded data
/// and what the renderer asks of it.
pub(crate) struct FieldBinding {
    /// Layout of the field group.
    pub layout: Vec<wgpu::BindGroupLayoutEntry>,
    /// The table it was made from.
    table: Vec<Binding>,
    /// The passes it runs before the traversal.
    passes: Vec<Stage>,
    /// (binding, buffer) pairs that live as long as the field.
    buffers: Vec<(u32, wgpu::Buffer)>,
    /// Textures with data, as long as the field.
    textures: Vec<(u32, wgpu::Texture, wgpu::TextureView)>,
    /// The source's name.
    pub name: &'static str,
    /// The source's features.
    pub features: u32,
    /// Whether the field's cells resume (bisection's per-pixel pass in rounds).
    resumes: bool,
    /// Bisection's block pass before its tile pass.
    block_pass: bool,
    /// The source's bits of the frame flags, sparse and dense.
    flags: [u32; 2],
    /// Evaluates the whole field in every tile (the dense baseline).
    pub dense: bool,
    /// What shares lavapipe's loop cap with bisection's iterations.
    pub shares_loop_cap: Option<&'static str>,
    /// The last dispatch's own resources and its tile count.
    cached: std::sync::Mutex<Option<(u64, PerDispatch)>>,
}

/// The wgpu texel format of a table's format.
fn wgpu_format(f: TexelFormat) -> wgpu::TextureFormat {
    match f {
        TexelFormat::Rgba32Uint => wgpu::TextureFormat::Rgba32Uint,
        TexelFormat::Rgba32Float => wgpu::TextureFormat::Rgba32Float,
        TexelFormat::R32Uint => wgpu::TextureFormat::R32Uint,
    }
}

/// The layout entry of a binding.
fn layout_entry(b: &Binding) -> wgpu::BindGroupLayoutEntry {
    match &b.texture {
        Some(t) => {
            let sample = if t.format == TexelFormat::Rgba32Float { wgpu::TextureSampleType::Float { filterable: false } } else { wgpu::TextureSampleType::Uint };
            texture_entry(b.binding, sample)
        }
        None => storage_entry(b.binding, b.read_only),
    }
}

/// Uploads what `source` binds for a kernel of `request`.
pub(crate) fn bind(gpu: &Gpu, source: &dyn FieldSource, request: &BindingRequest) -> Result<FieldBinding, GpuError> {
    if source.passes().iter().any(|p| matches!(p.groups, crate::bindings::Groups::Indirect { .. })) {
        return Err(GpuError::Limits(format!("the {} field asks for a pass dispatched indirectly: a field's passes are dispatched directly", source.name())));
    }
    let table = source.bindings(request);
    let layout = table.iter().map(layout_entry).collect();
    let (mut buffers, mut textures) = (vec![], vec![]);
    for b in table.iter().filter(|b| b.is_static()) {
        let words = b.data.as_deref().unwrap_or_default();
        match &b.texture {
            Some(t) => {
                let texels = crate::layout::Texels { width: t.width, height: t.height, texels: words.to_vec() };
                let (tex, view) = gpu.texture(b.name, &texels, wgpu_format(t.format))?;
                textures.push((b.binding, tex, view));
            }
            None => buffers.push((b.binding, gpu.storage(b.name, bytemuck::cast_slice(words))?)),
        }
    }
    Ok(FieldBinding {
        layout,
        passes: source.passes(),
        table,
        buffers,
        textures,
        name: source.name(),
        features: source.features(),
        resumes: source.cells_resume(),
        block_pass: request.bisect && source.block_pass(request.kernel_features),
        flags: [source.frame_flags(false), source.frame_flags(true)],
        dense: false,
        shares_loop_cap: source.shares_loop_cap(),
        cached: Default::default(),
    })
}

impl FieldBinding {
    /// The binding read back for the statistics, if any.
    fn reported(&self) -> Option<&Binding> {
        self.table.iter().find(|b| b.statistics.is_some())
    }

    /// What the field reports, if anything.
    pub fn statistics(&self) -> Option<Statistics> {
        self.reported().and_then(|b| b.statistics)
    }

    /// Whether bisection runs the field's block pass before its tile pass.
    pub fn block_pass(&self) -> bool {
        self.block_pass
    }

    /// Whether bisection's per-pixel pass runs in rounds that resume the
    /// pixels the field's work limit stopped.
    pub fn resumes(&self) -> bool {
        self.resumes
    }

    /// The field's bits of the frame flags.
    pub fn flags(&self) -> u32 {
        self.flags[self.dense as usize]
    }

    /// Bytes of the statistics the field reports for a rectangle (0 when
    /// it has none).
    pub fn tile_stats_size(&self, rect: Rect) -> u64 {
        self.reported().map_or(0, |b| b.size.bytes(rect.pixels(), rect.tiles(), 0))
    }

    /// Bytes per pixel of the field's largest per-dispatch resource: the
    /// dispatch rectangle must keep it within one storage binding.
    pub fn bytes_per_pixel(&self) -> u64 {
        self.table.iter().map(|b| b.size.bytes_per_pixel()).max().unwrap_or(0)
    }

    /// The most pixels a dispatch may cover: a texture filled per tile
    /// holds at most the device's texture side of rows.
    pub fn max_pixels(&self, gpu: &Gpu) -> u64 {
        let rows = gpu.device.limits().max_texture_dimension_2d as u64;
        let per_tile = |b: &Binding| b.size.bytes(64, 1, 0) / 4;
        let textures = self.table.iter().filter(|b| !b.is_static()).filter_map(|b| b.texture.as_ref().map(|t| (t, per_tile(b))));
        textures.map(|(t, texels)| rows * u64::from(t.width) / texels.max(1) * 64).min().unwrap_or(u64::MAX)
    }

    /// The per-dispatch resources of a rectangle (kept from the last
    /// dispatch of as many tiles, see [`PerDispatch`]), with `stats` (of
    /// [`FieldBinding::tile_stats_size`] bytes, read back by the caller)
    /// bound where the field writes them.
    pub fn per_dispatch(&self, gpu: &Gpu, rect: Rect, stats: Option<&wgpu::Buffer>) -> PerDispatch {
        let tiles = rect.tiles();
        let mut cached = self.cached.lock().unwrap_or_else(|e| e.into_inner());
        let mut own = match cached.take() {
            Some((n, own)) if n == tiles => own,
            _ => self.make_per_dispatch(gpu, rect),
        };
        *cached = Some((tiles, own.clone()));
        if let Some(b) = self.reported() {
            let buffer = stats.cloned().unwrap_or_else(|| token(gpu, b.name));
            if b.clear {
                own.clears.push(buffer.clone());
            }
            own.buffers.push((b.binding, buffer));
        }
        own
    }

    /// A dispatch's own resources over `rect` (without the statistics).
    fn make_per_dispatch(&self, gpu: &Gpu, rect: Rect) -> PerDispatch {
        let (pixels, tiles) = (rect.pixels(), rect.tiles());
        let mut own = PerDispatch { buffers: vec![], textures: vec![], clears: vec![] };
        let copies: Vec<_> = self.passes.iter().filter_map(|p| p.copy).collect();
        for b in self.table.iter().filter(|b| !b.is_static() && b.statistics.is_none()) {
            let bytes = b.size.bytes(pixels, tiles, 0);
            if let Some(t) = &b.texture {
                let rows = (bytes / 4 / u64::from(t.format.words())).div_ceil(u64::from(t.width)).max(1);
                let tex = gpu.device.create_texture(&wgpu::TextureDescriptor {
                    label: Some(b.name),
                    size: wgpu::Extent3d { width: t.width, height: rows as u32, depth_or_array_layers: 1 },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: wgpu_format(t.format),
                    usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                    view_formats: &[],
                });
                let view = tex.create_view(&Default::default());
                own.textures.push((b.binding, tex, view));
                continue;
            }
            // A buffer copied into a texture is whole rows of it.
            let copied_to = copies.iter().find(|c| c.from == b.binding).and_then(|c| self.table.iter().find(|t| t.binding == c.to));
            let (size, usage) = match copied_to.and_then(|t| t.texture.as_ref().map(|shape| (t, shape))) {
                Some((t, shape)) => {
                    let row = u64::from(shape.width) * 4 * u64::from(shape.format.words());
                    (t.size.bytes(pixels, tiles, 0).div_ceil(row).max(1) * row, wgpu::BufferUsages::COPY_SRC)
                }
                None => (bytes, wgpu::BufferUsages::empty()),
            };
            let usage = usage | wgpu::BufferUsages::STORAGE | if b.clear { wgpu::BufferUsages::COPY_DST } else { wgpu::BufferUsages::empty() };
            let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor { label: Some(b.name), size, usage, mapped_at_creation: false });
            if b.clear {
                own.clears.push(buffer.clone());
            }
            own.buffers.push((b.binding, buffer));
        }
        own
    }

    /// The field's passes over a rectangle, in order, with their workgroups.
    pub fn passes(&self, rect: Rect) -> Vec<([u32; 3], Option<crate::bindings::Copy>)> {
        self.passes.iter().map(|p| (self.workgroups(p, rect), p.copy)).collect()
    }

    fn workgroups(&self, p: &Stage, rect: Rect) -> [u32; 3] {
        use crate::bindings::Groups;
        match p.groups {
            Groups::Items { binding, per_group } => {
                let items = self.table.iter().find(|b| b.binding == binding).and_then(|b| b.data.as_ref()).map_or(0, |d| d.len() as u32);
                let groups = items.div_ceil(per_group).max(1);
                [groups.min(65_535), groups.div_ceil(65_535), 1]
            }
            Groups::Tiles { per_group } => [(rect.tiles() as u32).div_ceil(per_group), 1, 1],
            Groups::Blocks { side, layers } => [rect.w.div_ceil(side), rect.h.div_ceil(side), layers],
            Groups::PixelTiles { tiles_per_group } => [rect.w.div_ceil(8), rect.h.div_ceil(8).div_ceil(tiles_per_group), 1],
            // A field pass has no queue to read its counts from: `bind` refuses it.
            Groups::Indirect { .. } => [0, 0, 0],
        }
    }

    /// Writes an edit in place into the field's resources: the bind group
    /// stays valid (same buffers).
    pub fn write(&self, gpu: &Gpu, writes: &[FieldWrite]) -> Result<(), &'static str> {
        const FOREIGN: &str = "the edit does not fit the field's buffers: it belongs to another field";
        for w in writes {
            match w {
                FieldWrite::Texels { binding, first, texels } => {
                    let tex = self.textures.iter().find(|(b, _, _)| b == binding).map(|(_, t, _)| t).ok_or(FOREIGN)?;
                    write_texel_rows(gpu, tex, *first, texels).ok_or(FOREIGN)?;
                }
                FieldWrite::Bytes { binding, offset, bytes } => {
                    let buf = self.buffers.iter().find(|(b, _)| b == binding).map(|(_, b)| b).ok_or(FOREIGN)?;
                    if offset + bytes.len() as u64 > buf.size() {
                        return Err(FOREIGN);
                    }
                    gpu.queue.write_buffer(buf, *offset, bytes);
                }
            }
        }
        Ok(())
    }

    /// The bind group of these resources and a dispatch's.
    pub fn group(&self, d: &wgpu::Device, layout: &wgpu::BindGroupLayout, per_dispatch: &PerDispatch) -> wgpu::BindGroup {
        let views = self.textures.iter().chain(&per_dispatch.textures).map(|(b, _, view)| wgpu::BindGroupEntry { binding: *b, resource: wgpu::BindingResource::TextureView(view) });
        let buffers = self.buffers.iter().chain(&per_dispatch.buffers).map(|(b, buf)| wgpu::BindGroupEntry { binding: *b, resource: buf.as_entire_binding() });
        let entries: Vec<wgpu::BindGroupEntry> = buffers.chain(views).collect();
        d.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("field"), layout, entries: &entries })
    }
}

/// A smallest buffer standing in for statistics nobody reads.
fn token(gpu: &Gpu, label: &str) -> wgpu::Buffer {
    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
    gpu.device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: 16, usage, mapped_at_creation: false })
}

/// Writes vec4 `texels` from texel `first` of `tex`, row by row (the rows
/// may wrap onto the next texture row); `None` if they do not fit.
fn write_texel_rows(gpu: &Gpu, tex: &wgpu::Texture, first: u64, texels: &[[f32; 4]]) -> Option<()> {
    let width = u64::from(tex.width());
    if first + texels.len() as u64 > width * u64::from(tex.height()) {
        return None;
    }
    let (mut at, mut rest) = (first, texels);
    while !rest.is_empty() {
        let (x, y) = (at % width, at / width);
        let n = rest.len().min((width - x) as usize);
        gpu.queue.write_texture(
            wgpu::TexelCopyTextureInfo { texture: tex, mip_level: 0, origin: wgpu::Origin3d { x: x as u32, y: y as u32, z: 0 }, aspect: wgpu::TextureAspect::All },
            bytemuck::cast_slice(&rest[..n]),
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(n as u32 * 16), rows_per_image: None },
            wgpu::Extent3d { width: n as u32, height: 1, depth_or_array_layers: 1 },
        );
        rest = &rest[n..];
        at += n as u64;
    }
    Some(())
}
