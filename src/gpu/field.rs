//! The field group (`@group(1)`) of a render kernel: the buffers a field
//! source binds, and the passes it runs before the traversal. A compiled
//! formula lives in the shader and binds none; a tape binds its
//! instructions; a scene binds its nodes,
//! parameters, primitives and bounding balls once, and per dispatch the
//! tile lists and pruned views its pre-passes build.

use super::dispatch::Rect;
use super::{storage_entry, texture_entry, Gpu, GpuError};
use crate::field::scene::{SCENE_TILE_MAX, SCENE_VIEW_MAX};
use crate::field::FieldSource;

/// Binding of the texture the views pass's output is copied into.
const VIEW_TEXTURE: u32 = 10;
/// Binding of the counts zeroed before each dispatch: a scene's tile
/// counts, a tape's words of per-tile lists in use.
const COUNTS: u32 = 4;
/// Binding of a tape's per-tile lists (`templates/fields/tape_tiles.wgsl`).
const TAPE_LISTS: u32 = 1;
/// Binding of a compiled field's per-tile term lists (`templates/fields/loop_tiles.wgsl`).
const LOOP_LISTS: u32 = 1;
/// Binding of a tape's per-tile choice notes (`NOTE_BYTES_PER_TILE`).
const TAPE_NOTES: u32 = 5;
/// Binding of the views pass's output buffer.
const VIEW_BUFFER: u32 = 6;
/// Texels a row of the view texture.
const VIEW_WIDTH: u64 = crate::field::scene::SCENE_VIEW_TEX_WIDTH as u64;

/// A dispatch's own field resources: the tile lists and views, and the
/// view texture the trace reads the views from. Kept for the next dispatch
/// of as many tiles (making and zeroing them anew is a large part of a
/// frame on lavapipe): only the tile counts must start at zero, everything
/// else is written before it is read.
#[derive(Clone)]
pub(crate) struct PerDispatch {
    buffers: Vec<(u32, wgpu::Buffer)>,
    view: Option<(wgpu::Texture, wgpu::TextureView)>,
}

impl PerDispatch {
    /// The buffers to zero before the dispatch (the tile counts, appended to).
    pub fn clears(&self) -> Vec<wgpu::Buffer> {
        self.buffers.iter().filter(|(b, _)| *b == COUNTS).map(|(_, b)| b.clone()).collect()
    }

    /// The copy of the views pass's output into the view texture (after
    /// that pass; a buffer cannot be a texture, and the trace reads the
    /// views as texels: lavapipe loads storage at a per-lane address lane
    /// by lane).
    pub fn view_copy(&self) -> Option<(&wgpu::Buffer, &wgpu::Texture)> {
        let buf = self.buffers.iter().find(|(b, _)| *b == VIEW_BUFFER).map(|(_, b)| b)?;
        self.view.as_ref().map(|(t, _)| (buf, t))
    }
}

/// A field source's layout entries, buffers and pre-passes.
pub(crate) struct FieldBinding {
    /// Layout of the field group (static and per-dispatch entries).
    pub layout: Vec<wgpu::BindGroupLayoutEntry>,
    /// (binding, buffer) pairs that live as long as the field.
    pub buffers: Vec<(u32, wgpu::Buffer)>,
    /// A scene's node and parameter textures (bindings 0 and 1).
    textures: Vec<(u32, wgpu::Texture, wgpu::TextureView)>,
    /// Primitives of a scene (0 for a compiled field).
    prims: u32,
    scene: bool,
    /// A scene evaluates its whole tree in every tile (the dense baseline).
    pub dense: bool,
    /// An interpreted tape: bisection's budget must leave room for its work.
    pub tape: bool,
    /// A compiled formula with rerolled loops (`crate::field::compiled::term_loops`): the same
    /// budget rule as a tape.
    pub looped: bool,
    /// See [`FieldBinding::resumes`].
    resumes: bool,
    /// The tape, for the size of its per-tile lists (bisection's; `None`
    /// for other fields and traversals).
    tape_lists: Option<crate::field::TapeData>,
    /// A compiled formula's per-tile term lists of its rerolled min and max
    /// loops (`templates/fields/loop_tiles.wgsl`; bisection's only: `None`
    /// for other traversals, which bind token buffers in their place).
    loop_lists: Option<crate::field::compiled::term_loops::lists::Lists>,
    /// The field group has the lists' bindings (a formula with listed
    /// loops, whatever the traversal).
    lists_bound: bool,
    /// The last dispatch's own resources and its tile count.
    cached: std::sync::Mutex<Option<(u64, PerDispatch)>>,
}

