//! The field group (`@group(1)`) of a render kernel: the buffers a field
//! source binds, and the passes it runs before the traversal. A compiled
//! formula lives in the shader and binds none; a tape binds its
//! instructions; a scene binds its nodes,
//! parameters, primitives and bounding balls once, and per dispatch the
//! tile lists and pruned views its pre-passes build.

use super::dispatch::Rect;
use super::{storage_entry, Gpu, GpuError};
use crate::codegen::kernel::{SCENE_TILE_MAX, SCENE_VIEW_MAX};
use crate::codegen::FieldSource;

/// A field source's layout entries, buffers and pre-passes.
pub(crate) struct FieldBinding {
    /// Layout of the field group (static and per-dispatch entries).
    pub layout: Vec<wgpu::BindGroupLayoutEntry>,
    /// (binding, buffer) pairs that live as long as the field.
    pub buffers: Vec<(u32, wgpu::Buffer)>,
    /// Primitives of a scene (0 for a compiled field).
    prims: u32,
    scene: bool,
    /// A scene evaluates its whole tree in every tile (the dense baseline).
    pub dense: bool,
    /// An interpreted tape: bisection's budget must leave room for its work.
    pub tape: bool,
}

impl FieldBinding {
    /// The field's bits of the frame flags.
    pub fn flags(&self) -> u32 {
        if self.scene && self.dense { crate::layout::FLAG_SCENE_FULL } else { 0 }
    }

    /// Whether the field reports per-tile statistics.
    pub fn has_tile_stats(&self) -> bool {
        self.scene
    }

    /// Bytes of the per-tile statistics a field reports for a rectangle
    /// (a scene's view length and active primitives per tile), read back
    /// with the pixels; 0 when it has none.
    pub fn tile_stats_size(&self, rect: Rect) -> u64 {
        if self.has_tile_stats() { rect.tiles() * 8 } else { 0 }
    }

    /// The per-dispatch buffers of a rectangle (a scene's tile lists and
    /// views, zeroed), with `stats` (of [`FieldBinding::tile_stats_size`]
    /// bytes, read back by the caller) bound where the field writes them.
    pub fn per_dispatch(&self, gpu: &Gpu, rect: Rect, stats: Option<&wgpu::Buffer>) -> Vec<(u32, wgpu::Buffer)> {
        let (true, Some(stats)) = (self.scene, stats) else { return vec![] };
        let tiles = rect.tiles();
        let buffer = |label, size: u64| gpu.device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: size.max(16), usage: wgpu::BufferUsages::STORAGE, mapped_at_creation: false });
        vec![
            (4, buffer("scene tile counts", tiles * 4)),
            (5, buffer("scene tile primitives", tiles * SCENE_TILE_MAX as u64 * 4)),
            (6, buffer("scene tile views", tiles * SCENE_VIEW_MAX as u64 * 4)),
            (7, stats.clone()),
        ]
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
    /// changed parameter rows and bounding ball, nothing else. The bind
    /// group stays valid (same buffers).
    pub fn patch_scene(&self, gpu: &Gpu, patch: &crate::scene::linear::ScenePatch) -> Result<(), &'static str> {
        let find = |b: u32| self.buffers.iter().find(|(k, _)| *k == b).map(|(_, buf)| buf);
        let (Some(params), Some(balls), true) = (find(1), find(3), self.scene) else {
            return Err("an edit in place applies to a scene field");
        };
        let end = (patch.param_row as u64 + patch.params.len() as u64) * 16;
        if end > params.size() || (patch.ball_index as u64 + 1) * 16 > balls.size() {
            return Err("the edit does not fit the scene's buffers: it belongs to another scene");
        }
        gpu.queue.write_buffer(params, patch.param_row as u64 * 16, bytemuck::cast_slice(&patch.params));
        gpu.queue.write_buffer(balls, patch.ball_index as u64 * 16, bytemuck::cast_slice(&[patch.ball]));
        Ok(())
    }

    /// The bind group of these buffers and a dispatch's.
    pub fn group(&self, d: &wgpu::Device, layout: &wgpu::BindGroupLayout, per_dispatch: &[(u32, wgpu::Buffer)]) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry> =
            self.buffers.iter().chain(per_dispatch).map(|(b, buf)| wgpu::BindGroupEntry { binding: *b, resource: buf.as_entire_binding() }).collect();
        d.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("field"), layout, entries: &entries })
    }
}

/// Uploads what `source` needs on the device.
pub(crate) fn bind(gpu: &Gpu, source: FieldSource<'_>) -> Result<FieldBinding, GpuError> {
    match source {
        FieldSource::Compiled(_) => Ok(FieldBinding { layout: vec![], buffers: vec![], prims: 0, scene: false, dense: false, tape: false }),
        FieldSource::Scene(s) => {
            let mut layout: Vec<_> = (0..4).map(|b| storage_entry(b, true)).collect();
            layout.extend((4..8).map(|b| storage_entry(b, false)));
            let buffers = vec![
                (0, gpu.storage("scene nodes", bytemuck::cast_slice(&s.nodes))?),
                (1, gpu.storage("scene params", bytemuck::cast_slice(&s.params))?),
                (2, gpu.storage("scene primitives", bytemuck::cast_slice(&s.prims))?),
                (3, gpu.storage("scene balls", bytemuck::cast_slice(&s.balls))?),
            ];
            Ok(FieldBinding { layout, buffers, prims: s.prims.len() as u32, scene: true, dense: false, tape: false })
        }
        FieldSource::Tape(t) => {
            let buffers = vec![(0, gpu.storage("tape", bytemuck::cast_slice(&t.words))?)];
            Ok(FieldBinding { layout: vec![storage_entry(0, true)], buffers, prims: 0, scene: false, dense: false, tape: true })
        }
    }
}
