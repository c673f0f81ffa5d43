//! What one dispatch of a render kernel over a rectangle binds: the
//! uniforms, the traversal's pass buffers, the outputs read back, the
//! field's per-dispatch resources and the three bind groups (frame, field,
//! pass). Every frame binds its rectangles this way, and so does the
//! warm-up dispatch a new renderer sends before its first frame.

use super::dispatch::{Dispatch, Groups, Rect, Stage};
use super::field::{FieldBinding, PerDispatch};
use super::renderer::{PassBuffers, TraversalHost};
use super::{Gpu, GpuError};
use crate::render::record::Record;

/// Output slots read back after a dispatch: the pixel records, sphere
/// tracing's per-ray words, a field's per-tile statistics.
pub(crate) const OUTPUTS: usize = 3;

/// The kernel's side of binding: what every dispatch of one renderer shares.
pub(crate) struct Binder<'a> {
    pub gpu: &'a Gpu,
    pub host: &'a dyn TraversalHost,
    pub field: &'a FieldBinding,
    pub layouts: &'a [wgpu::BindGroupLayout; 3],
}

/// One rectangle's resources and bind groups (kept alive together).
pub(crate) struct RectBinding {
    /// The pass group's buffers besides the outputs.
    pub pass: PassBuffers,
    /// Each output slot's buffer and the buffer to map, where the slot is used.
    pub outputs: Vec<Option<(wgpu::Buffer, wgpu::Buffer)>>,
    /// Each output slot's size in bytes (0: unused).
    pub sizes: [u64; OUTPUTS],
    /// The field's resources of this dispatch.
    pub field: PerDispatch,
    /// Frame, field and pass groups.
    pub groups: [wgpu::BindGroup; 3],
}

impl Binder<'_> {
    /// Binds a dispatch over `rect` with `uniforms` (frame block, then the
    /// traversal's block); `output(slot, size)` gives each used output slot
    /// its buffer and the buffer to map.
    pub fn bind(&self, rect: Rect, uniforms: &[u8], output: impl Fn(usize, u64) -> (wgpu::Buffer, wgpu::Buffer)) -> Result<RectBinding, GpuError> {
        let rays = self.host.ray_stats_binding();
        let uniforms = self.gpu.storage("uniforms", uniforms)?;
        let pass = self.host.pass_buffers(self.gpu, rect, self.field.resumes());
        let per_pixel = std::mem::size_of::<Record>() as u64;
        let sizes = [rect.pixels() * per_pixel, if rays.is_some() { rect.pixels() * 4 } else { 0 }, self.field.tile_stats_size(rect)];
        let outputs: Vec<_> = sizes.iter().enumerate().map(|(slot, &size)| (size > 0).then(|| output(slot, size))).collect();
        let field = self.field.per_dispatch(self.gpu, rect, outputs[2].as_ref().map(|o| &o.0));
        let (frame_group, pass_group) = self.gpu.scoped("bind groups", || self.frame_and_pass(&uniforms, &pass, &outputs, rays))?;
        let field_group = self.gpu.scoped("field bind group", || self.field.group(&self.gpu.device, &self.layouts[1], &field))?;
        Ok(RectBinding { pass, outputs, sizes, field, groups: [frame_group, field_group, pass_group] })
    }

    /// The frame and pass bind groups of one dispatch.
    fn frame_and_pass(&self, uniforms: &wgpu::Buffer, pass: &PassBuffers, outputs: &[Option<(wgpu::Buffer, wgpu::Buffer)>], rays: Option<u32>) -> (wgpu::BindGroup, wgpu::BindGroup) {
        let d = &self.gpu.device;
        fn entry(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry { binding, resource: b.as_entire_binding() }
        }
        let resources = self.host.frame_resources();
        let mut frame = vec![entry(crate::kernel::bindings::UNIFORMS.binding, uniforms)];
        frame.extend(resources.iter().map(|(e, b)| entry(e.binding, b)));
        let pixels = &outputs[0].as_ref().expect("pixel records").0;
        let mut out = vec![entry(crate::kernel::bindings::PIXEL_RECORDS.binding, pixels)];
        out.extend(pass.entries.iter().map(|(i, b)| entry(*i, b)));
        if let (Some(i), Some(Some(o))) = (rays, outputs.get(1)) {
            out.push(entry(i, &o.0));
        }
        let group = |label, layout, entries: &[wgpu::BindGroupEntry]| d.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(label), layout, entries });
        (group("frame", &self.layouts[0], &frame), group("pass", &self.layouts[2], &out))
    }

    /// Sends each of `pipelines` to the device in a dispatch of no
    /// workgroups over a 8×8 rectangle, without waiting. lavapipe compiles a
    /// pipeline's machine code at its first dispatch (LLVM, on its queue's
    /// thread), so a renderer warms its tile pass and its field's passes
    /// up this way while its per-pixel pass is still being created on the
    /// other core: the first frame does not wait for them. Best effort: a
    /// warm-up that fails leaves the compile to the first frame.
    pub fn warm_up(&self, pipelines: &[wgpu::ComputePipeline], uniforms: &[u8]) -> Result<(), GpuError> {
        let d = &self.gpu.device;
        let rect = Rect { x: 0, y: 0, w: 8, h: 8 };
        let own = |_, size| {
            let b = d.create_buffer(&wgpu::BufferDescriptor { label: Some("warm-up output"), size, usage: wgpu::BufferUsages::STORAGE, mapped_at_creation: false });
            (b.clone(), b)
        };
        let b = self.bind(rect, uniforms, own)?;
        let job = Dispatch {
            label: "warm-up",
            stages: pipelines.iter().map(|pipeline| Stage { pipeline, groups: Groups::Direct([0, 0, 0]), copy: None }).collect(),
            groups: [&b.groups[0], &b.groups[1], &b.groups[2]],
            outputs: vec![],
            clears: vec![],
        };
        self.gpu.scoped("warm-up", || job.submit(self.gpu))
    }
}