impl FieldBinding {
    /// The kind of field source bound.
    pub fn kind(&self) -> crate::field::FieldKind {
        use crate::field::FieldKind;
        if self.scene { FieldKind::Scene } else if self.tape { FieldKind::Tape } else { FieldKind::Compiled }
    }

    /// Only bisection's tile pass shortens a tape: other traversals bind
    /// a token buffer for its lists. A kernel built with per-tile lists
    /// (`kernel_features`: min and max) reads its blocks' entries there
    /// whatever tape it runs, so the lists are sized for them.
    pub fn keep_lists(&mut self, keep: bool, kernel_features: u32) {
        if !keep {
            self.tape_lists = None;
            self.loop_lists = None;
        }
        if let Some(t) = &mut self.tape_lists {
            t.features |= kernel_features & crate::field::tape::features::MINMAX;
        }
    }

    /// A kernel with `--inline` WGSL has no term lists (`compiled::field_code`
    /// leaves its hooks to the user): nothing to size or count.
    pub fn no_loop_lists(&mut self) {
        self.loop_lists = None;
    }

    /// Whether bisection runs the field's block pass before its tile pass
    /// (a tape kernel with per-tile lists: its tile pass reads the blocks'
    /// entries, `templates/fields/tape_tiles.wgsl`).
    pub fn block_pass(&self) -> bool {
        self.tape_lists.as_ref().is_some_and(|t| crate::field::tape::wgsl::shortens(t.features))
    }

    /// Whether bisection's tile pass may shorten the bound tape per tile:
    /// it has min or max instructions (choice slots).
    pub fn shortens_tape(&self) -> bool {
        self.tape_lists.as_ref().is_some_and(|t| crate::field::tape::wgsl::shortens(t.features) && t.words[2][2] > 0)
    }

    /// Whether bisection's per-pixel pass runs in rounds that resume the
    /// pixels the field's work limit stopped: a tape, or a compiled formula
    /// with rerolled loops and no per-tile term lists
    /// (`kernel::cells_resume`).
    pub fn resumes(&self) -> bool {
        self.resumes
    }

    /// Whether bisection's tile pass lists the terms of the bound compiled
    /// formula's min and max loops per tile.
    pub fn lists_loops(&self) -> bool {
        self.loop_lists.is_some()
    }

    /// The field's bits of the frame flags.
    pub fn flags(&self) -> u32 {
        if self.scene && self.dense { crate::layout::FLAG_SCENE_FULL } else { 0 }
    }

    /// Whether the field reports per-tile statistics.
    pub fn has_tile_stats(&self) -> bool {
        self.scene
    }

    /// Bytes of the statistics a field reports for a rectangle, read back
    /// with the pixels and bound where the field writes them: a scene's view
    /// length and active primitives per tile, or a tape's counts of its
    /// per-tile lists ([`crate::render::TapeListStats`]); 0 when it has none.
    pub fn tile_stats_size(&self, rect: Rect) -> u64 {
        if self.loop_lists.is_some() {
            crate::render::LoopListStats::BYTES
        } else if self.has_tile_stats() {
            rect.tiles() * 8
        } else if self.tape {
            crate::render::TapeListStats::BYTES
        } else {
            0
        }
    }

    /// Bytes per pixel of the field's largest per-dispatch buffer (a
    /// scene's per-tile lists and views over the 64 pixels of a tile): the
    /// dispatch rectangle must keep it within one storage binding.
    pub fn bytes_per_pixel(&self) -> u64 {
        if self.block_pass() {
            // A tape's choice notes: 2 KB an 8×8 tile.
            return crate::field::tape::wgsl::NOTE_BYTES_PER_TILE / 64;
        }
        if let Some(l) = &self.loop_lists {
            return l.bytes(1).div_ceil(64);
        }
        if !self.scene {
            return 0;
        }
        [SCENE_TILE_MAX as u64 * 8, SCENE_VIEW_MAX as u64 * 4].into_iter().max().unwrap_or(0) / 64
    }

