//! The one tile loop of every render: a frame is split into rectangles that
//! fit the device (storage binding size, dispatch size) and a watchdog's
//! patience, and each rectangle is one submission: an optional pre-pass
//! over 8×8 tiles that queues work for an indirect dispatch, the per-pixel
//! pass, and the read-back of the pass group's outputs.

use super::{Gpu, GpuError};
use std::sync::Mutex;

/// A rectangle of the image rendered by one dispatch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rect {
    /// First column.
    pub x: u32,
    /// First row.
    pub y: u32,
    /// Width.
    pub w: u32,
    /// Height.
    pub h: u32,
}

impl Rect {
    /// Pixels in the rectangle.
    pub fn pixels(&self) -> u64 {
        self.w as u64 * self.h as u64
    }

    /// 8×8 tiles covering the rectangle.
    pub fn tiles(&self) -> u64 {
        self.w.div_ceil(8) as u64 * self.h.div_ceil(8) as u64
    }
}

/// The rectangles of a `w × h` frame with sides of at most `side`, row by row.
pub fn split(w: u32, h: u32, side: u32) -> impl Iterator<Item = Rect> {
    let side = side.max(8) as usize;
    (0..h).step_by(side).flat_map(move |y| (0..w).step_by(side).map(move |x| Rect { x, y, w: (side as u32).min(w - x), h: (side as u32).min(h - y) }))
}

/// The largest rectangle side for a device: its outputs (`bytes_per_pixel`
/// in the largest buffer) must fit one storage binding; an indirect
/// per-pixel dispatch (one workgroup per `indirect` queued 8×8 tiles, all in
/// x) must stay within 65,535 workgroups (4088 pixels with 4 tiles a
/// group); and it must not exceed the user's `tile`.
pub fn max_side(gpu: &Gpu, bytes_per_pixel: u64, indirect: Option<u32>, tile: u32) -> u32 {
    let fit = ((gpu.max_storage_binding / bytes_per_pixel) as f64).sqrt() as u32 / 8 * 8;
    let groups = indirect.map_or(u32::MAX, |tpg| (65_535.0 * tpg as f64).sqrt() as u32 * 8);
    tile.clamp(8, crate::render::settings::MAX_SIZE).min(fit.max(8)).min(groups)
}

/// Output buffers of the pass group and their read-back copies, kept between
/// frames and tiles of the same size (allocating tens of MB a frame is a
/// noticeable part of a frame on lavapipe). Slot `i` is the i-th read-back
/// output.
#[derive(Default)]
pub struct Outputs(Mutex<Vec<Option<(u64, wgpu::Buffer, wgpu::Buffer)>>>);

impl Outputs {
    /// Output `slot` of `size` bytes and the buffer to map: the same one
    /// when the device maps storage buffers in place.
    pub fn get(&self, gpu: &Gpu, slot: usize, size: u64) -> (wgpu::Buffer, wgpu::Buffer) {
        let mut cache = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if cache.len() <= slot {
            cache.resize(slot + 1, None);
        }
        if cache[slot].as_ref().is_none_or(|(s, _, _)| *s != size) {
            let (out, staging) = output_buffers(gpu, size);
            cache[slot] = Some((size, out, staging));
        }
        let (_, out, staging) = cache[slot].as_ref().expect("just filled");
        (out.clone(), staging.clone())
    }
}

/// A new output buffer of `size` bytes and the buffer to map: the same one
/// when the device maps storage buffers in place.
pub fn output_buffers(gpu: &Gpu, size: u64) -> (wgpu::Buffer, wgpu::Buffer) {
    let d = &gpu.device;
    // COPY_DST: a field's counts among the outputs are zeroed before the dispatch.
    let map = wgpu::BufferUsages::COPY_DST | if gpu.map_in_place { wgpu::BufferUsages::MAP_READ } else { wgpu::BufferUsages::COPY_SRC };
    let out = d.create_buffer(&wgpu::BufferDescriptor { label: Some("pass output"), size, usage: wgpu::BufferUsages::STORAGE | map, mapped_at_creation: false });
    let staging = if gpu.map_in_place {
        out.clone()
    } else {
        d.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pass output read-back"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    };
    (out, staging)
}

/// How many workgroups a stage runs.
pub enum Groups<'a> {
    /// A fixed grid.
    Direct([u32; 3]),
    /// The counts an earlier stage of the same dispatch left in the first
    /// 12 bytes of `list` (reset to (0, 1, 1) before the submission): a
    /// pre-pass queues work for the next stage this way.
    Indirect(&'a wgpu::Buffer),
}

/// One compute pass of a dispatch.
pub struct Stage<'a> {
    /// Its pipeline.
    pub pipeline: &'a wgpu::ComputePipeline,
    /// Its workgroups.
    pub groups: Groups<'a>,
    /// A buffer the stage writes, copied into a texture after it (the
    /// whole texture, rows of 4-byte texels) for the stages after it.
    pub copy: Option<(&'a wgpu::Buffer, &'a wgpu::Texture)>,
}

