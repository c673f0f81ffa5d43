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
/// frames and tiles of the same size (allocating ~30 MB per frame cost
/// ~15 ms on lavapipe). Slot `i` is the i-th read-back output.
#[derive(Default)]
pub struct Outputs(Mutex<Vec<Option<(u64, wgpu::Buffer, wgpu::Buffer)>>>);

impl Outputs {
    /// Output `slot` of `size` bytes and the buffer to map: the same one
    /// when the device maps storage buffers in place.
    pub fn get(&self, gpu: &Gpu, slot: usize, size: u64) -> (wgpu::Buffer, wgpu::Buffer) {
        let d = &gpu.device;
        let mut cache = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if cache.len() <= slot {
            cache.resize(slot + 1, None);
        }
        if cache[slot].as_ref().is_none_or(|(s, _, _)| *s != size) {
            let map = if gpu.map_in_place { wgpu::BufferUsages::MAP_READ } else { wgpu::BufferUsages::COPY_SRC };
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
            cache[slot] = Some((size, out, staging));
        }
        let (_, out, staging) = cache[slot].as_ref().expect("just filled");
        (out.clone(), staging.clone())
    }
}

/// A pre-pass over the rectangle's 8×8 tiles (one invocation each, 8×8
/// tiles a workgroup) that queues the tiles the per-pixel pass must run:
/// the per-pixel pass is then dispatched indirectly with the counts the
/// pre-pass leaves at the start of `list` (reset to (0, 1, 1, 0) first).
pub struct PrePass<'a> {
    /// The tile pass.
    pub pipeline: &'a wgpu::ComputePipeline,
    /// The tile list whose first 12 bytes are the indirect dispatch.
    pub list: &'a wgpu::Buffer,
}

/// One dispatch of a render kernel over a rectangle.
pub struct Dispatch<'a> {
    /// Debug label.
    pub label: &'static str,
    /// The per-pixel pass.
    pub main: &'a wgpu::ComputePipeline,
    /// An optional tile pre-pass.
    pub pre: Option<PrePass<'a>>,
    /// Frame, field and pass bind groups.
    pub groups: [&'a wgpu::BindGroup; 3],
    /// The rectangle.
    pub rect: Rect,
    /// 8×8 tiles per workgroup of the per-pixel pass (dispatched directly:
    /// x over tile columns, y over tile rows / this).
    pub tiles_per_group: u32,
    /// The outputs to read back: (buffer, its mappable copy, size).
    pub outputs: Vec<(wgpu::Buffer, wgpu::Buffer, u64)>,
}

/// GPU milliseconds of a dispatch: both passes, and the pre-pass alone.
#[derive(Debug, Clone, Copy, Default)]
pub struct Timing {
    /// Whole dispatch.
    pub total_ms: f64,
    /// The pre-pass (0 without one).
    pub pre_ms: f64,
}

impl Dispatch<'_> {
    /// Records, submits and reads back; `unpack` gets the mapped outputs in
    /// order, straight from the read-back buffers. Times with timestamp
    /// queries when the device has them, else the submit-to-read-back wall
    /// time.
    pub fn run(&self, gpu: &Gpu, unpack: impl FnOnce(&[&[u8]])) -> Result<Timing, GpuError> {
        let d = &gpu.device;
        let queries = if self.pre.is_some() { 3 } else { 2 };
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
        let last = queries - 1;
        let t0 = std::time::Instant::now();
        let ts_staging = gpu.scoped(self.label, || {
            let mut enc = d.create_command_encoder(&Default::default());
            self.record(gpu, &mut enc, ts.as_ref().map(|(set, _)| set), last);
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
        gpu.map_many(&staging, unpack)?;
        let wall = t0.elapsed().as_secs_f64() * 1e3;
        let Some((b, period)) = ts_staging.zip(gpu.timestamp_period) else { return Ok(Timing { total_ms: wall, pre_ms: 0.0 }) };
        let t = gpu.map_read(&b)?;
        let v: &[u64] = bytemuck::cast_slice(&t);
        let ms = |a: u64, b: u64| b.saturating_sub(a) as f64 * period as f64 * 1e-6;
        let total = ms(v[0], v[last as usize]);
        Ok(if total > 0.0 { Timing { total_ms: total, pre_ms: if self.pre.is_some() { ms(v[0], v[1]) } else { 0.0 } } } else { Timing { total_ms: wall, pre_ms: 0.0 } })
    }

    /// The passes. Query 0: start; 1: end of the pre-pass, if any; `last`: end.
    fn record(&self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, set: Option<&wgpu::QuerySet>, last: u32) {
        let stamp = |begin: Option<u32>, end: u32| set.map(|query_set| wgpu::ComputePassTimestampWrites { query_set, beginning_of_pass_write_index: begin, end_of_pass_write_index: Some(end) });
        let bind = |pass: &mut wgpu::ComputePass<'_>| {
            for (i, g) in self.groups.iter().enumerate() {
                pass.set_bind_group(i as u32, *g, &[]);
            }
        };
        let Some(pre) = &self.pre else {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(self.label), timestamp_writes: stamp(Some(0), last) });
            bind(&mut pass);
            pass.set_pipeline(self.main);
            pass.dispatch_workgroups(self.rect.w.div_ceil(8), self.rect.h.div_ceil(8).div_ceil(self.tiles_per_group), 1);
            return;
        };
        gpu.queue.write_buffer(pre.list, 0, bytemuck::cast_slice(&[0u32, 1, 1, 0]));
        // The pre-pass queues tiles in `list` (a storage buffer); it cannot
        // also be the indirect buffer of the next dispatch, so its counts are
        // copied to `args` between the two passes.
        let args = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("indirect dispatch"),
            size: 16,
            usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(self.label), timestamp_writes: stamp(Some(0), 1) });
            bind(&mut pass);
            pass.set_pipeline(pre.pipeline);
            pass.dispatch_workgroups(self.rect.w.div_ceil(64), self.rect.h.div_ceil(64), 1);
        }
        enc.copy_buffer_to_buffer(pre.list, 0, &args, 0, 12);
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(self.label), timestamp_writes: stamp(None, last) });
        bind(&mut pass);
        pass.set_pipeline(self.main);
        pass.dispatch_workgroups_indirect(&args, 0);
    }
}