    /// The most pixels a dispatch may cover: a scene's view texture holds
    /// SCENE_VIEW_MAX texels a tile in rows of VIEW_WIDTH, at most the
    /// device's texture side of rows.
    pub fn max_pixels(&self, gpu: &Gpu) -> u64 {
        if !self.scene {
            return u64::MAX;
        }
        let rows = gpu.device.limits().max_texture_dimension_2d as u64;
        rows * VIEW_WIDTH / SCENE_VIEW_MAX as u64 * 64
    }

    /// The per-dispatch resources of a rectangle (a scene's tile lists and
    /// views, and the view texture; kept from the last dispatch of as many
    /// tiles, see [`PerDispatch`]), with `stats` (of [`FieldBinding::tile_stats_size`]
    /// bytes, read back by the caller) bound where the field writes them.
    pub fn per_dispatch(&self, gpu: &Gpu, rect: Rect, stats: Option<&wgpu::Buffer>) -> PerDispatch {
        let tiles = rect.tiles();
        if self.lists_bound {
            return self.loop_per_dispatch(gpu, tiles, stats);
        }
        if self.tape {
            let mut own = self.tape_per_dispatch(gpu, tiles);
            if let Some(counts) = stats {
                own.buffers.push((COUNTS, counts.clone()));
            }
            return own;
        }
        let (true, Some(stats)) = (self.scene, stats) else { return PerDispatch { buffers: vec![], view: None } };
        let mut cached = self.cached.lock().unwrap_or_else(|e| e.into_inner());
        let mut own = match cached.take() {
            Some((n, own)) if n == tiles => own,
            _ => self.make_per_dispatch(gpu, tiles),
        };
        *cached = Some((tiles, own.clone()));
        own.buffers.push((7, stats.clone()));
        own
    }

