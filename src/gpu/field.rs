//! The field group (`@group(1)`) of a render kernel: the buffers a field
//! source binds. A compiled formula lives in the shader and binds none; a
//! data-driven source (a scene's nodes, a tape) adds its buffers here
//! without touching the traversal's groups.

use super::{Gpu, GpuError};
use crate::codegen::FieldSource;

/// A field source's layout entries and buffers.
pub(crate) struct FieldBinding {
    /// Layout of the field group.
    pub layout: Vec<wgpu::BindGroupLayoutEntry>,
    /// (binding, buffer) pairs.
    pub buffers: Vec<(u32, wgpu::Buffer)>,
}

impl FieldBinding {
    /// The bind group of these buffers.
    pub fn group(&self, d: &wgpu::Device, layout: &wgpu::BindGroupLayout) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry> = self.buffers.iter().map(|(b, buf)| wgpu::BindGroupEntry { binding: *b, resource: buf.as_entire_binding() }).collect();
        d.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("field"), layout, entries: &entries })
    }
}

/// Uploads what `source` needs on the device.
pub(crate) fn bind(gpu: &Gpu, source: FieldSource<'_>) -> Result<FieldBinding, GpuError> {
    match source {
        FieldSource::Compiled(_) => Ok(FieldBinding { layout: vec![], buffers: vec![] }),
        FieldSource::Scene(s) => Ok(FieldBinding {
            layout: vec![super::storage_entry(0, true), super::storage_entry(1, true)],
            buffers: vec![(0, gpu.storage("scene nodes", bytemuck::cast_slice(&s.nodes))?), (1, gpu.storage("scene params", bytemuck::cast_slice(&s.params))?)],
        }),
    }
}