/// One dispatch of a render kernel over a rectangle: its stages in order
/// (a field's pre-passes, a traversal's tile pass, the per-pixel pass), all
/// with the same three bind groups, in one submission.
pub struct Dispatch<'a> {
    /// Debug label.
    pub label: &'static str,
    /// The passes, in order.
    pub stages: Vec<Stage<'a>>,
    /// Frame, field and pass bind groups.
    pub groups: [&'a wgpu::BindGroup; 3],
    /// The outputs to read back: (buffer, its mappable copy, size).
    pub outputs: Vec<(wgpu::Buffer, wgpu::Buffer, u64)>,
    /// Buffers zeroed before the first stage (kept between dispatches).
    pub clears: Vec<wgpu::Buffer>,
}

/// GPU milliseconds of a dispatch: in all, and per stage.
#[derive(Debug, Clone, Default)]
pub struct Timing {
    /// Whole dispatch.
    pub total_ms: f64,
    /// Each stage (all zero without timestamp queries).
    pub stage_ms: Vec<f64>,
}

impl Dispatch<'_> {

    /// [`Dispatch::run`], leaving the first output's read-back buffer
    /// mapped and returning its view when `keep_first`.
    pub fn run_keeping(&self, gpu: &Gpu, keep_first: bool, unpack: impl FnOnce(&[&[u8]])) -> Result<(Timing, Option<wgpu::BufferView>), GpuError> {
        let d = &gpu.device;
        let queries = self.stages.len() as u32 + 1;
        let ts = gpu.timestamp_period.map(|_| {
            let set = d.create_query_set(&wgpu::QuerySetDescriptor { label: Some(self.label), ty: wgpu::QueryType::Timestamp, count: queries });
            let resolve = d.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps"),
                size: 8 * queries as u64,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            (set, resolve)
        });
        let t0 = std::time::Instant::now();
        let ts_staging = gpu.scoped(self.label, || {
            let mut enc = d.create_command_encoder(&Default::default());
            self.record(gpu, &mut enc, ts.as_ref().map(|(set, _)| set));
            let ts_staging = ts.as_ref().map(|(set, resolve)| {
                enc.resolve_query_set(set, 0..queries, resolve, 0);
                gpu.read_buffer(&mut enc, resolve, 8 * queries as u64)
            });
            if !gpu.map_in_place {
                for (out, staging, size) in &self.outputs {
                    enc.copy_buffer_to_buffer(out, 0, staging, 0, *size);
                }
            }
            gpu.queue.submit([enc.finish()]);
            ts_staging
        })?;
        let staging: Vec<&wgpu::Buffer> = self.outputs.iter().map(|(_, s, _)| s).collect();
        let ((), kept) = gpu.map_keeping(&staging, keep_first, unpack)?;
        let wall = t0.elapsed().as_secs_f64() * 1e3;
        let untimed = Timing { total_ms: wall, stage_ms: vec![0.0; self.stages.len()] };
        let Some((b, period)) = ts_staging.zip(gpu.timestamp_period) else { return Ok((untimed, kept)) };
        let t = gpu.map_read(&b)?;
        let v: &[u64] = bytemuck::cast_slice(&t);
        let ms = |a: u64, b: u64| b.saturating_sub(a) as f64 * period as f64 * 1e-6;
        let total = ms(v[0], v[queries as usize - 1]);
        if !(total > 0.0) {
            return Ok((untimed, kept));
        }
        Ok((Timing { total_ms: total, stage_ms: v.windows(2).map(|w| ms(w[0], w[1])).collect() }, kept))
    }

    /// Records and submits without reading back or waiting.
    pub fn submit(&self, gpu: &Gpu) {
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        self.record(gpu, &mut enc, None);
        gpu.queue.submit([enc.finish()]);
    }

    /// The passes. Query 0: start; query i + 1: end of stage i.
    fn record(&self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, set: Option<&wgpu::QuerySet>) {
        for b in &self.clears {
            enc.clear_buffer(b, 0, None);
        }
        for (i, stage) in self.stages.iter().enumerate() {
            let begin = (i == 0).then_some(0);
            let timestamp_writes = set.map(|query_set| wgpu::ComputePassTimestampWrites { query_set, beginning_of_pass_write_index: begin, end_of_pass_write_index: Some(i as u32 + 1) });
            let args = match stage.groups {
                Groups::Direct(_) => None,
                Groups::Indirect(list) => {
                    gpu.queue.write_buffer(list, 0, bytemuck::cast_slice(&[0u32, 1, 1, 0]));
                    // The stage before fills `list` (a storage buffer); it
                    // cannot also be the indirect buffer, so its counts are
                    // copied to `args` between the two passes.
                    let args = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("indirect dispatch"),
                        size: 16,
                        usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    });
                    enc.copy_buffer_to_buffer(list, 0, &args, 0, 12);
                    Some(args)
                }
            };
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(self.label), timestamp_writes });
            for (g, group) in self.groups.iter().enumerate() {
                pass.set_bind_group(g as u32, *group, &[]);
            }
            pass.set_pipeline(stage.pipeline);
            match (&stage.groups, &args) {
                (Groups::Direct([x, y, z]), _) => pass.dispatch_workgroups(*x, *y, *z),
                (Groups::Indirect(_), Some(args)) => pass.dispatch_workgroups_indirect(args, 0),
                (Groups::Indirect(_), None) => unreachable!("args made above"),
            }
            drop(pass);
            if let Some((buffer, texture)) = stage.copy {
                enc.copy_buffer_to_texture(
                    wgpu::TexelCopyBufferInfo { buffer, layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(texture.width() * 4), rows_per_image: None } },
                    texture.as_image_copy(),
                    texture.size(),
                );
            }
        }
    }
}