    /// A tape's per-dispatch lists for `tiles` tiles (kept for the next
    /// dispatch of as many; only the counts are zeroed).
    fn tape_per_dispatch(&self, gpu: &Gpu, tiles: u64) -> PerDispatch {
        let mut cached = self.cached.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((n, own)) = cached.as_ref() {
            if *n == tiles {
                return own.clone();
            }
        }
        let buffer = |label, size: u64, usage| gpu.device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: size.max(16), usage, mapped_at_creation: false });
        let storage = wgpu::BufferUsages::STORAGE;
        let bytes = self.tape_lists.as_ref().map_or(0, |t| crate::field::tape::wgsl::list_bytes(t, tiles));
        // The counts (binding COUNTS) are the caller's read-back buffer.
        // Only a kernel with per-tile lists notes choices (a tape without
        // min or max binds a token buffer).
        let notes = if self.block_pass() { tiles * crate::field::tape::wgsl::NOTE_BYTES_PER_TILE } else { 0 };
        let own = PerDispatch { buffers: vec![(TAPE_LISTS, buffer("tape lists", bytes, storage)), (TAPE_NOTES, buffer("tape notes", notes, storage))], view: None };
        *cached = Some((tiles, own.clone()));
        own
    }

    /// A compiled field's per-tile term lists for `tiles` tiles (kept for
    /// the next dispatch of as many; only the counts are zeroed), and its
    /// counts `stats`: token buffers for a traversal without the lists.
    fn loop_per_dispatch(&self, gpu: &Gpu, tiles: u64, stats: Option<&wgpu::Buffer>) -> PerDispatch {
        let buffer = |label, size: u64| {
            let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
            gpu.device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: size.max(16), usage, mapped_at_creation: false })
        };
        let mut cached = self.cached.lock().unwrap_or_else(|e| e.into_inner());
        let mut own = match cached.take() {
            Some((n, own)) if n == tiles => own,
            _ => PerDispatch { buffers: vec![(LOOP_LISTS, buffer("loop lists", self.loop_lists.as_ref().map_or(0, |l| l.bytes(tiles))))], view: None },
        };
        *cached = Some((tiles, own.clone()));
        own.buffers.push((COUNTS, stats.cloned().unwrap_or_else(|| buffer("loop list counts", 16))));
        own
    }

    /// A dispatch's own resources for `tiles` tiles (without the statistics).
    fn make_per_dispatch(&self, gpu: &Gpu, tiles: u64) -> PerDispatch {
        let buffer = |label, size: u64, usage| gpu.device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: size.max(16), usage, mapped_at_creation: false });
        let storage = wgpu::BufferUsages::STORAGE;
        // Whole rows of the view texture (a row holds several tiles' views).
        let rows = (tiles * SCENE_VIEW_MAX as u64).div_ceil(VIEW_WIDTH);
        let view = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("scene tile view texels"),
            size: wgpu::Extent3d { width: VIEW_WIDTH as u32, height: rows as u32, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Uint,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let view_view = view.create_view(&Default::default());
        let buffers = vec![
            (COUNTS, buffer("scene tile counts", tiles * 4, storage | wgpu::BufferUsages::COPY_DST)),
            (5, buffer("scene tile primitives", tiles * SCENE_TILE_MAX as u64 * 4, storage)),
            (VIEW_BUFFER, buffer("scene tile views", rows * VIEW_WIDTH * 4, storage | wgpu::BufferUsages::COPY_SRC)),
            (9, buffer("scene tile depths", tiles * SCENE_TILE_MAX as u64 * 8, storage)),
        ];
        PerDispatch { buffers, view: Some((view, view_view)) }
    }

    /// The pre-passes over a rectangle, in order, with their workgroups:
    /// the scatter runs an invocation per primitive, the view pass one per
    /// tile (64 to a workgroup).
    pub fn passes(&self, rect: Rect) -> Vec<[u32; 3]> {
        if !self.scene {
            return vec![];
        }
        let groups = self.prims.div_ceil(64).max(1);
        let (x, y) = (groups.min(65_535), groups.div_ceil(65_535));
        vec![[x, y, 1], [(rect.tiles() as u32).div_ceil(64), 1, 1]]
    }

    /// Uploads an edit in place of a scene (`Linear::set_primitive`): the
    /// changed parameter rows and balls, nothing else. The bind
    /// group stays valid (same buffers).
    pub fn patch_scene(&self, gpu: &Gpu, patch: &crate::scene::linear::ScenePatch) -> Result<(), &'static str> {
        let balls = self.buffers.iter().find(|(k, _)| *k == 3).map(|(_, buf)| buf);
        let params = self.textures.iter().find(|(k, _, _)| *k == 1).map(|(_, t, _)| t);
        let (Some(params), Some(balls), true) = (params, balls, self.scene) else {
            return Err("an edit in place applies to a scene field");
        };
        let width = crate::scene::linear::TEXTURE_WIDTH as u64;
        let end = patch.param_row as u64 + patch.params.len() as u64;
        if end > width * params.height() as u64 || patch.balls.iter().any(|&(i, _)| (i as u64 + 1) * 16 > balls.size()) {
            return Err("the edit does not fit the scene's buffers: it belongs to another scene");
        }
        // The rows may wrap onto the next texture row: one write per piece.
        let mut row = patch.param_row as u64;
        let mut rest: &[[f32; 4]] = &patch.params;
        while !rest.is_empty() {
            let (x, y) = (row % width, row / width);
            let n = rest.len().min((width - x) as usize);
            gpu.queue.write_texture(
                wgpu::TexelCopyTextureInfo { texture: params, mip_level: 0, origin: wgpu::Origin3d { x: x as u32, y: y as u32, z: 0 }, aspect: wgpu::TextureAspect::All },
                bytemuck::cast_slice(&rest[..n]),
                wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(n as u32 * 16), rows_per_image: None },
                wgpu::Extent3d { width: n as u32, height: 1, depth_or_array_layers: 1 },
            );
            rest = &rest[n..];
            row += n as u64;
        }
        for (i, b) in &patch.balls {
            gpu.queue.write_buffer(balls, *i as u64 * 16, bytemuck::cast_slice(&[*b]));
        }
        Ok(())
    }

    /// The bind group of these buffers and a dispatch's.
    pub fn group(&self, d: &wgpu::Device, layout: &wgpu::BindGroupLayout, per_dispatch: &PerDispatch) -> wgpu::BindGroup {
        let views = self.textures.iter().map(|(b, _, view)| (*b, view)).chain(per_dispatch.view.as_ref().map(|(_, v)| (VIEW_TEXTURE, v)));
        let textures = views.map(|(b, view)| wgpu::BindGroupEntry { binding: b, resource: wgpu::BindingResource::TextureView(view) });
        let entries: Vec<wgpu::BindGroupEntry> =
            self.buffers.iter().chain(&per_dispatch.buffers).map(|(b, buf)| wgpu::BindGroupEntry { binding: *b, resource: buf.as_entire_binding() }).chain(textures).collect();
        d.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("field"), layout, entries: &entries })
    }
}

/// Uploads what `source` needs on the device.
pub(crate) fn bind(gpu: &Gpu, source: FieldSource<'_>) -> Result<FieldBinding, GpuError> {
    match source {
        FieldSource::Compiled(ir) => {
            // Rerolled terms read their constants from a table (crate::field::compiled::term_loops).
            let (layout, textures) = match crate::field::compiled::term_loops::table_texels(ir) {
                Some(t) => {
                    let (tex, view) = gpu.texture("field table", &t, wgpu::TextureFormat::Rgba32Uint)?;
                    (vec![texture_entry(0, wgpu::TextureSampleType::Uint)], vec![(0, tex, view)])
                }
                None => (vec![], vec![]),
            };
            let looped = !textures.is_empty();
            // Per-tile term lists of its min and max loops (bound for every
            // kernel of the formula; only bisection's reads them).
            let loop_lists = crate::field::compiled::term_loops::lists::for_formula(ir);
            let mut layout = layout;
            if loop_lists.is_some() {
                layout.extend([storage_entry(LOOP_LISTS, false), storage_entry(COUNTS, false)]);
            }
            let lists_bound = loop_lists.is_some();
            let resumes = crate::kernel::cells_resume(FieldSource::Compiled(ir));
            Ok(FieldBinding { layout, buffers: vec![], textures, prims: 0, scene: false, dense: false, tape: false, looped, resumes, tape_lists: None, loop_lists, lists_bound, cached: Default::default() })
        }
        FieldSource::Scene(s) => {
            let mut layout = vec![
                texture_entry(0, wgpu::TextureSampleType::Uint),
                texture_entry(1, wgpu::TextureSampleType::Float { filterable: false }),
            ];
            layout.extend((2..4).map(|b| storage_entry(b, true)));
            layout.extend([4, 5, 6, 7, 9].map(|b| storage_entry(b, false)));
            layout.push(texture_entry(VIEW_TEXTURE, wgpu::TextureSampleType::Uint));
            let (nodes, nodes_view) = gpu.texture("scene nodes", &s.node_texels(), wgpu::TextureFormat::Rgba32Uint)?;
            let (params, params_view) = gpu.texture("scene params", &s.param_texels(), wgpu::TextureFormat::Rgba32Float)?;
            let buffers = vec![
                (2, gpu.storage("scene primitives", bytemuck::cast_slice(&s.prims))?),
                (3, gpu.storage("scene balls", bytemuck::cast_slice(&s.balls))?),
            ];
            let textures = vec![(0, nodes, nodes_view), (1, params, params_view)];
            Ok(FieldBinding { layout, buffers, textures, prims: s.prims.len() as u32, scene: true, dense: false, tape: false, looped: false, resumes: false, tape_lists: None, loop_lists: None, lists_bound: false, cached: Default::default() })
        }
        FieldSource::Tape(t) => {
            let (tex, view) = gpu.texture("tape", &t.texels(), wgpu::TextureFormat::Rgba32Uint)?;
            // Bisection's per-tile lists (bound for every tape kernel, so
            // one layout serves every tape; unused by the others).
            let layout = vec![texture_entry(0, wgpu::TextureSampleType::Uint), storage_entry(TAPE_LISTS, false), storage_entry(COUNTS, false), storage_entry(TAPE_NOTES, false)];
            Ok(FieldBinding { layout, buffers: vec![], textures: vec![(0, tex, view)], prims: 0, scene: false, dense: false, tape: true, looped: false, resumes: true, tape_lists: Some(t.clone()), loop_lists: None, lists_bound: false, cached: Default::default() })
        }
    }
}
